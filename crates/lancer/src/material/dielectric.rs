//! Dielectric interfaces: smooth or rough (Trowbridge–Reitz) Fresnel reflection and refraction,
//! and the thin slab of a window pane.

use super::fresnel::{fresnel_dielectric, reflect, refract};
use super::microfacet::TrowbridgeReitz;
use super::scatter::{
    BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode, abs_cos_theta, cos_theta,
    same_hemisphere,
};
use crate::math::{SampledSpectrum, Vec2, Vec3, face_forward};

/// A dielectric interface with relative index `eta` = η_inside/η_outside (the +z side is
/// outside).
///
/// Smooth: specular reflection with probability R = F(cos θo) and refraction (Snell) with
/// T = 1 − R, f_r = R/|cos θi|, f_t = T/|cos θi| (÷ η'² for radiance).
///
/// Rough (Walter et al. 2007, as pbrt-v4): with the generalised half vector
/// ωm = normalize(η'ωi + ωo) (η' = 1 for reflection, η or 1/η for refraction, facing +z),
/// f_r = D(ωm) G(ωo, ωi) F(ωo·ωm) / (4 |cos θi cos θo|),
/// f_t = D(ωm) G(ωo, ωi) (1 − F) |ωi·ωm| |ωo·ωm| / (|cos θi cos θo| (ωi·ωm + ωo·ωm/η')²)
/// (÷ η'² for radiance). A visible normal ωm is sampled, then reflection with probability
/// R/(R + T) or refraction; pdf_r = D_ωo(ωm)/(4|ωo·ωm|) · R/(R + T),
/// pdf_t = D_ωo(ωm) |ωi·ωm| / (ωi·ωm + ωo·ωm/η')² · T/(R + T).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricBxdf {
    /// Relative index of refraction.
    pub eta: f32,
    /// Microfacet distribution.
    pub distrib: TrowbridgeReitz,
}

impl DielectricBxdf {
    /// True when the interface is handled as a perfectly smooth one (no refraction at all
    /// when η = 1, where only the straight-through delta remains).
    #[inline]
    fn is_smooth(&self) -> bool {
        self.eta == 1.0 || self.distrib.effectively_smooth()
    }

    /// The generalised half vector of a pair, facing +z, with the relative index η' of the
    /// crossing (1 for reflection) — `None` for degenerate configurations and for microfacets
    /// that would face away from either direction.
    #[inline]
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, f32, bool)> {
        let (cos_o, cos_i) = (cos_theta(wo), cos_theta(wi));
        if cos_i == 0.0 || cos_o == 0.0 {
            return None;
        }
        let reflect = cos_i * cos_o > 0.0;
        let etap = if reflect {
            1.0
        } else if cos_o > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let wm = face_forward((wi * etap + wo).try_normalize()?, Vec3::Z);
        // Back-facing microfacets contribute nothing.
        if wm.dot(wi) * cos_i < 0.0 || wm.dot(wo) * cos_o < 0.0 {
            return None;
        }
        Some((wm, etap, reflect))
    }

    /// (p_R, p_T) after `mask`, unnormalised.
    #[inline]
    fn lobe_weights(r: f32, mask: ReflTrans) -> (f32, f32) {
        (
            if mask.reflection() { r } else { 0.0 },
            if mask.transmission() { 1.0 - r } else { 0.0 },
        )
    }
}

