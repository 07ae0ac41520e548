//! pbrt-v4's `point` light: an isotropic point light, I the same in every direction, so the
//! light arriving at a point r away is Li = I / r² and the power Φ = 4π·I.

use super::bounds::{LightBounds, LightExtent};
use super::kind::{LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere};
use super::sample::{LightLiSample, LightSampleContext};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::{sample_uniform_sphere, uniform_sphere_pdf};
use crate::shape::{Shape, TriangleMesh};
use std::f32::consts::PI;

/// A point light as a scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct PointDesc {
    /// Position, world space.
    pub from: Vec3,
    /// Radiant intensity (scaled and normalised).
    pub intensity: Rgb,
}

/// An isotropic point light.
#[derive(Clone, Debug, PartialEq)]
pub struct PointLight {
    /// Position.
    pub p: Vec3,
    /// Radiant intensity I.
    pub intensity: Rgb,
}

impl LightDescKind for PointDesc {
    type Light = PointLight;

    fn pbrt_name(&self) -> &'static str {
        "point"
    }

    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    fn build(&self, _: &SceneSphere) -> Result<PointLight, String> {
        Ok(PointLight {
            p: self.from,
            intensity: self.intensity,
        })
    }
}

impl LightKind for PointLight {
    fn light_type(&self) -> LightType {
        LightType::DeltaPosition
    }

    /// Li = I / r² from the light's position.
    #[inline]
    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        _: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        let d = self.p - ctx.p;
        let r2 = d.length_squared();
        if r2 == 0.0 {
            return None;
        }
        Some(LightLiSample {
            l: self.intensity / r2,
            factor: 1.0 / r2,
            wi: d / r2.sqrt(),
            pdf: 1.0,
            p_light: self.p,
        })
    }

    /// Φ = 4π·I.
    fn power(&self) -> f32 {
        let i = self.intensity;
        4.0 * PI * ((i.x + i.y + i.z) / 3.0)
    }

    /// A point emits everywhere: normal cone = sphere, no spread needed; φ = 4π·max(I).
    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        let i = self.intensity;
        LightBounds::point(self.p, 4.0 * PI * i.x.max(i.y).max(i.z)).extent()
    }

    fn constant_colour(&self) -> Option<Rgb> {
        Some(self.intensity)
    }

    /// A direction uniform on the sphere (p_dir = 1/4π) from the light's position.
    fn sample_le(
        &self,
        u1: Vec2,
        _: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        Some(LightLeSample {
            l: self.intensity,
            factor: 1.0,
            p: self.p,
            p_error: Vec3::ZERO,
            w: sample_uniform_sphere(u1),
            n: Vec3::ZERO,
            pdf_pos: 1.0,
            pdf_dir: uniform_sphere_pdf(),
        })
    }

    fn pdf_le(&self, _: Vec3, _: Vec3, _: Vec3) -> LightLePdf {
        LightLePdf {
            pos: 0.0,
            dir: uniform_sphere_pdf(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::testing::{le_pdfs_agree, le_power};
    use crate::math::normalize;

    fn light() -> PointLight {
        PointLight {
            p: Vec3::new(0.3, 1.0, -0.2),
            intensity: Rgb::new(2.0, 1.0, 0.5),
        }
    }

    #[test]
    fn importance_bounds_the_true_contribution() {
        // A point light of intensity I: the irradiance at p on a surface of normal n is
        // I·cos θᵢ/d², and φ = 4π·max(I), so importance/(4π) must be at least it.
        let light = light();
        let LightExtent::Bounded(b) = light.extent(&[], &[]) else {
            panic!("a point light has bounds")
        };
        let mut rng = crate::sampling::Pcg32::new(3, 4);
        for _ in 0..1000 {
            let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0 - 2.0;
            let n = sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            let d = light.p - p;
            let e = 2.0 * n.dot(normalize(d)).abs() / d.length_squared();
            assert!(b.importance(p, n) / (4.0 * PI) >= e * 0.9999, "{p:?}");
        }
    }

    #[test]
    fn emitted_rays_carry_the_power() {
        let light = light();
        let phi = le_power(&light, &[], &[], 4096);
        assert!((phi - light.power()).abs() < 1e-4 * light.power(), "{phi}");
        le_pdfs_agree(&light, &[], &[], 256, 1e-3);
    }
}
