//! Lambertian reflection, and Lambertian reflection plus transmission.

use super::scatter::{
    BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode, abs_cos_theta, same_hemisphere,
};
use crate::math::{INV_PI, SampledSpectrum, Vec2, Vec3};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};

/// Lambert: f = ρ/π on the side of `wo`, sampled with density |cos θi|/π.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseBxdf {
    /// Albedo ρ (packed, as every colour of a BxDF, so that a [`BxDF`](super::BxDF) stays
    /// small enough to copy).
    pub r: SampledSpectrum,
}

impl Scatter for DiffuseBxdf {
    #[inline]
    fn flags(&self) -> BxdfFlags {
        if self.r == SampledSpectrum::ZERO {
            BxdfFlags::NONE
        } else {
            BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE
        }
    }

    #[inline]
    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if same_hemisphere(wo, wi) {
            self.r * INV_PI
        } else {
            SampledSpectrum::ZERO
        }
    }

    #[inline]
    fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        u: Vec2,
        _mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        if !mask.reflection() || self.r == SampledSpectrum::ZERO {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi));
        (pdf > 0.0).then(|| {
            BsdfSample::new(
                self.r * INV_PI,
                wi,
                pdf,
                BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE,
            )
        })
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, mask: ReflTrans) -> f32 {
        if !mask.reflection() || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        cosine_hemisphere_pdf(abs_cos_theta(wi))
    }
}

/// Lambertian reflection and transmission (pbrt-v4's `diffusetransmission`): f = R/π on the
/// side of `wo`, T/π on the other. The side is chosen with probability proportional to the
/// largest channel of R or T, then a cosine-weighted direction:
/// pdf = p_side · |cos θi|/π with p_R = max R / (max R + max T).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmissionBxdf {
    /// Reflectance R (packed).
    pub r: SampledSpectrum,
    /// Transmittance T (packed).
    pub t: SampledSpectrum,
}

impl DiffuseTransmissionBxdf {
    /// (p_R, p_T) after `mask`, unnormalised.
    #[inline]
    fn lobe_weights(&self, mask: ReflTrans) -> (f32, f32) {
        let pr = if mask.reflection() {
            self.r.max_element()
        } else {
            0.0
        };
        let pt = if mask.transmission() {
            self.t.max_element()
        } else {
            0.0
        };
        (pr, pt)
    }
}

impl Scatter for DiffuseTransmissionBxdf {
    fn flags(&self) -> BxdfFlags {
        let mut fl = BxdfFlags::NONE;
        if self.r != SampledSpectrum::ZERO {
            fl |= BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE;
        }
        if self.t != SampledSpectrum::ZERO {
            fl |= BxdfFlags::TRANSMISSION | BxdfFlags::DIFFUSE;
        }
        fl
    }

    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if same_hemisphere(wo, wi) {
            self.r * INV_PI
        } else {
            self.t * INV_PI
        }
    }

    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        let (pr, pt) = self.lobe_weights(mask);
        if pr == 0.0 && pt == 0.0 {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        let (p_lobe, flags) = if uc < pr / (pr + pt) {
            // Same side as wo.
            if wo.z < 0.0 {
                wi.z = -wi.z;
            }
            (pr / (pr + pt), BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE)
        } else {
            // The other side.
            if wo.z > 0.0 {
                wi.z = -wi.z;
            }
            (pt / (pr + pt), BxdfFlags::TRANSMISSION | BxdfFlags::DIFFUSE)
        };
        let pdf = cosine_hemisphere_pdf(abs_cos_theta(wi)) * p_lobe;
        (pdf > 0.0).then(|| BsdfSample::new(self.f(wo, wi, mode), wi, pdf, flags))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, mask: ReflTrans) -> f32 {
        let (pr, pt) = self.lobe_weights(mask);
        if pr == 0.0 && pt == 0.0 {
            return 0.0;
        }
        let p_lobe = if same_hemisphere(wo, wi) { pr } else { pt } / (pr + pt);
        p_lobe * cosine_hemisphere_pdf(abs_cos_theta(wi))
    }
}
