//! pbrt-v4's `spot` light: a point light limited to a cone with a smooth falloff,
//! I(θ) = I · smoothstep(cos θ; cos θ_total, cos θ_falloff) about its axis.
//!
//! Its power: Φ = 2π·I·((1 − cos θ_start) + (cos θ_start − cos θ_end)/2), full intensity
//! inside θ_start and, over the falloff, the smoothstep's mean of ½.

use super::bounds::{DirectionCone, LightBounds, LightExtent, safe_acos};
use super::kind::{LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere};
use super::sample::{LightLiSample, LightSampleContext};
use crate::math::{Bounds3, Frame, Rgb, Vec2, Vec3, smooth_step};
use crate::sampling::{sample_uniform_cone, uniform_cone_pdf};
use crate::shape::{Shape, TriangleMesh};
use std::f32::consts::PI;

/// A spot light as a scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct SpotDesc {
    /// Position, world space.
    pub from: Vec3,
    /// A point on the axis, world space.
    pub to: Vec3,
    /// Radiant intensity on the axis.
    pub intensity: Rgb,
    /// Total half-angle of the cone, degrees.
    pub cone_angle: f32,
    /// Width of the falloff at the cone's edge, degrees.
    pub cone_delta_angle: f32,
}

/// A spot light.
#[derive(Clone, Debug, PartialEq)]
pub struct SpotLight {
    /// Position.
    pub p: Vec3,
    /// Unit axis: the direction of full intensity.
    pub axis: Vec3,
    /// Intensity on the axis.
    pub intensity: Rgb,
    /// cos of the angle where the falloff starts (full intensity inside).
    pub cos_falloff_start: f32,
    /// cos of the cone's total half-angle (zero outside).
    pub cos_falloff_end: f32,
}

impl LightDescKind for SpotDesc {
    type Light = SpotLight;

    fn pbrt_name(&self) -> &'static str {
        "spot"
    }

    /// `from` and `to` apart.
    fn validate(&self) -> Result<(), String> {
        match (self.to - self.from).try_normalize() {
            Some(_) => Ok(()),
            None => Err("spot light with \"from\" equal to \"to\"".to_string()),
        }
    }

    fn build(&self, _: &SceneSphere) -> Result<SpotLight, String> {
        Ok(SpotLight {
            p: self.from,
            axis: (self.to - self.from)
                .try_normalize()
                .expect("validated: from and to apart"),
            intensity: self.intensity,
            cos_falloff_end: self.cone_angle.to_radians().cos(),
            cos_falloff_start: (self.cone_angle - self.cone_delta_angle).to_radians().cos(),
        })
    }
}

impl SpotLight {
    /// The smoothstep falloff at cos θ from the axis.
    #[inline]
    fn falloff(&self, cos_theta: f32) -> f32 {
        smooth_step(cos_theta, self.cos_falloff_end, self.cos_falloff_start)
    }

    /// Density per solid angle of a direction at cos θ in the falloff, chosen there with
    /// probability p₁/(p₀ + p₁): 2·smoothstep/(cos θ_start − cos θ_end) in cos θ, over 2π in φ.
    fn falloff_pdf(&self, cos_theta: f32, p: [f32; 2]) -> f32 {
        let width = self.cos_falloff_start - self.cos_falloff_end;
        2.0 / width * self.falloff(cos_theta) * p[1] / ((p[0] + p[1]) * 2.0 * PI)
    }

    /// The weights of the two parts of the cone [`SpotLight::sample_le`] chooses between
    /// (pbrt-v4's): the full cone, 1 − cos θ_start, and the falloff, (cos θ_start −
    /// cos θ_end)/2 (each ∝ its share of Φ).
    fn sections(&self) -> [f32; 2] {
        [
            1.0 - self.cos_falloff_start,
            (self.cos_falloff_start - self.cos_falloff_end) / 2.0,
        ]
    }
}

impl LightKind for SpotLight {
    fn light_type(&self) -> LightType {
        LightType::DeltaPosition
    }

