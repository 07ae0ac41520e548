//! pbrt-v4's `rgbgrid` medium (`RGBGridMedium`): σ_a, σ_s and L_e each given per sample as RGB
//! over a box. Each sample becomes a spectrum (unbounded for σ, illuminant for L_e) at the path's
//! wavelengths *before* the trilinear blend, as pbrt-v4 does.
//!
//! σ_a(p) = scale·Σ wᵢ·σ_a,ᵢ (1 where no σ_a grid is given), σ_s likewise, and
//! L_e(p) = Lescale·Σ wᵢ·L_e,ᵢ, wᵢ the trilinear weights at q = (M⁻¹p − p₀)/(p₁ − p₀).

use super::coeff::{Coefficient, PointProperties};
use super::grid::SampledGrid;
use super::majorant::{DdaMajorantIterator, MAJORANT_RES, MajorantGrid, grid_majorants};
use crate::math::{Bounds3, Rgb, SampledSpectrum, Transform, Vec3};
use crate::ray::Ray;
use crate::spectrum::sampled::SampledWavelengths;

/// An `rgbgrid` medium as the scene describes it. The grids given share the resolution
/// (nx, ny, nz); at least one of σ_a, σ_s is given, and L_e only with σ_a.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbGridDesc {
    /// Medium space → render space (the CTM at `MakeNamedMedium`).
    pub medium_to_render: Transform,
    /// The box the grids span in medium space (`p0`, `p1`).
    pub bounds: Bounds3,
    /// Henyey–Greenstein asymmetry `g`.
    pub g: f32,
    /// `sigma_a` samples.
    pub sigma_a: Option<SampledGrid<Rgb>>,
    /// `sigma_s` samples.
    pub sigma_s: Option<SampledGrid<Rgb>>,
    /// `scale`, multiplying σ_a and σ_s.
    pub scale: f32,
    /// `Le` samples (radiance, not normalised).
    pub le: Option<SampledGrid<Rgb>>,
    /// `Lescale`.
    pub le_scale: f32,
}

/// pbrt-v4's `RGBGridMedium`, ready to render.
#[derive(Clone, Debug)]
pub struct RgbGridMedium {
    render_to_medium: Transform,
    bounds: Bounds3,
    g: f32,
    sigma_a: Option<SampledGrid<Coefficient>>,
    sigma_s: Option<SampledGrid<Coefficient>>,
    scale: f32,
    le: Option<SampledGrid<Coefficient>>,
    le_scale: f32,
    majorant: MajorantGrid,
}

/// Each sample's colour turned into its spectrum once.
fn prepare(g: Option<SampledGrid<Rgb>>) -> Option<SampledGrid<Coefficient>> {
    let g = g?;
    let [nx, ny, nz] = g.resolution();
    let v = g.values().iter().map(|&c| Coefficient::new(c)).collect();
    SampledGrid::new(v, nx, ny, nz)
}

impl RgbGridMedium {
    /// Prepares the medium: one spectrum per sample, and the 16³ majorant grid
    /// scale·(max σ_a + max σ_s) per cell (a missing grid counts as 1).
    pub fn new(desc: RgbGridDesc) -> RgbGridMedium {
        let sigma_a = prepare(desc.sigma_a);
        let sigma_s = prepare(desc.sigma_s);
        let le = prepare(desc.le);
        let max = |g: &Option<SampledGrid<Coefficient>>, lo, hi| {
            g.as_ref()
                .map_or(1.0, |g| g.max_value_with(lo, hi, |c| c.max_value()))
        };
        let scale = desc.scale;
        let majorant = MajorantGrid::build(desc.bounds, [MAJORANT_RES; 3], |lo, hi| {
            scale * (max(&sigma_a, lo, hi) + max(&sigma_s, lo, hi))
        });
        RgbGridMedium {
            render_to_medium: desc.medium_to_render.inverse(),
            bounds: desc.bounds,
            g: desc.g,
            sigma_a,
            sigma_s,
            scale,
            le,
            le_scale: desc.le_scale,
            majorant,
        }
    }

    /// The Henyey–Greenstein asymmetry of its phase function.
    pub fn g(&self) -> f32 {
        self.g
    }

    /// True if it emits light.
    pub fn is_emissive(&self) -> bool {
        self.le.is_some() && self.le_scale > 0.0
    }

