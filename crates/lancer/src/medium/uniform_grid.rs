//! pbrt-v4's `uniformgrid` medium (`GridMedium`): a density grid scaling constant σ_a and σ_s
//! over a box, with emission from a constant spectrum or a temperature grid (a black body), each
//! scaled by an `Lescale` grid.
//!
//! At a render-space point p, with q = (M⁻¹p − p₀)/(p₁ − p₀) ∈ [0,1]³:
//! σ_a(p) = scale·σ_a·d(q), σ_s(p) = scale·σ_s·d(q), and
//! L_e(p) = s(q)·B̂((T(q) − offset)·tscale) (temperature) or s(q)·L_e (spectrum), s the `Lescale`
//! grid, B̂ the black body normalised to peak 1, zero below 100 K.

use super::coeff::{Coefficient, PointProperties, blackbody_at};
use super::grid::SampledGrid;
use super::majorant::{DdaMajorantIterator, MAJORANT_RES, MajorantGrid, grid_majorants};
use crate::math::{Bounds3, Rgb, SampledSpectrum, Transform, Vec3};
use crate::ray::Ray;
use crate::spectrum::sampled::SampledWavelengths;

/// A `uniformgrid` medium as the scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct UniformGridDesc {
    /// Medium space → render space (the CTM at `MakeNamedMedium`).
    pub medium_to_render: Transform,
    /// The box the grid spans in medium space (`p0`, `p1`).
    pub bounds: Bounds3,
    /// σ_a before `scale` and density (RGB, reduced from the scene's spectrum as unbounded).
    pub sigma_a: Rgb,
    /// σ_s before `scale` and density.
    pub sigma_s: Rgb,
    /// `scale`, multiplying σ_a and σ_s.
    pub scale: f32,
    /// Henyey–Greenstein asymmetry `g`.
    pub g: f32,
    /// `density`.
    pub density: SampledGrid<f32>,
    /// `temperature` (kelvin before offset and scale), if given.
    pub temperature: Option<SampledGrid<f32>>,
    /// `temperaturescale`.
    pub temperature_scale: f32,
    /// `temperatureoffset` (pbrt-v4 also reads it as `temperaturecutoff`).
    pub temperature_offset: f32,
    /// `Le` as an illuminant of luminance 1 (zero when not given).
    pub le: Rgb,
    /// `Lescale`: one value, or one per density sample.
    pub le_scale: SampledGrid<f32>,
}

/// pbrt-v4's `GridMedium`, ready to render.
#[derive(Clone, Debug)]
pub struct UniformGridMedium {
    render_to_medium: Transform,
    bounds: Bounds3,
    sigma_a: Coefficient,
    sigma_s: Coefficient,
    scale: f32,
    g: f32,
    density: SampledGrid<f32>,
    temperature: Option<SampledGrid<f32>>,
    temperature_scale: f32,
    temperature_offset: f32,
    le: Coefficient,
    le_scale: SampledGrid<f32>,
    emissive: bool,
    majorant: MajorantGrid,
}

impl UniformGridMedium {
    /// Prepares the medium: spectra for σ_a, σ_s and L_e, and the 16³ majorant grid of the
    /// density's maxima.
    pub fn new(desc: UniformGridDesc) -> UniformGridMedium {
        let density = desc.density;
        let majorant = MajorantGrid::build(desc.bounds, [MAJORANT_RES; 3], |lo, hi| {
            density.max_value(lo, hi)
        });
        let emissive = desc.temperature.is_some() || desc.le.max_element() > 0.0;
        UniformGridMedium {
            render_to_medium: desc.medium_to_render.inverse(),
            bounds: desc.bounds,
            sigma_a: Coefficient::new(desc.sigma_a),
            sigma_s: Coefficient::new(desc.sigma_s),
            scale: desc.scale,
            g: desc.g,
            density,
            temperature: desc.temperature,
            temperature_scale: desc.temperature_scale,
            temperature_offset: desc.temperature_offset,
            le: Coefficient::new(desc.le),
            le_scale: desc.le_scale,
            emissive,
            majorant,
        }
    }

    /// The Henyey–Greenstein asymmetry of its phase function.
    pub fn g(&self) -> f32 {
        self.g
    }

    /// True if it emits light.
    pub fn is_emissive(&self) -> bool {
        self.emissive
    }

    /// Bytes held by its grids.
    pub fn bytes(&self) -> usize {
        self.density.bytes()
            + self.le_scale.bytes()
            + self.temperature.as_ref().map_or(0, |t| t.bytes())
            + self.majorant.bytes()
    }

    /// σ_a, σ_s and L_e at render-space point `p`.
    pub fn properties(&self, p: Vec3, lambda: Option<&SampledWavelengths>) -> PointProperties {
        let q = self.bounds.offset(self.render_to_medium.point(p));
        let d = self.density.lookup(q) * self.scale;
        let mut le = SampledSpectrum::ZERO;
        if self.emissive {
            let s = self.le_scale.lookup(q);
            if s > 0.0 {
                le = match &self.temperature {
                    Some(t) => {
                        let k = (t.lookup(q) - self.temperature_offset) * self.temperature_scale;
                        blackbody_at(lambda, k) * s
                    }
                    None => self.le.emission_at(lambda) * s,
                };
            }
        }
        PointProperties {
            sigma_a: self.sigma_a.at(lambda) * d,
            sigma_s: self.sigma_s.at(lambda) * d,
            le,
        }
    }

