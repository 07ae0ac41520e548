//! Hair: pbrt-v4's `HairBxDF`, the model of d'Eon et al. (2011) with Chiang et al.'s (2016)
//! azimuthal logistic and lobe widths, and Marschner et al.'s tilted cuticle scales.
//!
//! The fibre is a dielectric cylinder of index η with absorption σₐ inside. Light leaves it
//! after p internal paths: p = 0 reflection (R), p = 1 transmission (TT), p = 2 one internal
//! reflection (TRT), and one lumped term for every longer path. Each term is a product
//! f_p = M_p(θo, θi) · A_p(θo, h) · N_p(φ) / |cos θi|:
//!
//! - **M_p**, the longitudinal lobe, a von Mises–Fisher-like function of the angles to the
//!   fibre's normal plane with variance v_p (from `beta_m`);
//! - **A_p**, the attenuation: Fresnel at the entry and between bounces, and the transmittance
//!   T = exp(−σₐ · 2 cos γt / cos θt) of one crossing;
//! - **N_p**, the azimuthal lobe: a logistic of scale s (from `beta_n`) around the exit angle
//!   Φ(p) = 2pγt − 2γo + pπ, trimmed to [−π, π].
//!
//! Local frame: x is along the fibre (∂p/∂u of the curve), so sin θ = w.x and φ = atan2(w.z, w.y);
//! h ∈ [−1, 1] is where across its width the ray met the fibre.

use super::fresnel::fresnel_dielectric;
use super::scatter::{BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode};
use crate::math::{Rgb, SampledSpectrum, Vec2, Vec3};
use std::f32::consts::{PI, TAU};

/// Number of explicit scattering terms before the lumped remainder (pbrt's `pMax`).
const P_MAX: usize = 3;

/// pbrt-v4's `HairBxDF`: a hair fibre seen at offset `h` across its width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairBxdf {
    /// Offset across the fibre, −1 (one edge) to 1 (the other).
    pub h: f32,
    /// Index of refraction of the fibre.
    pub eta: f32,
    /// Absorption coefficient inside the fibre, per unit of the fibre's diameter.
    pub sigma_a: SampledSpectrum,
    /// Longitudinal variance of each term p = 0..=3.
    v: [f32; P_MAX + 1],
    /// Azimuthal logistic scale s.
    s: f32,
    /// sin(2ᵏα) for k = 0, 1, 2 (α the cuticle scales' tilt).
    sin_2k_alpha: [f32; P_MAX],
    /// cos(2ᵏα).
    cos_2k_alpha: [f32; P_MAX],
}

/// Absorption of eumelanin and pheomelanin per unit concentration (pbrt-v4, linear sRGB).
const EUMELANIN_SIGMA_A: Rgb = Rgb::new(0.419, 0.697, 1.37);
const PHEOMELANIN_SIGMA_A: Rgb = Rgb::new(0.187, 0.4, 1.05);

/// σₐ of a fibre with concentrations `ce` of eumelanin and `cp` of pheomelanin (linear sRGB,
/// an unbounded colour): ce · (0.419, 0.697, 1.37) + cp · (0.187, 0.4, 1.05).
pub fn hair_sigma_a_from_concentration(ce: f32, cp: f32) -> Rgb {
    ce * EUMELANIN_SIGMA_A + cp * PHEOMELANIN_SIGMA_A
}

/// σₐ that makes a fibre of azimuthal roughness `beta_n` have (multiply scattered) colour `c`,
/// per lane (Chiang et al.'s fit): σₐ = (ln c / (5.969 − 0.215βn + 2.532βn² − 10.73βn³ +
/// 5.574βn⁴ + 0.245βn⁵))². A colour of 0 would make σₐ infinite; it is taken as 10⁻⁴.
pub fn hair_sigma_a_from_reflectance(c: SampledSpectrum, beta_n: f32) -> SampledSpectrum {
    let b = beta_n;
    let d = 5.969 - 0.215 * b + 2.532 * b * b - 10.73 * b.powi(3)
        + 5.574 * b.powi(4)
        + 0.245 * b.powi(5);
    c.max(SampledSpectrum::splat(1e-4)).map(|c| {
        let x = c.ln() / d;
        x * x
    })
}