    /// Bytes held by its grids.
    pub fn bytes(&self) -> usize {
        [&self.sigma_a, &self.sigma_s, &self.le]
            .iter()
            .map(|g| g.as_ref().map_or(0, |g| g.bytes()))
            .sum::<usize>()
            + self.majorant.bytes()
    }

    /// σ_a, σ_s and L_e at render-space point `p`.
    pub fn properties(&self, p: Vec3, lambda: Option<&SampledWavelengths>) -> PointProperties {
        let q = self.bounds.offset(self.render_to_medium.point(p));
        let sigma = |g: &Option<SampledGrid<Coefficient>>| {
            g.as_ref()
                .map_or(SampledSpectrum::ONE, |g| g.lookup_with(q, |c| c.at(lambda)))
                * self.scale
        };
        let le = match &self.le {
            Some(g) if self.le_scale > 0.0 => {
                g.lookup_with(q, |c| c.emission_at(lambda)) * self.le_scale
            }
            _ => SampledSpectrum::ZERO,
        };
        PointProperties {
            sigma_a: sigma(&self.sigma_a),
            sigma_s: sigma(&self.sigma_s),
            le,
        }
    }

    /// The majorant segments of render-space `ray` over [0, t_max], one per majorant cell
    /// crossed inside the box (the cells hold σ_maj itself).
    pub fn majorants(
        &self,
        ray: &Ray,
        t_max: f32,
        _lambda: Option<&SampledWavelengths>,
    ) -> DdaMajorantIterator<'_> {
        grid_majorants(
            &self.render_to_medium,
            &self.bounds,
            &self.majorant,
            ray,
            t_max,
            SampledSpectrum::ONE,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc() -> RgbGridDesc {
        // 2×1×1 over the unit cube: red absorber on the left, blue on the right.
        RgbGridDesc {
            medium_to_render: Transform::IDENTITY,
            bounds: Bounds3::new(Vec3::ZERO, Vec3::ONE),
            g: 0.0,
            sigma_a: SampledGrid::new(
                vec![Rgb::new(1.0, 0.0, 0.0), Rgb::new(0.0, 0.0, 3.0)],
                2,
                1,
                1,
            ),
            sigma_s: None,
            scale: 2.0,
            le: None,
            le_scale: 1.0,
        }
    }

    #[test]
    fn samples_blend_and_missing_sigma_s_is_one() {
        let m = RgbGridMedium::new(desc());
        let p = m.properties(Vec3::new(0.25, 0.5, 0.5), None);
        assert_eq!(p.sigma_a, SampledSpectrum::new(2.0, 0.0, 0.0, 0.0));
        assert_eq!(p.sigma_s, SampledSpectrum::splat(2.0));
        let p = m.properties(Vec3::new(0.5, 0.5, 0.5), None);
        assert_eq!(p.sigma_a, SampledSpectrum::new(1.0, 0.0, 3.0, 3.0));
        assert!(!m.is_emissive());
    }

    #[test]
    fn majorants_bound_sigma_t_in_both_modes() {
        let m = RgbGridMedium::new(desc());
        let ray = Ray::new(Vec3::new(-1.0, 0.3, 0.6), Vec3::new(1.0, 0.1, 0.0));
        for lambda in [None, Some(SampledWavelengths::sample_visible(0.37))] {
            let segs: Vec<_> = m.majorants(&ray, 10.0, lambda.as_ref()).collect();
            assert!(!segs.is_empty());
            for s in segs {
                for k in 0..=8 {
                    let t = s.t_min + (s.t_max - s.t_min) * k as f32 / 8.0;
                    let p = m.properties(ray.at(t), lambda.as_ref());
                    let st = p.sigma_a + p.sigma_s;
                    assert!(
                        st.cmple(s.sigma_maj * 1.0001).all(),
                        "{st} > {}",
                        s.sigma_maj
                    );
                }
            }
        }
    }

    #[test]
    fn le_is_emitted_with_lescale() {
        let mut d = desc();
        d.le = SampledGrid::new(vec![Rgb::splat(1.0), Rgb::splat(3.0)], 2, 1, 1);
        d.le_scale = 0.5;
        let m = RgbGridMedium::new(d);
        assert!(m.is_emissive());
        let p = m.properties(Vec3::new(0.5, 0.5, 0.5), None);
        assert_eq!(p.le, SampledSpectrum::splat(1.0));
    }
}
