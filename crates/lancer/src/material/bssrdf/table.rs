//! The photon-beam-diffusion profile table of a subsurface material (pbrt-v4's
//! `ComputeBeamDiffusionBSSRDF`): for 100 single-scattering albedos ρ and 64 optical radii r
//! (σt = 1), the radial profile 2πr·(S_ss(r) + S_ms(r)) of a semi-infinite medium of index η
//! with Henyey–Greenstein asymmetry g, its integral ρ_eff (the effective albedo) and running
//! CDF. Tables depend on (g, η) only and are shared between materials.

use super::spline::integrate_catmull_rom;
use crate::material::fresnel::fresnel_dielectric;
use crate::sampling::{henyey_greenstein, sample_exponential};
use std::f32::consts::PI;
use std::sync::{Arc, Mutex};

/// Albedo samples.
const N_RHO: usize = 100;
/// Radius samples.
const N_RADIUS: usize = 64;
/// Depth samples per profile value (pbrt-v4's 100).
const N_DEPTH: usize = 100;

/// The tabulated profile for one (g, η).
#[derive(Clone, PartialEq)]
pub struct BssrdfTable {
    /// Asymmetry the table was made for.
    pub g: f32,
    /// Index of refraction it was made for.
    pub eta: f32,
    /// Albedos ρᵢ = (1 − e^(−8i/99)) / (1 − e^(−8)), denser near 1.
    pub rho_samples: Vec<f32>,
    /// Optical radii: 0, 2.5·10⁻³, then × 1.2 each.
    pub radius_samples: Vec<f32>,
    /// 2πr·S(r) per (ρ, r), rows along ρ.
    pub profile: Vec<f32>,
    /// ∫ profile dr per ρ.
    pub rho_eff: Vec<f32>,
    /// Running integrals of each row.
    pub profile_cdf: Vec<f32>,
}

impl std::fmt::Debug for BssrdfTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "BssrdfTable {{ g: {}, eta: {} }}", self.g, self.eta)
    }
}

/// First Fresnel moment M₁(η) = ∫₀¹ F(μ, 1/η) μ dμ, as pbrt-v4's polynomial fits (one for
/// η < 1 and one for η ≥ 1).
pub fn fresnel_moment1(eta: f32) -> f32 {
    let (e2, e3, e4, e5) = (eta * eta, eta.powi(3), eta.powi(4), eta.powi(5));
    if eta < 1.0 {
        0.45966 - 1.73965 * eta + 3.37668 * e2 - 3.904945 * e3 + 2.49277 * e4 - 0.68441 * e5
    } else {
        -4.61686 + 11.1136 * eta - 10.4646 * e2 + 5.11455 * e3 - 1.27198 * e4 + 0.12746 * e5
    }
}

/// Second Fresnel moment M₂(η) = ∫₀¹ F(μ, 1/η) μ² dμ, pbrt-v4's fits.
pub fn fresnel_moment2(eta: f32) -> f32 {
    let (e2, e3, e4, e5) = (eta * eta, eta.powi(3), eta.powi(4), eta.powi(5));
    if eta < 1.0 {
        0.27614 - 0.87350 * eta + 1.12077 * e2 - 0.65095 * e3 + 0.07883 * e4 + 0.04860 * e5
    } else {
        let r = 1.0 / eta;
        -547.033 + 45.3087 * r * r * r - 218.725 * r * r + 458.843 * r + 404.557 * eta
            - 189.519 * e2
            + 54.9327 * e3
            - 9.00603 * e4
            + 0.63942 * e5
    }
}