/// I₀(x), the modified Bessel function of the first kind of order 0, by its series
/// Σᵢ x²ⁱ / (4ⁱ (i!)²), ten terms.
fn bessel_i0(x: f32) -> f32 {
    let (mut val, mut x2i, mut ifact, mut i4) = (0.0f32, 1.0f32, 1.0f32, 1.0f32);
    for i in 0..10 {
        if i > 1 {
            ifact *= i as f32;
        }
        val += x2i / (i4 * ifact * ifact);
        x2i *= x * x;
        i4 *= 4.0;
    }
    val
}

/// ln I₀(x): for x > 12 the asymptote x + ½(−ln 2π + ln(1/x) + 1/(8x)), else ln of the series.
fn log_bessel_i0(x: f32) -> f32 {
    if x > 12.0 {
        x + 0.5 * (-(TAU).ln() + (1.0 / x).ln() + 1.0 / (8.0 * x))
    } else {
        bessel_i0(x).ln()
    }
}

/// The longitudinal lobe M_p with variance v:
/// M = e^(−sin θi sin θo / v) I₀(cos θi cos θo / v) / (2v sinh(1/v)), evaluated in logarithms
/// for v ≤ 0.1 where sinh and I₀ overflow: exp(ln I₀(a) − b − 1/v + ln 2 + ln(1/(2v))).
fn mp(cos_i: f32, cos_o: f32, sin_i: f32, sin_o: f32, v: f32) -> f32 {
    let a = cos_i * cos_o / v;
    let b = sin_i * sin_o / v;
    if v <= 0.1 {
        (log_bessel_i0(a) - b - 1.0 / v + std::f32::consts::LN_2 + (1.0 / (2.0 * v)).ln()).exp()
    } else {
        (-b).exp() * bessel_i0(a) / ((1.0 / v).sinh() * 2.0 * v)
    }
}

/// The attenuations A₀..A₃ for a ray at cos θo hitting at offset h, with one crossing's
/// transmittance T: A₀ = F, A₁ = (1 − F)² T, A_p = A_{p−1} T F, and the remainder
/// A₃ = A₂ F T / (1 − F T) (a geometric series), F the Fresnel reflectance at
/// cos θ = cos θo cos γo.
fn ap(cos_theta_o: f32, eta: f32, h: f32, t: SampledSpectrum) -> [SampledSpectrum; P_MAX + 1] {
    let cos_gamma_o = (1.0 - h * h).max(0.0).sqrt();
    let f = fresnel_dielectric(cos_theta_o * cos_gamma_o, eta);
    let mut a = [SampledSpectrum::ZERO; P_MAX + 1];
    a[0] = SampledSpectrum::splat(f);
    a[1] = (1.0 - f) * (1.0 - f) * t;
    for p in 2..P_MAX {
        a[p] = a[p - 1] * t * f;
    }
    let denom = SampledSpectrum::ONE - t * f;
    // Lanes where T F = 1 (no loss at all) keep 0, as pbrt's whole-spectrum test does
    // lane by lane.
    a[P_MAX] = SampledSpectrum::select(
        denom.cmpne(SampledSpectrum::ZERO),
        a[P_MAX - 1] * f * t / denom,
        SampledSpectrum::ZERO,
    );
    a
}

/// Φ(p) = 2pγt − 2γo + pπ: the azimuth at which term p leaves the fibre.
#[inline]
fn phi_exit(p: usize, gamma_o: f32, gamma_t: f32) -> f32 {
    let p = p as f32;
    2.0 * p * gamma_t - 2.0 * gamma_o + p * PI
}

/// The logistic density of scale s: e^(−|x|/s) / (s (1 + e^(−|x|/s))²).
fn logistic(x: f32, s: f32) -> f32 {
    let e = (-x.abs() / s).exp();
    e / (s * (1.0 + e) * (1.0 + e))
}

/// Its cumulative distribution: 1/(1 + e^(−x/s)).
fn logistic_cdf(x: f32, s: f32) -> f32 {
    1.0 / (1.0 + (-x / s).exp())
}