impl Scatter for DielectricBxdf {
    fn flags(&self) -> BxdfFlags {
        let sides = if self.eta == 1.0 {
            BxdfFlags::TRANSMISSION
        } else {
            BxdfFlags::REFLECTION | BxdfFlags::TRANSMISSION
        };
        sides
            | if self.distrib.effectively_smooth() {
                BxdfFlags::SPECULAR
            } else {
                BxdfFlags::GLOSSY
            }
    }

    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if self.is_smooth() {
            return SampledSpectrum::ZERO;
        }
        let Some((wm, etap, reflect)) = self.half_vector(wo, wi) else {
            return SampledSpectrum::ZERO;
        };
        let (cos_o, cos_i) = (cos_theta(wo), cos_theta(wi));
        let fr = fresnel_dielectric(wo.dot(wm), self.eta);
        let d = &self.distrib;
        if reflect {
            SampledSpectrum::splat(d.d(wm) * d.g(wo, wi) * fr / (4.0 * cos_i * cos_o).abs())
        } else {
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2) * cos_i * cos_o;
            let mut ft =
                d.d(wm) * (1.0 - fr) * d.g(wo, wi) * (wi.dot(wm) * wo.dot(wm) / denom).abs();
            if mode == TransportMode::Radiance {
                ft /= etap * etap;
            }
            SampledSpectrum::splat(ft)
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
        if self.is_smooth() {
            let r = fresnel_dielectric(cos_theta(wo), self.eta);
            let (pr, pt) = Self::lobe_weights(r, mask);
            if pr == 0.0 && pt == 0.0 {
                return None;
            }
            if uc < pr / (pr + pt) {
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let c = abs_cos_theta(wi);
                if c == 0.0 {
                    return None;
                }
                return Some(BsdfSample::new(
                    SampledSpectrum::splat(r / c),
                    wi,
                    pr / (pr + pt),
                    BxdfFlags::REFLECTION | BxdfFlags::SPECULAR,
                ));
            }
            let (wi, etap) = refract(wo, Vec3::Z, self.eta)?;
            let c = abs_cos_theta(wi);
            if c == 0.0 {
                return None;
            }
            let mut ft = (1.0 - r) / c;
            // Radiance is compressed into a smaller solid angle when entering a denser
            // medium: L scales by 1/η².
            if mode == TransportMode::Radiance {
                ft /= etap * etap;
            }
            return Some(BsdfSample {
                eta: etap,
                ..BsdfSample::new(
                    SampledSpectrum::splat(ft),
                    wi,
                    pt / (pr + pt),
                    BxdfFlags::TRANSMISSION | BxdfFlags::SPECULAR,
                )
            });
        }
        if wo.z == 0.0 {
            return None;
        }
        let d = &self.distrib;
        let wm = d.sample_wm(wo, u);
        let r = fresnel_dielectric(wo.dot(wm), self.eta);
        let (pr, pt) = Self::lobe_weights(r, mask);
        if pr == 0.0 && pt == 0.0 {
            return None;
        }
        if uc < pr / (pr + pt) {
            let wi = reflect(wo, wm);
            if !same_hemisphere(wo, wi) {
                return None;
            }
            // D(ωm) and Λ(ωo) serve both the density and the value.
            let (d_wm, lambda_o) = (d.d(wm), d.lambda(wo));
            let pdf = TrowbridgeReitz::d_visible_from(wo, wm, d_wm, lambda_o)
                / (4.0 * wo.dot(wm).abs())
                * pr
                / (pr + pt);
            let g = TrowbridgeReitz::g_from_lambdas(lambda_o, d.lambda(wi));
            let f = d_wm * g * r / (4.0 * cos_theta(wi) * cos_theta(wo));
            return Some(BsdfSample::new(
                SampledSpectrum::splat(f),
                wi,
                pdf,
                BxdfFlags::REFLECTION | BxdfFlags::GLOSSY,
            ));
        }
        let (wi, etap) = refract(wo, wm, self.eta)?;
        if same_hemisphere(wo, wi) || wi.z == 0.0 {
            return None;
        }
        // dωm/dωi = |ωi·ωm| / (ωi·ωm + ωo·ωm/η')²
        let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
        let dwm_dwi = wi.dot(wm).abs() / denom;
        let (d_wm, lambda_o) = (d.d(wm), d.lambda(wo));
        let pdf =
            TrowbridgeReitz::d_visible_from(wo, wm, d_wm, lambda_o) * dwm_dwi * pt / (pr + pt);
        let mut ft = (1.0 - r)
            * d_wm
            * TrowbridgeReitz::g_from_lambdas(lambda_o, d.lambda(wi))
            * (wi.dot(wm) * wo.dot(wm) / (cos_theta(wi) * cos_theta(wo) * denom)).abs();
        if mode == TransportMode::Radiance {
            ft /= etap * etap;
        }
        Some(BsdfSample {
            eta: etap,
            ..BsdfSample::new(
                SampledSpectrum::splat(ft),
                wi,
                pdf,
                BxdfFlags::TRANSMISSION | BxdfFlags::GLOSSY,
            )
        })
    }

    /// f and pdf sharing the half vector, the Fresnel term, D(ωm) and Λ(ωo): the same
    /// expressions as [`Scatter::f`] and [`Scatter::pdf`], so the same bits.
    fn f_pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> (SampledSpectrum, f32) {
        if self.is_smooth() {
            return (SampledSpectrum::ZERO, 0.0);
        }
        let Some((wm, etap, reflect)) = self.half_vector(wo, wi) else {
            return (SampledSpectrum::ZERO, 0.0);
        };
        let (cos_o, cos_i) = (cos_theta(wo), cos_theta(wi));
        let fr = fresnel_dielectric(wo.dot(wm), self.eta);
        let d = &self.distrib;
        let (d_wm, lambda_o) = (d.d(wm), d.lambda(wo));
        let g = TrowbridgeReitz::g_from_lambdas(lambda_o, d.lambda(wi));
        let (pr, pt) = Self::lobe_weights(fr, mask);
        let lobes = pr != 0.0 || pt != 0.0;
        if reflect {
            let f = d_wm * g * fr / (4.0 * cos_i * cos_o).abs();
            let pdf = if lobes {
                TrowbridgeReitz::d_visible_from(wo, wm, d_wm, lambda_o) / (4.0 * wo.dot(wm).abs())
                    * pr
                    / (pr + pt)
            } else {
                0.0
            };
            (SampledSpectrum::splat(f), pdf)
        } else {
            let denom_pdf = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            let denom = denom_pdf * cos_i * cos_o;
            let mut ft = d_wm * (1.0 - fr) * g * (wi.dot(wm) * wo.dot(wm) / denom).abs();
            if mode == TransportMode::Radiance {
                ft /= etap * etap;
            }
            let pdf = if lobes {
                let dwm_dwi = wi.dot(wm).abs() / denom_pdf;
                TrowbridgeReitz::d_visible_from(wo, wm, d_wm, lambda_o) * dwm_dwi * pt / (pr + pt)
            } else {
                0.0
            };
            (SampledSpectrum::splat(ft), pdf)
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, mask: ReflTrans) -> f32 {
        if self.is_smooth() {
            return 0.0;
        }
        let Some((wm, etap, reflect)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let r = fresnel_dielectric(wo.dot(wm), self.eta);
        let (pr, pt) = Self::lobe_weights(r, mask);
        if pr == 0.0 && pt == 0.0 {
            return 0.0;
        }
        let d = &self.distrib;
        if reflect {
            d.pdf(wo, wm) / (4.0 * wo.dot(wm).abs()) * pr / (pr + pt)
        } else {
            let denom = (wi.dot(wm) + wo.dot(wm) / etap).powi(2);
            let dwm_dwi = wi.dot(wm).abs() / denom;
            d.pdf(wo, wm) * dwm_dwi * pt / (pr + pt)
        }
    }
}

/// An infinitely thin dielectric slab (pbrt-v4's `thindielectric`): light either reflects
/// specularly or passes straight through (wi = −wo), after any number of internal bounces.
/// With single-interface Fresnel reflectance R and T = 1 − R, summing the geometric series of
/// internal reflections gives R' = R + T²R/(1 − R²) and T' = 1 − R'.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectricBxdf {
    /// Index of refraction of the slab.
    pub eta: f32,
}