/// Multiple scattering by photon beam diffusion: real point sources at depths z_r sampled
/// along the refracted beam (exponential in σ′t), each with its virtual source at
/// z_v = −z_r + 2z_e (z_e = −2D(1 + 3M₂)/(1 − 2M₁)), Grosjean's D = (2σa + σ′s)/(3σ′t²),
/// σ_tr = √(σa/D); the exitance φ(r)·c_φ + E(r)·c_E with c_φ = (1 − 2M₁)/4,
/// c_E = (1 − 3M₂)/2, weighted by ρ′² and κ = 1 − e^(−2σ′t(d_r + z_r)).
fn beam_diffusion_ms(sigma_s: f32, sigma_a: f32, g: f32, eta: f32, r: f32) -> f32 {
    let sigmap_s = sigma_s * (1.0 - g);
    let sigmap_t = sigma_a + sigmap_s;
    let rhop = sigmap_s / sigmap_t;
    let d_g = (2.0 * sigma_a + sigmap_s) / (3.0 * sigmap_t * sigmap_t);
    let sigma_tr = (sigma_a / d_g).max(0.0).sqrt();
    let (fm1, fm2) = (fresnel_moment1(eta), fresnel_moment2(eta));
    let ze = -2.0 * d_g * (1.0 + 3.0 * fm2) / (1.0 - 2.0 * fm1);
    let c_phi = 0.25 * (1.0 - 2.0 * fm1);
    let c_e = 0.5 * (1.0 - 3.0 * fm2);
    let inv_4pi = 0.25 / PI;
    let mut ed = 0.0;
    for i in 0..N_DEPTH {
        let zr = sample_exponential((i as f32 + 0.5) / N_DEPTH as f32, sigmap_t);
        let zv = -zr + 2.0 * ze;
        let dr = (r * r + zr * zr).sqrt();
        let dv = (r * r + zv * zv).sqrt();
        let (er, ev) = ((-sigma_tr * dr).exp(), (-sigma_tr * dv).exp());
        let phi_d = inv_4pi / d_g * (er / dr - ev / dv);
        let ed_n = inv_4pi
            * (zr * (1.0 + sigma_tr * dr) * er / dr.powi(3)
                - zv * (1.0 + sigma_tr * dv) * ev / dv.powi(3));
        let e = phi_d * c_phi + ed_n * c_e;
        let kappa = 1.0 - (-2.0 * sigmap_t * (dr + zr)).exp();
        ed += kappa * rhop * rhop * e;
    }
    ed / N_DEPTH as f32
}

/// Single scattering along the refracted beam, from depths past t_crit = r√(η² − 1):
/// ρ e^(−σt(d + t_crit)) / d² · p_HG(cos θo) · (1 − F(−cos θo)) · |cos θo|, d = √(r² + t²).
fn beam_diffusion_ss(sigma_s: f32, sigma_a: f32, g: f32, eta: f32, r: f32) -> f32 {
    let sigma_t = sigma_a + sigma_s;
    let rho = sigma_s / sigma_t;
    let t_crit = r * (eta * eta - 1.0).max(0.0).sqrt();
    let mut ess = 0.0;
    for i in 0..N_DEPTH {
        let ti = t_crit + sample_exponential((i as f32 + 0.5) / N_DEPTH as f32, sigma_t);
        let d = (r * r + ti * ti).sqrt();
        let cos_o = ti / d;
        ess += rho * (-sigma_t * (d + t_crit)).exp() / (d * d)
            * henyey_greenstein(cos_o, g)
            * (1.0 - fresnel_dielectric(-cos_o, eta))
            * cos_o.abs();
    }
    ess / N_DEPTH as f32
}