/// The logistic restricted to [−π, π] and renormalised.
fn trimmed_logistic(x: f32, s: f32) -> f32 {
    logistic(x, s) / (logistic_cdf(PI, s) - logistic_cdf(-PI, s))
}

/// Samples the trimmed logistic by inversion: u mapped into [P(−π), P(π)], then
/// x = −s ln(1/u − 1), clamped to [−π, π].
fn sample_trimmed_logistic(u: f32, s: f32) -> f32 {
    let (a, b) = (logistic_cdf(-PI, s), logistic_cdf(PI, s));
    let u = a + u * (b - a);
    (-s * (1.0 / u - 1.0).ln()).clamp(-PI, PI)
}

/// The azimuthal lobe N_p at relative azimuth φ: the trimmed logistic of φ − Φ(p), wrapped to
/// [−π, π].
fn np(phi: f32, p: usize, s: f32, gamma_o: f32, gamma_t: f32) -> f32 {
    let mut dphi = phi - phi_exit(p, gamma_o, gamma_t);
    while dphi > PI {
        dphi -= TAU;
    }
    while dphi < -PI {
        dphi += TAU;
    }
    trimmed_logistic(dphi, s)
}

/// asin clamped to its domain.
#[inline]
fn safe_asin(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).asin()
}

/// √max(x, 0).
#[inline]
fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// Everything about a direction `wo` the terms share.
struct Outgoing {
    sin_theta: f32,
    cos_theta: f32,
    phi: f32,
    gamma_o: f32,
    gamma_t: f32,
    /// T = exp(−σₐ · 2 cos γt / cos θt).
    t: SampledSpectrum,
}

