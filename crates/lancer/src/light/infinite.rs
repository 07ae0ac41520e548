//! pbrt-v4's `infinite` light without an image: a constant-radiance environment ("sky"),
//! L from every direction. Its power is what crosses the scene's bounding disk from every
//! direction, Φ = 4π·π·r²·L.

use super::bounds::LightExtent;
use super::distant::{disk_pdf, disk_point, has_disk};
use super::kind::{
    LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere, point_error,
};
use super::sample::{LightLiSample, LightSampleContext};
use crate::math::{Frame, INV_PI, Rgb, Vec2, Vec3};
use crate::sampling::{sample_cosine_hemisphere, sample_uniform_sphere, uniform_sphere_pdf};
use crate::shape::{Shape, TriangleMesh};
use std::f32::consts::PI;

/// A uniform environment as a scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct UniformInfiniteDesc {
    /// Radiance from every direction (scaled and normalised).
    pub l: Rgb,
}

/// A constant-radiance environment.
#[derive(Clone, Debug, PartialEq)]
pub struct UniformInfiniteLight {
    /// Radiance from every direction.
    pub l: Rgb,
    /// The scene's bounding sphere.
    pub scene: SceneSphere,
}

impl LightDescKind for UniformInfiniteDesc {
    type Light = UniformInfiniteLight;

    fn pbrt_name(&self) -> &'static str {
        "infinite"
    }

    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    fn build(&self, scene: &SceneSphere) -> Result<UniformInfiniteLight, String> {
        Ok(UniformInfiniteLight {
            l: self.l,
            scene: *scene,
        })
    }
}

impl LightKind for UniformInfiniteLight {
    fn light_type(&self) -> LightType {
        LightType::Infinite
    }

    /// Cosine-weighted about the shading normal when there is one (p = cos θ/π), else
    /// uniform on the sphere (p = 1/4π).
    #[inline]
    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        let (wi, pdf) = if ctx.ns != Vec3::ZERO {
            let local = sample_cosine_hemisphere(u);
            (Frame::from_z(ctx.ns).from_local(local), local.z * INV_PI)
        } else {
            (sample_uniform_sphere(u), uniform_sphere_pdf())
        };
        (pdf > 0.0).then_some(LightLiSample {
            l: self.l,
            factor: 1.0,
            wi,
            pdf,
            p_light: ctx.p + wi * (2.0 * self.scene.radius.max(1e-3)),
        })
    }

    fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, _: Option<(Vec3, Vec3)>) -> f32 {
        if ctx.ns != Vec3::ZERO {
            wi.dot(ctx.ns).max(0.0) * INV_PI
        } else {
            uniform_sphere_pdf()
        }
    }

    /// Φ = 4π²·r²·L.
    fn power(&self) -> f32 {
        let (l, r) = (self.l, self.scene.radius);
        4.0 * PI * PI * r * r * ((l.x + l.y + l.z) / 3.0)
    }

    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        LightExtent::Unbounded
    }

    fn constant_colour(&self) -> Option<Rgb> {
        Some(self.l)
    }

    fn le(&self, _: Vec3) -> Rgb {
        self.l
    }

    /// pbrt-v4's: a direction uniform on the sphere from `u1` (p_dir = 1/4π), then a point
    /// uniform on the scene's disk facing where the light comes from (p_pos = 1/(π r²)).
    fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        if !has_disk(&self.scene) {
            return None;
        }
        let w = sample_uniform_sphere(u1);
        let p = disk_point(&self.scene, -w, u2);
        Some(LightLeSample {
            l: self.l,
            factor: 1.0,
            p,
            p_error: point_error(p),
            w,
            n: Vec3::ZERO,
            pdf_pos: disk_pdf(&self.scene),
            pdf_dir: uniform_sphere_pdf(),
        })
    }

    fn pdf_le(&self, _: Vec3, _: Vec3, _: Vec3) -> LightLePdf {
        LightLePdf {
            pos: disk_pdf(&self.scene),
            dir: uniform_sphere_pdf(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};

    #[test]
    fn emitted_rays_carry_the_power() {
        let light = UniformInfiniteDesc {
            l: Rgb::new(0.5, 1.0, 2.0),
        }
        .build(&SceneSphere {
            centre: Vec3::new(0.0, 1.0, 0.0),
            radius: 2.0,
        })
        .unwrap();
        let phi = le_power(&light, &[], &[], 1024);
        assert!((phi - light.power()).abs() < 1e-4 * light.power(), "{phi}");
        le_pdfs_agree(&light, &[], &[], 64, 1e-3);
        let total = le_dir_integral(&light, Vec3::ZERO, Vec3::ZERO, 4096);
        assert!((total - 1.0).abs() < 1e-4, "{total}");
    }
}