impl ThinDielectricBxdf {
    /// (R', T') for outgoing cosine `cos_o`.
    #[inline]
    pub fn reflectance_transmittance(&self, cos_o: f32) -> (f32, f32) {
        let mut r = fresnel_dielectric(cos_o.abs(), self.eta);
        let mut t = 1.0 - r;
        if r < 1.0 {
            r += t * t * r / (1.0 - r * r);
            t = 1.0 - r;
        }
        (r, t)
    }
}

impl Scatter for ThinDielectricBxdf {
    fn flags(&self) -> BxdfFlags {
        BxdfFlags::REFLECTION | BxdfFlags::TRANSMISSION | BxdfFlags::SPECULAR
    }

    fn f(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        SampledSpectrum::ZERO
    }

    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        _u: Vec2,
        _mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        let (r, t) = self.reflectance_transmittance(cos_theta(wo));
        let pr = if mask.reflection() { r } else { 0.0 };
        let pt = if mask.transmission() { t } else { 0.0 };
        if pr == 0.0 && pt == 0.0 {
            return None;
        }
        let c = abs_cos_theta(wo);
        if c == 0.0 {
            return None;
        }
        Some(if uc < pr / (pr + pt) {
            BsdfSample::new(
                SampledSpectrum::splat(r / c),
                Vec3::new(-wo.x, -wo.y, wo.z),
                pr / (pr + pt),
                BxdfFlags::REFLECTION | BxdfFlags::SPECULAR,
            )
        } else {
            BsdfSample::new(
                SampledSpectrum::splat(t / c),
                -wo,
                pt / (pr + pt),
                BxdfFlags::TRANSMISSION | BxdfFlags::SPECULAR,
            )
        })
    }

    fn pdf(&self, _wo: Vec3, _wi: Vec3, _mode: TransportMode, _mask: ReflTrans) -> f32 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    #[test]
    fn f_pdf_gives_f_and_pdf_bit_for_bit() {
        // The fused evaluation the layered walks use must not change their estimates: same
        // bits as f and pdf apart, for reflection and refraction pairs, both sides, each mask.
        let mut rng = Pcg32::new(11, 2);
        let mut dir = || {
            let z = 2.0 * rng.uniform() - 1.0;
            let phi = 2.0 * std::f32::consts::PI * rng.uniform();
            let s = (1.0 - z * z).max(0.0).sqrt();
            Vec3::new(s * phi.cos(), s * phi.sin(), z)
        };
        for b in [
            DielectricBxdf {
                eta: 1.5,
                distrib: TrowbridgeReitz::new(0.3, 0.3),
            },
            DielectricBxdf {
                eta: 1.33,
                distrib: TrowbridgeReitz::new(0.05, 0.4),
            },
        ] {
            for _ in 0..2000 {
                let (wo, wi) = (dir(), dir());
                for mode in [TransportMode::Radiance, TransportMode::Importance] {
                    for mask in [
                        ReflTrans::ALL,
                        ReflTrans::REFLECTION,
                        ReflTrans::TRANSMISSION,
                    ] {
                        let (f, pdf) = b.f_pdf(wo, wi, mode, mask);
                        assert_eq!(f, b.f(wo, wi, mode));
                        assert_eq!(pdf.to_bits(), b.pdf(wo, wi, mode, mask).to_bits());
                    }
                }
            }
        }
    }
}
