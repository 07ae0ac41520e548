//! pbrt-v4's `distant` light (the sun): radiance L arriving along one direction everywhere.
//! Its power is what crosses the scene's bounding disk, Φ = π·r²·L.

use super::bounds::LightExtent;
use super::kind::{
    LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere, point_error,
};
use super::sample::{LightLiSample, LightSampleContext};
use crate::math::{Frame, Rgb, Vec2, Vec3};
use crate::sampling::sample_uniform_disk_concentric;
use crate::shape::{Shape, TriangleMesh};
use std::f32::consts::PI;

/// A distant light as a scene describes it: light arrives along `to − from` everywhere.
#[derive(Clone, Debug, PartialEq)]
pub struct DistantDesc {
    /// Direction *towards* the light, world space (not necessarily normalised).
    pub direction: Vec3,
    /// Radiance (scaled and normalised).
    pub l: Rgb,
}

/// A directional light.
#[derive(Clone, Debug, PartialEq)]
pub struct DistantLight {
    /// Unit direction towards the light.
    pub w: Vec3,
    /// Radiance.
    pub l: Rgb,
    /// The scene's bounding sphere: shadow rays go twice its radius; emitted rays start on
    /// its disk facing the light.
    pub scene: SceneSphere,
}

impl LightDescKind for DistantDesc {
    type Light = DistantLight;

    fn pbrt_name(&self) -> &'static str {
        "distant"
    }

    /// The direction not zero.
    fn validate(&self) -> Result<(), String> {
        match self.direction.try_normalize() {
            Some(_) => Ok(()),
            None => Err("distant light with \"from\" equal to \"to\"".to_string()),
        }
    }

    fn build(&self, scene: &SceneSphere) -> Result<DistantLight, String> {
        Ok(DistantLight {
            w: self
                .direction
                .try_normalize()
                .expect("validated: a direction not zero"),
            l: self.l,
            scene: *scene,
        })
    }
}

/// A point of the disk of radius `scene.radius` through the scene's centre facing `w`, moved
/// back along `w` to the scene's boundary (where rays from an infinitely far light enter),
/// uniform by area: density 1/(π r²) (pbrt-v4's distant and infinite lights).
pub(super) fn disk_point(scene: &SceneSphere, w: Vec3, u: Vec2) -> Vec3 {
    let cd = sample_uniform_disk_concentric(u);
    let r = scene.radius;
    scene.centre + r * Frame::from_z(w).from_local(Vec3::new(cd.x, cd.y, 0.0)) + r * w
}

/// True when the scene has a disk to start rays on (a positive radius).
pub(super) fn has_disk(scene: &SceneSphere) -> bool {
    scene.radius > 0.0
}

/// 1/(π r²): the density of [`disk_point`].
pub(super) fn disk_pdf(scene: &SceneSphere) -> f32 {
    1.0 / (PI * scene.radius * scene.radius)
}

impl LightKind for DistantLight {
    fn light_type(&self) -> LightType {
        LightType::DeltaDirection
    }

    /// Li = L along the light's direction, the shadow ray reaching past the scene.
    #[inline]
    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        _: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        Some(LightLiSample {
            l: self.l,
            factor: 1.0,
            wi: self.w,
            pdf: 1.0,
            p_light: ctx.p + self.w * (2.0 * self.scene.radius.max(1e-3)),
        })
    }

    /// Φ = π·r²·L through the scene's bounding disk.
    fn power(&self) -> f32 {
        let (l, r) = (self.l, self.scene.radius);
        PI * r * r * ((l.x + l.y + l.z) / 3.0)
    }

    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        LightExtent::Unbounded
    }

    fn constant_colour(&self) -> Option<Rgb> {
        Some(self.l)
    }

    /// A ray along −w from a point uniform on the scene's disk facing the light (pbrt-v4's:
    /// p_pos = 1/(π r²), the direction given, p_dir = 1).
    fn sample_le(
        &self,
        u1: Vec2,
        _: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        if !has_disk(&self.scene) {
            return None;
        }
        let p = disk_point(&self.scene, self.w, u1);
        Some(LightLeSample {
            l: self.l,
            factor: 1.0,
            p,
            p_error: point_error(p),
            w: -self.w,
            n: Vec3::ZERO,
            pdf_pos: disk_pdf(&self.scene),
            pdf_dir: 1.0,
        })
    }

    fn pdf_le(&self, _: Vec3, _: Vec3, _: Vec3) -> LightLePdf {
        LightLePdf {
            pos: disk_pdf(&self.scene),
            dir: 0.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::testing::{le_pdfs_agree, le_power};

    #[test]
    fn emitted_rays_cross_the_scene_and_carry_the_power() {
        let scene = SceneSphere {
            centre: Vec3::new(1.0, -2.0, 0.5),
            radius: 3.0,
        };
        let light = DistantDesc {
            direction: Vec3::new(1.0, 2.0, -0.5),
            l: Rgb::new(1.0, 2.0, 3.0),
        }
        .build(&scene)
        .unwrap();
        let phi = le_power(&light, &[], &[], 1024);
        assert!((phi - light.power()).abs() < 1e-4 * light.power(), "{phi}");
        le_pdfs_agree(&light, &[], &[], 64, 1e-3);
        // Each ray starts on the sphere's tangent plane towards the light and passes within
        // r of the centre.
        for i in 0..64 {
            let u = Vec2::new((i % 8) as f32 / 8.0 + 0.06, (i / 8) as f32 / 8.0 + 0.06);
            let s = light.sample_le(u, Vec2::ZERO, &[], &[]).unwrap();
            let c = s.p - scene.centre;
            assert!((c.dot(light.w) - 3.0).abs() < 1e-4);
            let miss = c - c.dot(s.w) * s.w;
            assert!(miss.length() <= 3.0 + 1e-4);
        }
    }
}