    /// The majorant segments of render-space `ray` over [0, t_max]: one per majorant cell it
    /// crosses inside the box, σ_maj = scale·(σ_a + σ_s)·(max density in the cell).
    pub fn majorants(
        &self,
        ray: &Ray,
        t_max: f32,
        lambda: Option<&SampledWavelengths>,
    ) -> DdaMajorantIterator<'_> {
        let sigma_t = (self.sigma_a.at(lambda) + self.sigma_s.at(lambda)) * self.scale;
        grid_majorants(
            &self.render_to_medium,
            &self.bounds,
            &self.majorant,
            ray,
            t_max,
            sigma_t,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2×1×1 grid over [0,2]×[0,1]×[0,1], placed at x + 10 in render space.
    fn desc() -> UniformGridDesc {
        UniformGridDesc {
            medium_to_render: Transform::translate(Vec3::new(10.0, 0.0, 0.0)),
            bounds: Bounds3::new(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0)),
            sigma_a: Rgb::splat(1.0),
            sigma_s: Rgb::new(0.5, 1.0, 2.0),
            scale: 2.0,
            g: 0.3,
            density: SampledGrid::new(vec![1.0, 3.0], 2, 1, 1).unwrap(),
            temperature: None,
            temperature_scale: 1.0,
            temperature_offset: 0.0,
            le: Rgb::ZERO,
            le_scale: SampledGrid::new(vec![1.0], 1, 1, 1).unwrap(),
        }
    }

    #[test]
    fn properties_scale_coefficients_by_density() {
        let m = UniformGridMedium::new(desc());
        assert!(!m.is_emissive());
        assert_eq!(m.g(), 0.3);
        // Render (10.5, .5, .5) → medium (.5, .5, .5) → q = (.25, .5, .5): sample 0, density 1.
        let p = m.properties(Vec3::new(10.5, 0.5, 0.5), None);
        assert_eq!(p.sigma_a, SampledSpectrum::splat(2.0));
        assert_eq!(p.sigma_s, SampledSpectrum::new(1.0, 2.0, 4.0, 4.0));
        assert_eq!(p.le, SampledSpectrum::ZERO);
        // The middle blends both samples: density 2.
        let p = m.properties(Vec3::new(11.0, 0.5, 0.5), None);
        assert_eq!(p.sigma_a, SampledSpectrum::splat(4.0));
    }

    #[test]
    fn majorants_bound_the_density_along_a_ray() {
        let m = UniformGridMedium::new(desc());
        let ray = Ray::new(Vec3::new(9.0, 0.5, 0.5), Vec3::X);
        let segs: Vec<_> = m.majorants(&ray, 100.0, None).collect();
        assert_eq!(segs.first().unwrap().t_min, 1.0);
        assert!((segs.last().unwrap().t_max - 3.0).abs() < 1e-5);
        for s in &segs {
            for k in 0..=10 {
                let t = s.t_min + (s.t_max - s.t_min) * k as f32 / 10.0;
                let p = m.properties(ray.at(t), None);
                let st = p.sigma_a + p.sigma_s;
                assert!(
                    st.cmple(s.sigma_maj * (1.0 + 1e-5)).all(),
                    "{st} > {}",
                    s.sigma_maj
                );
            }
        }
        // A ray that misses the box has none; one stopped before it too.
        let miss = Ray::new(Vec3::new(9.0, 5.0, 0.5), Vec3::X);
        assert_eq!(m.majorants(&miss, 100.0, None).count(), 0);
        assert_eq!(m.majorants(&ray, 0.5, None).count(), 0);
    }

    #[test]
    fn temperature_emits_a_black_body_scaled_by_lescale() {
        let mut d = desc();
        d.temperature = Some(SampledGrid::new(vec![1100.0, 1100.0], 2, 1, 1).unwrap());
        d.temperature_offset = 100.0;
        d.temperature_scale = 5.0;
        d.le_scale = SampledGrid::new(vec![3.0], 1, 1, 1).unwrap();
        let m = UniformGridMedium::new(d);
        assert!(m.is_emissive());
        // At the middle of the box: T = (1100 − 100)·5 = 5000 K, Lescale 3 (its single sample).
        let p = m.properties(Vec3::new(11.0, 0.5, 0.5), None);
        let want = blackbody_at(None, 5000.0) * 3.0;
        assert!((p.le - want).abs().max_element() < 1e-5, "{} {want}", p.le);
    }

    #[test]
    fn constant_le_is_scaled() {
        let mut d = desc();
        d.le = Rgb::new(1.0, 0.5, 0.25);
        d.le_scale = SampledGrid::new(vec![2.0], 1, 1, 1).unwrap();
        let m = UniformGridMedium::new(d);
        let p = m.properties(Vec3::new(11.0, 0.5, 0.5), None);
        assert_eq!(p.le, SampledSpectrum::new(2.0, 1.0, 0.5, 0.5));
        assert!(m.bytes() >= 16 * 16 * 16 * 4);
    }
}
