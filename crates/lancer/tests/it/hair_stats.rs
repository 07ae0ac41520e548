//! Statistical checks of the hair BxDF (pbrt-v4's `HairBxDF`), after pbrt-v4's own hair tests:
//!
//! - White furnace: without absorption, ∫ f |cos θi| dωi = 1 for every roughness (estimated
//!   with uniform sphere directions, blind to the lobes).
//! - Sampling weights: without absorption the sampling density is proportional to
//!   f |cos θi|, so every sample's weight f |cos θi| / pdf is 1.
//! - Sampled values and densities equal `f` and `pdf`; `pdf` integrates to 1; chi-square fit
//!   of the sampled directions against `pdf` (with absorption and scale tilt).
//!
//! The model is not reciprocal at a fixed offset h (its attenuation and azimuthal terms follow
//! the outgoing direction only; pbrt-v4's reciprocity test of it is compiled out), so only the
//! longitudinal term's symmetry is checked (a unit test beside the code).

use lancer::material::{BxDF, HairBxdf, TransportMode, hair_sigma_a_from_concentration};
use lancer::math::{SampledSpectrum, Vec2, Vec3, rgb_lanes};
use lancer::sampling::{Pcg32, sample_uniform_sphere, uniform_sphere_pdf};

use crate::common::chi2::*;

const RADIANCE: TransportMode = TransportMode::Radiance;

/// Chi-square tests in this file, for the Šidák correction.
const N_CHI2_TESTS: usize = 4;

fn hair(h: f32, sigma_a: SampledSpectrum, beta_m: f32, beta_n: f32, alpha: f32) -> BxDF {
    BxDF::Hair(HairBxdf::new(h, 1.55, sigma_a, beta_m, beta_n, alpha))
}

fn uniform_dir(rng: &mut Pcg32) -> Vec3 {
    sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()))
}

/// Roughnesses 0.1, 0.3, …, 0.9 (pbrt's test grid).
fn betas() -> impl Iterator<Item = f32> {
    (0..5).map(|i| 0.1 + 0.2 * i as f32)
}

#[test]
fn white_furnace_without_absorption() {
    let mut rng = Pcg32::new(17, 0);
    let wo = uniform_dir(&mut rng);
    for beta_m in betas() {
        for beta_n in betas() {
            // Blind sampling needs more samples for the narrow lobes.
            let n = if beta_m < 0.5 || beta_n < 0.5 {
                200_000
            } else {
                40_000
            };
            let mut sum = 0.0f64;
            for _ in 0..n {
                let h = (-1.0 + 2.0 * rng.uniform()).clamp(-0.999_999, 0.999_999);
                let b = hair(h, SampledSpectrum::ZERO, beta_m, beta_n, 0.0);
                let wi = uniform_dir(&mut rng);
                sum += (b.f(wo, wi, RADIANCE).x * wi.z.abs()) as f64;
            }
            let avg = sum / (n as f64 * uniform_sphere_pdf() as f64);
            assert!(
                (0.95..=1.05).contains(&avg),
                "βm {beta_m} βn {beta_n}: albedo {avg}"
            );
        }
    }
}

#[test]
fn sample_weights_are_one_without_absorption() {
    let mut rng = Pcg32::new(23, 0);
    for beta_m in betas() {
        for beta_n in betas().filter(|&b| b > 0.35) {
            for _ in 0..4_000 {
                let h = (-1.0 + 2.0 * rng.uniform()).clamp(-0.999_999, 0.999_999);
                let b = hair(h, SampledSpectrum::ZERO, beta_m, beta_n, 0.0);
                let wo = uniform_dir(&mut rng);
                let u = Vec2::new(rng.uniform(), rng.uniform());
                let Some(s) = b.sample_f(wo, rng.uniform(), u, RADIANCE) else {
                    continue;
                };
                let w = s.f * s.wi.z.abs() / s.pdf;
                assert!(
                    (w - SampledSpectrum::ONE).abs().max_element() < 0.01,
                    "βm {beta_m} βn {beta_n} h {h} wo {wo}: weight {w}"
                );
            }
        }
    }
}