    /// Li = I · falloff(θ) / r².
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
        let wi = d / r2.sqrt();
        let cos_theta = self.axis.dot(-wi);
        let falloff = self.falloff(cos_theta);
        if falloff == 0.0 {
            return None;
        }
        Some(LightLiSample {
            l: self.intensity * falloff / r2,
            factor: falloff / r2,
            wi,
            pdf: 1.0,
            p_light: self.p,
        })
    }

    /// Φ = 2π·I·(1 − (cos θ_start + cos θ_end)/2): full inside, half over the falloff.
    fn power(&self) -> f32 {
        let i = self.intensity;
        2.0 * PI
            * ((i.x + i.y + i.z) / 3.0)
            * (1.0 - 0.5 * (self.cos_falloff_start + self.cos_falloff_end))
    }

    /// Full intensity inside θ_start, falling off over θ_end − θ_start.
    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        let (start, end) = (self.cos_falloff_start, self.cos_falloff_end);
        let mut cos_theta_e = (safe_acos(end) - safe_acos(start)).cos();
        // Slack for round-off in the importance's cos θ' (as pbrt-v4).
        if cos_theta_e == 1.0 && end != start {
            cos_theta_e = 0.999;
        }
        let i = self.intensity;
        LightBounds {
            bounds: Bounds3::from_point(self.p),
            phi: 4.0 * PI * i.x.max(i.y).max(i.z),
            normals: DirectionCone {
                w: self.axis,
                cos_theta: start,
            },
            cos_theta_e,
            two_sided: false,
        }
        .extent()
    }

    fn constant_colour(&self) -> Option<Rgb> {
        Some(self.intensity)
    }

    /// pbrt-v4's: one of the two parts of the cone chosen by `u2.x` in proportion to
    /// [`SpotLight::sections`]; in the full cone a direction uniform in it, in the falloff
    /// cos θ with density ∝ smoothstep (2·smoothstep/(cos θ_start − cos θ_end)) and φ uniform.
    /// The density is then ∝ I(θ): every sample carries Φ exactly.
    fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        let p = self.sections();
        let (local, pdf_dir) = if u2.x * (p[0] + p[1]) < p[0] {
            let pdf = uniform_cone_pdf(self.cos_falloff_start) * p[0] / (p[0] + p[1]);
            (sample_uniform_cone(u1, self.cos_falloff_start), pdf)
        } else {
            let cos_theta = sample_smooth_step(u1.x, self.cos_falloff_end, self.cos_falloff_start);
            let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
            let phi = 2.0 * PI * u1.y;
            let w = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
            (w, self.falloff_pdf(cos_theta, p))
        };
        let falloff = self.falloff(local.z);
        if falloff == 0.0 || !(pdf_dir > 0.0 && pdf_dir.is_finite()) {
            return None;
        }
        Some(LightLeSample {
            l: self.intensity * falloff,
            factor: falloff,
            p: self.p,
            p_error: Vec3::ZERO,
            w: Frame::from_z(self.axis).from_local(local),
            n: Vec3::ZERO,
            pdf_pos: 1.0,
            pdf_dir,
        })
    }

    /// p_dir = p_cone/(p_cone + p_falloff) · 1/(2π(1 − cos θ_start)) inside θ_start,
    /// p_falloff/(p_cone + p_falloff) · 2·smoothstep/(cos θ_start − cos θ_end) / 2π over the
    /// falloff, 0 outside.
    fn pdf_le(&self, _: Vec3, _: Vec3, w: Vec3) -> LightLePdf {
        let p = self.sections();
        let cos_theta = self.axis.dot(w);
        let dir = if cos_theta >= self.cos_falloff_start {
            uniform_cone_pdf(self.cos_falloff_start) * p[0] / (p[0] + p[1])
        } else if cos_theta < self.cos_falloff_end {
            0.0
        } else {
            self.falloff_pdf(cos_theta, p)
        };
        LightLePdf { pos: 0.0, dir }
    }
}

/// A value of [a, b] with density ∝ smoothstep(x; a, b), a < b (pbrt-v4's `SampleSmoothStep`):
/// the CDF in t = (x − a)/(b − a) is P(t) = 2t³ − t⁴ (∫ of 3t² − 2t³, over its integral ½),
/// inverted by Newton steps kept inside a shrinking bracket.
fn sample_smooth_step(u: f32, a: f32, b: f32) -> f32 {
    let (mut lo, mut hi, mut t) = (0.0f32, 1.0f32, 0.5f32);
    for _ in 0..64 {
        let f = t * t * t * (2.0 - t) - u;
        if f.abs() < 1e-7 {
            break;
        }
        if f < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        // P'(t) = 6t² − 4t³.
        let next = t - f / (t * t * (6.0 - 4.0 * t));
        t = if next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
        if hi - lo < 1e-7 {
            break;
        }
    }
    a + t * (b - a)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};

    fn spot(angle: f32, delta: f32) -> SpotLight {
        SpotDesc {
            from: Vec3::new(1.0, 2.0, 3.0),
            to: Vec3::new(1.5, 1.0, 3.2),
            intensity: Rgb::new(3.0, 2.0, 1.0),
            cone_angle: angle,
            cone_delta_angle: delta,
        }
        .build(&SceneSphere::default())
        .unwrap()
    }

    #[test]
    fn smooth_step_samples_follow_its_cdf() {
        for k in 0..=20 {
            let u = k as f32 / 20.0;
            let x = sample_smooth_step(u, 0.2, 0.7);
            let t = (x - 0.2) / 0.5;
            assert!((t * t * t * (2.0 - t) - u).abs() < 1e-5, "{u} {x}");
        }
    }

    #[test]
    fn emitted_rays_carry_the_power_and_their_density_integrates_to_one() {
        for (angle, delta) in [(30.0, 5.0), (60.0, 60.0), (45.0, 0.0), (120.0, 30.0)] {
            let light = spot(angle, delta);
            let phi = le_power(&light, &[], &[], 1 << 14);
            let want = light.power();
            assert!(
                (phi - want).abs() < 2e-3 * want,
                "{angle} {delta}: {phi} vs {want}"
            );
            le_pdfs_agree(&light, &[], &[], 256, 1e-3);
            let total = le_dir_integral(&light, light.p, Vec3::ZERO, 1 << 16);
            assert!((total - 1.0).abs() < 0.03, "{angle} {delta}: {total}");
        }
    }

    #[test]
    fn falloff_follows_the_axis() {
        let light = spot(30.0, 10.0);
        let ctx = |p: Vec3| LightSampleContext::in_medium(p);
        let on_axis = light.sample_li(&ctx(light.p + 2.0 * light.axis), Vec2::ZERO, &[], &[]);
        let s = on_axis.expect("lit on the axis");
        assert!((s.l - light.intensity / 4.0).abs().max_element() < 1e-6);
        assert!(
            light
                .sample_li(&ctx(light.p - light.axis), Vec2::ZERO, &[], &[])
                .is_none()
        );
    }
}