impl HairBxdf {
    /// A fibre hit at `h` with index `eta`, absorption `sigma_a`, longitudinal roughness
    /// `beta_m`, azimuthal roughness `beta_n` (both in [0, 1]) and scale tilt `alpha_deg`
    /// (degrees). The lobe widths are Chiang et al.'s fits:
    /// v₀ = (0.726βm + 0.812βm² + 3.7βm²⁰)², v₁ = v₀/4, v₂ = v₃ = 4v₀, and
    /// s = √(π/8) (0.265βn + 1.194βn² + 5.372βn²²).
    pub fn new(
        h: f32,
        eta: f32,
        sigma_a: SampledSpectrum,
        beta_m: f32,
        beta_n: f32,
        alpha_deg: f32,
    ) -> HairBxdf {
        let h = if h.is_finite() {
            h.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        let bm = beta_m.clamp(0.0, 1.0);
        let bn = beta_n.clamp(0.0, 1.0);
        let v0 = {
            let x = 0.726 * bm + 0.812 * bm * bm + 3.7 * bm.powi(20);
            x * x
        };
        let v = [v0, 0.25 * v0, 4.0 * v0, 4.0 * v0];
        const SQRT_PI_OVER_8: f32 = 0.626_657_07;
        let s = SQRT_PI_OVER_8 * (0.265 * bn + 1.194 * bn * bn + 5.372 * bn.powi(22));
        let mut sin_2k_alpha = [0.0; P_MAX];
        let mut cos_2k_alpha = [0.0; P_MAX];
        sin_2k_alpha[0] = alpha_deg.to_radians().sin();
        cos_2k_alpha[0] = safe_sqrt(1.0 - sin_2k_alpha[0] * sin_2k_alpha[0]);
        // Double angles: sin 2x = 2 sin x cos x, cos 2x = cos²x − sin²x.
        for i in 1..P_MAX {
            sin_2k_alpha[i] = 2.0 * cos_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
            cos_2k_alpha[i] = cos_2k_alpha[i - 1] * cos_2k_alpha[i - 1]
                - sin_2k_alpha[i - 1] * sin_2k_alpha[i - 1];
        }
        HairBxdf {
            h,
            eta,
            sigma_a: sigma_a.max(SampledSpectrum::ZERO),
            v,
            s,
            sin_2k_alpha,
            cos_2k_alpha,
        }
    }

    /// The angles of `wo` and the refracted ray: sin θt = sin θo / η, the modified index
    /// η′ = √(η² − sin²θo) / cos θo, sin γt = h / η′, and the transmittance of one crossing.
    fn outgoing(&self, wo: Vec3) -> Outgoing {
        let sin_theta = wo.x;
        let cos_theta = safe_sqrt(1.0 - sin_theta * sin_theta);
        let sin_theta_t = sin_theta / self.eta;
        let cos_theta_t = safe_sqrt(1.0 - sin_theta_t * sin_theta_t);
        let etap = safe_sqrt(self.eta * self.eta - sin_theta * sin_theta) / cos_theta;
        let sin_gamma_t = self.h / etap;
        let cos_gamma_t = safe_sqrt(1.0 - sin_gamma_t * sin_gamma_t);
        let t = (-self.sigma_a * (2.0 * cos_gamma_t / cos_theta_t)).map(f32::exp);
        Outgoing {
            sin_theta,
            cos_theta,
            phi: wo.z.atan2(wo.y),
            gamma_o: safe_asin(self.h),
            gamma_t: safe_asin(sin_gamma_t),
            t,
        }
    }

    /// θo as term p sees it, tilted by the scales: R by −2α, TT by α, TRT by 4α (the
    /// rotations written with the sines and cosines of 2ᵏα); |cos| keeps it in range.
    fn tilted(&self, p: usize, sin_o: f32, cos_o: f32) -> (f32, f32) {
        let (s, c) = match p {
            0 => (
                sin_o * self.cos_2k_alpha[1] - cos_o * self.sin_2k_alpha[1],
                cos_o * self.cos_2k_alpha[1] + sin_o * self.sin_2k_alpha[1],
            ),
            1 => (
                sin_o * self.cos_2k_alpha[0] + cos_o * self.sin_2k_alpha[0],
                cos_o * self.cos_2k_alpha[0] - sin_o * self.sin_2k_alpha[0],
            ),
            2 => (
                sin_o * self.cos_2k_alpha[2] + cos_o * self.sin_2k_alpha[2],
                cos_o * self.cos_2k_alpha[2] - sin_o * self.sin_2k_alpha[2],
            ),
            _ => (sin_o, cos_o),
        };
        (s, c.abs())
    }

    /// The probability of sampling each term: A_p averaged over the lanes, normalised.
    /// (In RGB mode the lanes are (r, g, b, b), which weights blue twice: this only shapes
    /// the sampling, whose density is accounted for exactly.)
    fn ap_pdf(&self, o: &Outgoing) -> [f32; P_MAX + 1] {
        let a = ap(o.cos_theta, self.eta, self.h, o.t);
        let w = a.map(|x| x.element_sum() * 0.25);
        let sum: f32 = w.iter().sum();
        if sum > 0.0 && sum.is_finite() {
            w.map(|x| x / sum)
        } else {
            [1.0, 0.0, 0.0, 0.0]
        }
    }

    /// The density of `wi` given the terms' probabilities `ap_pdf`, at relative azimuth `dphi`:
    /// Σ_p M_p · P(p) · N_p(Δφ) + M₃ · P(3) / 2π.
    fn pdf_given(&self, o: &Outgoing, wi: Vec3, dphi: f32, ap_pdf: &[f32; P_MAX + 1]) -> f32 {
        let sin_i = wi.x;
        let cos_i = safe_sqrt(1.0 - sin_i * sin_i);
        let mut pdf = 0.0;
        for (p, &w) in ap_pdf.iter().enumerate().take(P_MAX) {
            let (sin_o, cos_o) = self.tilted(p, o.sin_theta, o.cos_theta);
            pdf += mp(cos_i, cos_o, sin_i, sin_o, self.v[p])
                * w
                * np(dphi, p, self.s, o.gamma_o, o.gamma_t);
        }
        pdf + mp(cos_i, o.cos_theta, sin_i, o.sin_theta, self.v[P_MAX]) * ap_pdf[P_MAX] / TAU
    }
}

/// pbrt's `SampleDiscrete`: the index i with Σ_{j<i} w_j ≤ u Σw < Σ_{j≤i} w_j, and u remapped
/// to [0, 1) within that interval.
fn sample_discrete(w: &[f32; P_MAX + 1], u: f32) -> (usize, f32) {
    let sum: f32 = w.iter().sum();
    let up = u * sum;
    let mut acc = 0.0;
    for (i, &wi) in w.iter().enumerate() {
        if wi > 0.0 && (up < acc + wi || i == P_MAX) {
            let r = ((up - acc) / wi).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
            return (i, r);
        }
        acc += wi;
    }
    // Only reached when the last weights are zero and rounding left u·Σw past the sum.
    let last = w.iter().rposition(|&x| x > 0.0).unwrap_or(0);
    (last, 1.0 - f32::EPSILON / 2.0)
}

impl Scatter for HairBxdf {
    fn flags(&self) -> BxdfFlags {
        BxdfFlags::REFLECTION | BxdfFlags::GLOSSY
    }

    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        let o = self.outgoing(wo);
        let sin_i = wi.x;
        let cos_i = safe_sqrt(1.0 - sin_i * sin_i);
        let phi = wi.z.atan2(wi.y) - o.phi;
        let a = ap(o.cos_theta, self.eta, self.h, o.t);
        let mut sum = SampledSpectrum::ZERO;
        for (p, ap) in a.iter().enumerate().take(P_MAX) {
            let (sin_o, cos_o) = self.tilted(p, o.sin_theta, o.cos_theta);
            sum += mp(cos_i, cos_o, sin_i, sin_o, self.v[p])
                * *ap
                * np(phi, p, self.s, o.gamma_o, o.gamma_t);
        }
        // Every longer path: no azimuthal preference.
        sum += mp(cos_i, o.cos_theta, sin_i, o.sin_theta, self.v[P_MAX]) * a[P_MAX] / TAU;
        // The terms are radiance per unit projected area: divide out |cos θi| (of the shading
        // frame), which the integrator multiplies back in.
        let cos = wi.z.abs();
        if cos > 0.0 { sum / cos } else { sum }
    }

    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        if !mask.reflection() {
            return None;
        }
        let o = self.outgoing(wo);
        let ap_pdf = self.ap_pdf(&o);
        let (p, uc) = sample_discrete(&ap_pdf, uc);
        let (sin_o, cos_o) = self.tilted(p, o.sin_theta, o.cos_theta);
        // M_p by inversion (d'Eon et al.): cos θ = 1 + v ln(u₀ + (1 − u₀) e^(−2/v)), then
        // sin θi = −cos θ sin θo + sin θ cos(2πu₁) cos θo.
        let v = self.v[p];
        let cos_theta = 1.0 + v * (u.x.max(1e-5) + (1.0 - u.x) * (-2.0 / v).exp()).ln();
        let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
        let cos_phi = (TAU * u.y).cos();
        let sin_i = -cos_theta * sin_o + sin_theta * cos_phi * cos_o;
        let cos_i = safe_sqrt(1.0 - sin_i * sin_i);
        // N_p: Δφ = Φ(p) + a trimmed-logistic offset; the remainder is uniform.
        let dphi = if p < P_MAX {
            phi_exit(p, o.gamma_o, o.gamma_t) + sample_trimmed_logistic(uc, self.s)
        } else {
            TAU * uc
        };
        let phi_i = o.phi + dphi;
        let wi = Vec3::new(sin_i, cos_i * phi_i.cos(), cos_i * phi_i.sin());
        let pdf = self.pdf_given(&o, wi, dphi, &ap_pdf);
        Some(BsdfSample::new(self.f(wo, wi, mode), wi, pdf, self.flags()))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, mask: ReflTrans) -> f32 {
        if !mask.reflection() {
            return 0.0;
        }
        let o = self.outgoing(wo);
        let ap_pdf = self.ap_pdf(&o);
        let dphi = wi.z.atan2(wi.y) - o.phi;
        self.pdf_given(&o, wi, dphi, &ap_pdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bessel_i0_matches_tabulated_values() {
        // I₀(0) = 1, I₀(1) = 1.2660659, I₀(5) = 27.239872 (Abramowitz & Stegun, table 9.8).
        assert_eq!(bessel_i0(0.0), 1.0);
        assert!((bessel_i0(1.0) - 1.266_066).abs() < 1e-6);
        assert!((bessel_i0(5.0) / 27.239_872 - 1.0).abs() < 1e-4);
        // Past 12 the asymptote: ln I₀(20) = 17.58961 (the full series); pbrt's asymptote
        // gives 17.58632.
        assert!((log_bessel_i0(20.0) - 17.589_61).abs() < 5e-3);
    }

    #[test]
    fn mp_integrates_to_one_over_theta_i() {
        // ∫ M_p(θi) cos θi dθi over [−π/2, π/2] = 1 for any θo and v (both branches; the
        // logarithmic one, with its asymptotic ln I₀, which is 0.4 % low near x = 20, to ~5·10⁻³).
        for v in [0.01f32, 0.05, 0.3, 1.0] {
            for theta_o in [-1.0f32, 0.0, 0.4, 1.3] {
                let n = 20_000;
                let mut sum = 0.0f64;
                for k in 0..n {
                    let ti = -PI / 2.0 + PI * (k as f32 + 0.5) / n as f32;
                    sum +=
                        (mp(ti.cos(), theta_o.cos(), ti.sin(), theta_o.sin(), v) * ti.cos()) as f64;
                }
                let integral = sum * (PI / n as f32) as f64;
                assert!(
                    (integral - 1.0).abs() < 6e-3,
                    "v {v} θo {theta_o}: {integral}"
                );
            }
        }
    }

    #[test]
    fn mp_is_symmetric_in_its_two_directions() {
        // M_p(θi, θo) = M_p(θo, θi): the longitudinal term is reciprocal.
        for v in [0.02f32, 0.3] {
            for (a, b) in [(0.3f32, -1.1f32), (1.2, 0.7), (-0.4, -0.2)] {
                let m1 = mp(a.cos(), b.cos(), a.sin(), b.sin(), v);
                let m2 = mp(b.cos(), a.cos(), b.sin(), a.sin(), v);
                assert!((m1 - m2).abs() <= 1e-6 * m1.abs().max(1e-30), "{m1} {m2}");
            }
        }
    }

    #[test]
    fn attenuations_sum_to_one_without_absorption() {
        // A₀ + A₁ + A₂ + A₃ = F + (1 − F)²(1 + F) + (1 − F)F² = 1 when T = 1.
        for h in [-0.9f32, 0.0, 0.5] {
            let a = ap(0.7, 1.55, h, SampledSpectrum::ONE);
            let sum = a.iter().fold(SampledSpectrum::ZERO, |s, x| s + *x);
            assert!(
                (sum - SampledSpectrum::ONE).abs().max_element() < 1e-5,
                "{sum}"
            );
        }
    }

    #[test]
    fn sigma_a_helpers_follow_pbrt() {
        let s = hair_sigma_a_from_concentration(1.3, 0.0);
        assert!((s - Rgb::new(0.5447, 0.9061, 1.781)).abs().max_element() < 1e-4);
        // Inverting the fit: with βn = 0.3 the divisor is 5.969 − 0.0645 + 0.22788 − 0.28971
        // + 0.045149 + 0.00005954 = 5.88764; ln 0.5 / 5.88764 = −0.117729, squared 0.013860.
        let sa = hair_sigma_a_from_reflectance(SampledSpectrum::splat(0.5), 0.3);
        assert!((sa.x - 0.013_860).abs() < 2e-5, "{sa}");
        assert_eq!(
            hair_sigma_a_from_reflectance(SampledSpectrum::ONE, 0.3),
            SampledSpectrum::ZERO
        );
    }

    #[test]
    fn discrete_sampling_remaps_u() {
        let w = [0.25, 0.25, 0.5, 0.0];
        assert_eq!(sample_discrete(&w, 0.1), (0, 0.4));
        assert_eq!(sample_discrete(&w, 0.75), (2, 0.5));
        assert_eq!(sample_discrete(&w, 0.999_999_9).0, 2);
    }
}