/// Absorbing fibres with tilted scales, from light to dark, at several offsets.
fn absorbing_cases() -> Vec<(BxDF, &'static str)> {
    let brown = rgb_lanes(hair_sigma_a_from_concentration(1.3, 0.0));
    let blond = rgb_lanes(hair_sigma_a_from_concentration(0.3, 0.2));
    vec![
        (hair(0.3, blond, 0.3, 0.3, 2.0), "blond βm 0.3"),
        (hair(-0.7, brown, 0.5, 0.6, 2.0), "brown βm 0.5"),
        (hair(0.9, blond, 0.2, 0.8, 4.0), "blond grazing h"),
        (hair(0.0, brown, 0.7, 0.2, 0.0), "brown βn 0.2"),
    ]
}

#[test]
fn sampled_values_and_densities_match_f_and_pdf() {
    let mut rng = Pcg32::new(29, 0);
    for (b, name) in absorbing_cases() {
        for _ in 0..5_000 {
            let wo = uniform_dir(&mut rng);
            let u = Vec2::new(rng.uniform(), rng.uniform());
            let Some(s) = b.sample_f(wo, rng.uniform(), u, RADIANCE) else {
                continue;
            };
            assert!(s.f.is_finite() && s.pdf.is_finite() && s.pdf > 0.0);
            let f = b.f(wo, s.wi, RADIANCE);
            let pdf = b.pdf(wo, s.wi, RADIANCE);
            let close = |a: f32, e: f32| (a - e).abs() <= 2e-3 * a.abs().max(e.abs()) + 1e-6;
            assert!(
                (0..3).all(|i| close(s.f[i], f[i])),
                "{name}: wo {wo} wi {}: sampled f {} but f = {f}",
                s.wi,
                s.f
            );
            assert!(
                close(s.pdf, pdf),
                "{name}: sampled pdf {} but pdf = {pdf}",
                s.pdf
            );
        }
    }
}

#[test]
fn chi2_sampling_matches_pdf_which_integrates_to_one() {
    for (seed, (b, name)) in absorbing_cases().into_iter().enumerate() {
        let wo = lancer::math::normalize(Vec3::new(0.4, -0.5, 0.7));
        let n = 200_000;
        let mut rng = Pcg32::new(31 + seed as u64, 0);
        let mut obs = vec![0.0; N_BINS];
        for _ in 0..n {
            let u = Vec2::new(rng.uniform(), rng.uniform());
            if let Some(s) = b.sample_f(wo, rng.uniform(), u, RADIANCE) {
                obs[bin_of(s.wi)] += 1.0;
            }
        }
        let integral = integrate_bins(12, |wi| b.pdf(wo, wi, RADIANCE) as f64);
        let total: f64 = integral.iter().sum();
        assert!((total - 1.0).abs() < 5e-3, "{name}: ∫pdf = {total}");
        let exp: Vec<f64> = integral.iter().map(|p| p * n as f64).collect();
        let (chi2, dof) = pooled_chi2(&obs, &exp).unwrap_or_else(|e| panic!("{name}: {e}"));
        let p = chi2_survival(chi2, dof);
        println!("{name}: χ² = {chi2:.1}, {dof} dof, p = {p:.3}; ∫pdf = {total:.4}");
        assert!(
            p > sidak(N_CHI2_TESTS),
            "{name}: χ² = {chi2:.1} with {dof} dof, p = {p:.2e}"
        );
    }
}

#[test]
fn absorption_darkens_and_stays_below_one() {
    // With σₐ > 0 the albedo falls below 1, and more melanin means less albedo.
    let mut rng = Pcg32::new(37, 0);
    let wo = lancer::math::normalize(Vec3::new(0.2, 0.6, 0.3));
    let albedo = |ce: f32, rng: &mut Pcg32| {
        let sa = rgb_lanes(hair_sigma_a_from_concentration(ce, 0.0));
        let n = 40_000;
        let mut sum = SampledSpectrum::ZERO;
        for _ in 0..n {
            let h = -1.0 + 2.0 * rng.uniform();
            let b = hair(h, sa, 0.3, 0.3, 2.0);
            let u = Vec2::new(rng.uniform(), rng.uniform());
            if let Some(s) = b.sample_f(wo, rng.uniform(), u, RADIANCE) {
                sum += s.f * s.wi.z.abs() / s.pdf;
            }
        }
        sum / n as f32
    };
    let light = albedo(0.2, &mut rng);
    let dark = albedo(3.0, &mut rng);
    assert!(light.max_element() < 1.0, "{light}");
    assert!((0..3).all(|i| dark[i] < light[i]), "{dark} vs {light}");
    // Blue is absorbed most: the light hair is warm.
    assert!(light.x > light.z, "{light}");
}
