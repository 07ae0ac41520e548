//! pbrt-v4's `nanovdb` medium (`NanoVDBMedium`): σ_a and σ_s scaled by a sparse VDB density
//! grid, emission from an optional temperature grid as a black body, and a 64³ majorant grid
//! over the grids' world bounds.
//!
//! σ_a(p) = scale·σ_a·d(x), σ_s(p) = scale·σ_s·d(x), x the index-space position of M⁻¹p;
//! L_e(p) = Lescale·B̂((T(x) − offset)·tscale), zero at or below 100 K.

use super::coeff::{Coefficient, PointProperties, blackbody_at};
use super::majorant::{DdaMajorantIterator, MajorantGrid, grid_majorants};
use super::vdb::{VdbGrid, VdbGridDesc};
use crate::math::{Bounds3, Rgb, SampledSpectrum, Transform, Vec3};
use crate::ray::Ray;
use crate::spectrum::sampled::SampledWavelengths;

/// pbrt-v4's majorant resolution for NanoVDB media.
pub const NANOVDB_MAJORANT_RES: i32 = 64;

/// A `nanovdb` medium as the scene describes it: its grids as read and checked, plain data
/// ([`VdbGridDesc`]); [`NanoVdbMedium::new`] makes them ready for lookups.
#[derive(Clone, Debug, PartialEq)]
pub struct NanoVdbDesc {
    /// Medium space → render space (the CTM at `MakeNamedMedium`).
    pub medium_to_render: Transform,
    /// σ_a (RGB, reduced as unbounded), before `scale`.
    pub sigma_a: Rgb,
    /// σ_s before `scale`.
    pub sigma_s: Rgb,
    /// `scale`.
    pub scale: f32,
    /// Henyey–Greenstein asymmetry `g`.
    pub g: f32,
    /// The `density` grid (or the one `gridname` names).
    pub density: VdbGridDesc,
    /// The `temperature` grid, if the file has one.
    pub temperature: Option<VdbGridDesc>,
    /// `Lescale`.
    pub le_scale: f32,
    /// `temperatureoffset` (or `temperaturecutoff`).
    pub temperature_offset: f32,
    /// `temperaturescale`.
    pub temperature_scale: f32,
}

/// pbrt-v4's `NanoVDBMedium`, ready to render.
#[derive(Clone, Debug)]
pub struct NanoVdbMedium {
    render_to_medium: Transform,
    bounds: Bounds3,
    sigma_a: Coefficient,
    sigma_s: Coefficient,
    scale: f32,
    g: f32,
    density: VdbGrid,
    temperature: Option<VdbGrid>,
    le_scale: f32,
    temperature_offset: f32,
    temperature_scale: f32,
    majorant: MajorantGrid,
}

impl NanoVdbMedium {
    /// Prepares the medium: its grids ready for lookups ([`VdbGrid::new`]), its box (the
    /// union of the grids' world bounds) and the 64³ majorant grid, each cell the largest
    /// density over the voxels its box reaches (widened by one voxel for the trilinear
    /// filter, as pbrt-v4).
    pub fn new(desc: NanoVdbDesc) -> NanoVdbMedium {
        let density = VdbGrid::new(desc.density);
        let temperature = desc.temperature.map(VdbGrid::new);
        let mut bounds = density.world_bounds();
        if let Some(t) = &temperature {
            bounds = bounds.union(&t.world_bounds());
        }
        let d = &density;
        let diag = bounds.diagonal();
        let majorant = MajorantGrid::build(bounds, [NANOVDB_MAJORANT_RES; 3], |lo, hi| {
            let i0 = d.world_to_index(bounds.min + lo * diag);
            let i1 = d.world_to_index(bounds.min + hi * diag);
            // pbrt-v4 truncates toward zero after widening by one voxel.
            let a: [i32; 3] = std::array::from_fn(|k| (i0[k] - 1.0) as i32);
            let b: [i32; 3] = std::array::from_fn(|k| (i1[k] + 1.0) as i32);
            let lo3 = std::array::from_fn(|k| a[k].min(b[k]));
            let hi3 = std::array::from_fn(|k| a[k].max(b[k]));
            d.max_in(lo3, hi3)
        });
        NanoVdbMedium {
            render_to_medium: desc.medium_to_render.inverse(),
            bounds,
            sigma_a: Coefficient::new(desc.sigma_a),
            sigma_s: Coefficient::new(desc.sigma_s),
            scale: desc.scale,
            g: desc.g,
            density,
            temperature,
            le_scale: desc.le_scale,
            temperature_offset: desc.temperature_offset,
            temperature_scale: desc.temperature_scale,
            majorant,
        }
    }

    /// The Henyey–Greenstein asymmetry of its phase function.
    pub fn g(&self) -> f32 {
        self.g
    }

    /// True if it emits light (a temperature grid and a positive `Lescale`).
    pub fn is_emissive(&self) -> bool {
        self.temperature.is_some() && self.le_scale > 0.0
    }