impl BssrdfTable {
    /// Computes the table for asymmetry `g` and index `eta` (about 1.3 M exponentials).
    pub fn compute(g: f32, eta: f32) -> BssrdfTable {
        let mut radius_samples = vec![0.0f32; N_RADIUS];
        radius_samples[1] = 2.5e-3;
        for i in 2..N_RADIUS {
            radius_samples[i] = radius_samples[i - 1] * 1.2;
        }
        let rho_samples: Vec<f32> = (0..N_RHO)
            .map(|i| (1.0 - (-8.0 * i as f32 / (N_RHO - 1) as f32).exp()) / (1.0 - (-8.0f32).exp()))
            .collect();
        let mut profile = vec![0.0f32; N_RHO * N_RADIUS];
        let mut profile_cdf = vec![0.0f32; N_RHO * N_RADIUS];
        let mut rho_eff = vec![0.0f32; N_RHO];
        for (i, &rho) in rho_samples.iter().enumerate() {
            let row = &mut profile[i * N_RADIUS..(i + 1) * N_RADIUS];
            for (j, &r) in radius_samples.iter().enumerate() {
                row[j] = 2.0
                    * PI
                    * r
                    * (beam_diffusion_ss(rho, 1.0 - rho, g, eta, r)
                        + beam_diffusion_ms(rho, 1.0 - rho, g, eta, r));
            }
            rho_eff[i] = integrate_catmull_rom(
                &radius_samples,
                row,
                &mut profile_cdf[i * N_RADIUS..(i + 1) * N_RADIUS],
            );
        }
        BssrdfTable {
            g,
            eta,
            rho_samples,
            radius_samples,
            profile,
            rho_eff,
            profile_cdf,
        }
    }

    /// The shared table for (g, η), computed on first use.
    pub fn shared(g: f32, eta: f32) -> Arc<BssrdfTable> {
        static TABLES: Mutex<Vec<Arc<BssrdfTable>>> = Mutex::new(Vec::new());
        let mut tables = TABLES.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = tables
            .iter()
            .find(|t| t.g.to_bits() == g.to_bits() && t.eta.to_bits() == eta.to_bits())
        {
            return t.clone();
        }
        let t = Arc::new(BssrdfTable::compute(g, eta));
        tables.push(t.clone());
        t
    }

    /// The profile value at (ρ index, radius index).
    #[inline]
    pub(crate) fn eval_profile(&self, rho: usize, radius: usize) -> f32 {
        self.profile[rho * self.radius_samples.len() + radius]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_moments_match_their_integrals() {
        // Mₖ(η) = ∫₀¹ F(μ, 1/η) μᵏ dμ: F for light meeting the boundary from inside a medium
        // of index η (relative index 1/η), e.g. M₁(1.33) ≈ 0.2360, M₂(1.33) ≈ 0.1094.
        for eta in [1.33f32, 1.5] {
            let n = 100_000;
            let (mut m1, mut m2) = (0.0f64, 0.0f64);
            for k in 0..n {
                let mu = (k as f32 + 0.5) / n as f32;
                let f = fresnel_dielectric(mu, 1.0 / eta) as f64;
                m1 += f * mu as f64;
                m2 += f * (mu * mu) as f64;
            }
            let (m1, m2) = (m1 / n as f64, m2 / n as f64);
            assert!(
                (fresnel_moment1(eta) as f64 - m1).abs() < 3e-3,
                "{eta}: {m1}"
            );
            assert!(
                (fresnel_moment2(eta) as f64 - m2).abs() < 3e-3,
                "{eta}: {m2}"
            );
        }
    }

    #[test]
    fn effective_albedo_grows_with_albedo_up_to_about_one() {
        let t = BssrdfTable::compute(0.0, 1.33);
        assert_eq!(t.rho_samples[0], 0.0);
        assert!((t.rho_samples[N_RHO - 1] - 1.0).abs() < 1e-6);
        assert!((t.radius_samples[2] - 3e-3).abs() < 1e-9);
        assert_eq!(t.rho_eff[0], 0.0);
        for w in t.rho_eff.windows(2) {
            assert!(w[1] >= w[0], "{w:?}");
        }
        let top = t.rho_eff[N_RHO - 1];
        // A non-absorbing medium returns (nearly) everything: the diffusion approximation
        // overshoots by about 2 % at ρ = 1.
        assert!((top - 1.0).abs() < 0.03, "ρ_eff(1) = {top}");
        assert_eq!(*t.profile_cdf.last().unwrap(), top);
    }
}
