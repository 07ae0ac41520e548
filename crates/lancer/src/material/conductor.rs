//! Conductors: Fresnel reflection with a complex index of refraction, from a perfect mirror or
//! from a Trowbridge–Reitz microsurface (Torrance–Sparrow).

use super::fresnel::{fresnel_complex, reflect};
use super::microfacet::TrowbridgeReitz;
use super::scatter::{
    BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode, abs_cos_theta, same_hemisphere,
};
use crate::math::{SampledSpectrum, Vec2, Vec3, face_forward};

/// A conductor with index `eta + i·k` per channel.
///
/// Smooth (α < 10⁻³): a mirror, wi = (−wo.x, −wo.y, wo.z), f = F(|cos θi|)/|cos θi| δ(…).
/// Rough: the Torrance–Sparrow BRDF
/// f = D(ωm) F(|ωo·ωm|) G(ωo, ωi) / (4 |cos θo| |cos θi|), ωm = normalize(ωo + ωi),
/// sampled through visible normals: pdf = D_ωo(ωm) / (4 |ωo·ωm|).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConductorBxdf {
    /// Microfacet distribution.
    pub distrib: TrowbridgeReitz,
    /// Real part of the index, per channel (packed, as every colour of a BxDF).
    pub eta: SampledSpectrum,
    /// Imaginary part (absorption), per channel (packed).
    pub k: SampledSpectrum,
}

impl Scatter for ConductorBxdf {
    fn flags(&self) -> BxdfFlags {
        if self.distrib.effectively_smooth() {
            BxdfFlags::REFLECTION | BxdfFlags::SPECULAR
        } else {
            BxdfFlags::REFLECTION | BxdfFlags::GLOSSY
        }
    }

    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) || self.distrib.effectively_smooth() {
            return SampledSpectrum::ZERO;
        }
        let (cos_o, cos_i) = (abs_cos_theta(wo), abs_cos_theta(wi));
        if cos_i == 0.0 || cos_o == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let Some(wm) = (wi + wo).try_normalize() else {
            return SampledSpectrum::ZERO;
        };
        let fr = fresnel_complex(wo.dot(wm).abs(), self.eta, self.k);
        // f = D F G / (4 cos θo cos θi)
        self.distrib.d(wm) * fr * self.distrib.g(wo, wi) / (4.0 * cos_i * cos_o)
    }

    fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        u: Vec2,
        _mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        if !mask.reflection() {
            return None;
        }
        if self.distrib.effectively_smooth() {
            let wi = Vec3::new(-wo.x, -wo.y, wo.z);
            let c = abs_cos_theta(wi);
            if c == 0.0 {
                return None;
            }
            return Some(BsdfSample::new(
                fresnel_complex(c, self.eta, self.k) / c,
                wi,
                1.0,
                BxdfFlags::REFLECTION | BxdfFlags::SPECULAR,
            ));
        }
        if wo.z == 0.0 {
            return None;
        }
        let wm = self.distrib.sample_wm(wo, u);
        let wi = reflect(wo, wm);
        if !same_hemisphere(wo, wi) {
            return None;
        }
        let d = &self.distrib;
        // D(ωm) and Λ(ωo) serve both the density and the value.
        let (d_wm, lambda_o) = (d.d(wm), d.lambda(wo));
        // dωm/dωi = 1/(4 |ωo·ωm|) for reflection.
        let pdf =
            TrowbridgeReitz::d_visible_from(wo, wm, d_wm, lambda_o) / (4.0 * wo.dot(wm).abs());
        let (cos_o, cos_i) = (abs_cos_theta(wo), abs_cos_theta(wi));
        if cos_i == 0.0 || cos_o == 0.0 {
            return None;
        }
        let fr = fresnel_complex(wo.dot(wm).abs(), self.eta, self.k);
        let g = TrowbridgeReitz::g_from_lambdas(lambda_o, d.lambda(wi));
        let f = d_wm * fr * g / (4.0 * cos_i * cos_o);
        Some(BsdfSample::new(
            f,
            wi,
            pdf,
            BxdfFlags::REFLECTION | BxdfFlags::GLOSSY,
        ))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, mask: ReflTrans) -> f32 {
        if !mask.reflection() || !same_hemisphere(wo, wi) || self.distrib.effectively_smooth() {
            return 0.0;
        }
        let Some(wm) = (wo + wi).try_normalize() else {
            return 0.0;
        };
        let wm = face_forward(wm, Vec3::Z);
        self.distrib.pdf(wo, wm) / (4.0 * wo.dot(wm).abs())
    }
}