    /// The medium-space box its majorants cover.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Bytes held by its grids.
    pub fn bytes(&self) -> usize {
        self.density.bytes()
            + self.temperature.as_ref().map_or(0, |t| t.bytes())
            + self.majorant.bytes()
    }

    /// σ_a, σ_s and L_e at render-space point `p`.
    pub fn properties(&self, p: Vec3, lambda: Option<&SampledWavelengths>) -> PointProperties {
        let pm = self.render_to_medium.point(p);
        let d = self.density.sample_world(pm) * self.scale;
        let le = match &self.temperature {
            Some(t) if self.le_scale > 0.0 => {
                let k = (t.sample_world(pm) - self.temperature_offset) * self.temperature_scale;
                blackbody_at(lambda, k) * self.le_scale
            }
            _ => SampledSpectrum::ZERO,
        };
        PointProperties {
            sigma_a: self.sigma_a.at(lambda) * d,
            sigma_s: self.sigma_s.at(lambda) * d,
            le,
        }
    }

    /// The majorant segments of render-space `ray` over [0, t_max], one per majorant cell
    /// crossed inside the box, σ_maj = scale·(σ_a + σ_s)·(max density in the cell).
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
    use crate::math::Mat3;
    use crate::medium::vdb::VdbParts;

    /// A ball of density 1 − r/8 (voxels within radius 8 of index (8, 8, 8)), voxel size ¼.
    fn ball() -> VdbGridDesc {
        let mut origins = Vec::new();
        let mut values = Vec::new();
        for bx in 0..3 {
            for by in 0..3 {
                for bz in 0..3 {
                    let o = [bx * 8, by * 8, bz * 8];
                    origins.push(o);
                    for i in 0..8 {
                        for j in 0..8 {
                            for k in 0..8 {
                                let p = Vec3::new(
                                    (o[0] + i) as f32,
                                    (o[1] + j) as f32,
                                    (o[2] + k) as f32,
                                );
                                values.push((1.0 - (p - Vec3::splat(8.0)).length() / 8.0).max(0.0));
                            }
                        }
                    }
                }
            }
        }
        VdbParts {
            world_to_index: Mat3::from_diagonal(glam::Vec3::splat(4.0)),
            translation: Vec3::ZERO,
            world_bounds: Bounds3::new(Vec3::ZERO, Vec3::splat(4.0)),
            index_bounds: [[0, 0, 0], [16, 16, 16]],
            background: 0.0,
            leaf_origins: origins,
            leaf_values: values,
            tiles: Vec::new(),
        }
        .check()
        .unwrap()
    }

    fn medium(temperature: Option<VdbGridDesc>) -> NanoVdbMedium {
        NanoVdbMedium::new(NanoVdbDesc {
            medium_to_render: Transform::IDENTITY,
            sigma_a: Rgb::splat(0.5),
            sigma_s: Rgb::new(0.9, 1.2, 1.5),
            scale: 2.0,
            g: 0.0,
            density: ball(),
            temperature,
            le_scale: 1.0,
            temperature_offset: 0.0,
            temperature_scale: 1.0,
        })
    }

    #[test]
    fn density_scales_the_coefficients() {
        let m = medium(None);
        assert!(!m.is_emissive());
        // The centre (world 2, index 8): density 1.
        let p = m.properties(Vec3::splat(2.0), None);
        assert_eq!(p.sigma_a, SampledSpectrum::splat(1.0));
        assert_eq!(p.sigma_s, SampledSpectrum::new(1.8, 2.4, 3.0, 3.0));
        // Outside: background 0.
        assert_eq!(
            m.properties(Vec3::splat(10.0), None).sigma_a,
            SampledSpectrum::ZERO
        );
    }

    #[test]
    fn majorants_bound_the_density_along_rays() {
        let m = medium(None);
        for (o, d) in [
            (Vec3::new(-1.0, 2.0, 2.0), Vec3::X),
            (Vec3::new(-1.0, -0.5, 0.3), Vec3::new(1.0, 0.8, 0.6)),
            (Vec3::new(5.0, 5.0, 5.0), Vec3::new(-1.0, -1.1, -0.9)),
        ] {
            let ray = Ray::new(o, d);
            let segs: Vec<_> = m.majorants(&ray, 100.0, None).collect();
            assert!(segs.len() > 10);
            for s in segs {
                for k in 0..=4 {
                    let t = s.t_min + (s.t_max - s.t_min) * k as f32 / 4.0;
                    let p = m.properties(ray.at(t), None);
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
    fn temperature_emits() {
        let m = medium(Some(ball()));
        assert!(m.is_emissive());
        // Temperature 1 K at most: below 100 K, no light.
        assert_eq!(
            m.properties(Vec3::splat(2.0), None).le,
            SampledSpectrum::ZERO
        );
        let mut hot = medium(Some(ball()));
        hot.temperature_scale = 4000.0;
        let le = hot.properties(Vec3::splat(2.0), None).le;
        assert_eq!(le, blackbody_at(None, 4000.0));
    }
}
