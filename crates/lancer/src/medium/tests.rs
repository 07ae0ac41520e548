//! The medium module against closed forms: the Henyey–Greenstein density integrates to 1 and
//! its sampling matches it (chi-square), its mean cosine is g in pbrt-v4's convention, and a
//! homogeneous slab transmits exp(−σ_t·d) under delta tracking.

use super::*;
use crate::math::{Rgb, Vec2, normalize};
use crate::sampling::Pcg32;
use std::f32::consts::PI;

/// 2π ∫₋₁¹ p(μ) dμ by the midpoint rule.
fn hg_integral(g: f32) -> f64 {
    let n = 200_000;
    (0..n)
        .map(|i| {
            let mu = -1.0 + (i as f64 + 0.5) * 2.0 / n as f64;
            henyey_greenstein(mu as f32, g) as f64 * 2.0 / n as f64
        })
        .sum::<f64>()
        * 2.0
        * PI as f64
}

#[test]
fn hg_density_integrates_to_one_and_is_isotropic_at_zero() {
    for g in [-0.9, -0.3, 0.0, 0.3, 0.7, 0.95] {
        let i = hg_integral(g);
        assert!((i - 1.0).abs() < 2e-3, "g = {g}: ∫p = {i}");
    }
    // g = 0: 1/(4π) everywhere.
    assert!((henyey_greenstein(0.3, 0.0) - 1.0 / (4.0 * PI)).abs() < 1e-7);
    // Hand value: g = 0.5, cos θ = 0: (1 − ¼)/(4π·1.25^{3/2}).
    let expected = 0.75 / (4.0 * PI * 1.25f32.powf(1.5));
    assert!((henyey_greenstein(0.0, 0.5) - expected).abs() < 1e-7);
}

/// The chi-square statistic of `n` sampled cosines μ = wo·wi in `bins` equal bins against the
/// expected counts 2π∫p dμ per bin.
fn hg_chi_square(g: f32, wo: Vec3, n: usize, bins: usize) -> f64 {
    let phase = HgPhaseFunction { g };
    let mut rng = Pcg32::new(11, g.to_bits() as u64);
    let mut counts = vec![0usize; bins];
    for _ in 0..n {
        let u = Vec2::new(rng.uniform(), rng.uniform());
        let s = phase.sample(wo, u).expect("HG always samples");
        assert!((s.wi.length() - 1.0).abs() < 1e-4);
        // The sample's value and density agree with the evaluation.
        let p = phase.p(wo, s.wi);
        assert!((s.pdf - p).abs() <= 2e-3 * p.max(1.0), "{} vs {p}", s.pdf);
        let mu = wo.dot(s.wi).clamp(-1.0, 1.0);
        let b = (((mu + 1.0) * 0.5 * bins as f32) as usize).min(bins - 1);
        counts[b] += 1;
    }
    let sub = 64;
    (0..bins)
        .map(|b| {
            let mut prob = 0.0f64;
            for k in 0..sub {
                let mu = -1.0 + 2.0 * (b as f64 + (k as f64 + 0.5) / sub as f64) / bins as f64;
                prob += henyey_greenstein(mu as f32, g) as f64 * 2.0 / (bins * sub) as f64;
            }
            let expected = prob * 2.0 * PI as f64 * n as f64;
            let d = counts[b] as f64 - expected;
            d * d / expected
        })
        .sum()
}

#[test]
fn hg_sampling_matches_its_density() {
    let wo = normalize(Vec3::new(0.3, -0.5, 0.8));
    // 20 bins: 19 degrees of freedom; the 99.9 % quantile of χ²₁₉ is 43.8.
    for g in [-0.7, 0.0, 0.2, 0.8] {
        let chi2 = hg_chi_square(g, wo, 200_000, 20);
        assert!(chi2 < 43.8, "g = {g}: χ² = {chi2}");
    }
}

#[test]
fn hg_mean_cosine_is_g_forward_along_the_ray() {
    // wo points back along the ray; forward scattering continues along d = −wo.
    let d = normalize(Vec3::new(1.0, 2.0, -0.5));
    let wo = -d;
    for g in [-0.5, 0.3, 0.8] {
        let phase = HgPhaseFunction { g };
        let mut rng = Pcg32::new(3, 5);
        let n = 200_000;
        let mean: f64 = (0..n)
            .map(|_| {
                let s = phase
                    .sample(wo, Vec2::new(rng.uniform(), rng.uniform()))
                    .unwrap();
                d.dot(s.wi) as f64
            })
            .sum::<f64>()
            / n as f64;
        assert!((mean - g as f64).abs() < 0.01, "g = {g}: mean cos {mean}");
    }
}

#[test]
fn majorant_transmittance_is_beer_lambert() {
    let t = majorant_transmittance(SampledSpectrum::new(0.0, 0.5, 1.0, 2.0), 2.0);
    let e = SampledSpectrum::new(1.0, (-1.0f32).exp(), (-2.0f32).exp(), (-4.0f32).exp());
    assert!((t - e).abs().max_element() < 1e-6);
    // An infinite distance through nothing transmits everything, through anything nothing.
    let t = majorant_transmittance(SampledSpectrum::new(0.0, 1.0, 0.0, 1.0), f32::INFINITY);
    assert_eq!(t, SampledSpectrum::new(1.0, 0.0, 1.0, 0.0));
}

/// The mean of `n` ratio-tracking estimates of the transmittance along the ray `(o, d, t_max)`
/// through `medium` with hero lane `hero`, as the integrator's shadow rays estimate it: each
/// tentative collision multiplies by T_maj·σ_n/(T_maj[h]·σ_maj[h]), the last stretch by
/// T_maj/T_maj[h].
fn ratio_tracked(
    medium: &Medium,
    (o, d, t_max): (Vec3, Vec3, f32),
    hero: usize,
    n: usize,
    rng: &mut Pcg32,
) -> SampledSpectrum {
    let mut sum = SampledSpectrum::ZERO;
    for _ in 0..n {
        let mut t_ray = SampledSpectrum::ONE;
        let u = rng.uniform();
        let t_maj = sample_t_maj(
            medium,
            o,
            d,
            t_max,
            u,
            rng,
            None,
            hero,
            |_, mp, sigma_maj, t_maj, _| {
                let sigma_n = (sigma_maj - mp.sigma_a - mp.sigma_s).max(SampledSpectrum::ZERO);
                t_ray *= t_maj * sigma_n / (t_maj[hero] * sigma_maj[hero]);
                t_ray != SampledSpectrum::ZERO
            },
        );
        sum += t_ray * t_maj / t_maj[hero];
    }
    sum / n as f32
}

/// A slab of thickness `d` of a homogeneous medium, crossed along its normal: the estimator
/// of the integrator's shadow rays (ratio tracking; σ_n = 0 here, so a path that collides
/// carries nothing, one that crosses carries T_maj/T_maj[hero]) averages to exp(−σ_t·d) in
/// every lane.
#[test]
fn homogeneous_slab_transmits_exp_minus_sigma_t_d() {
    let sigma_a = Rgb::new(0.2, 0.5, 1.0);
    let sigma_s = Rgb::new(0.3, 0.1, 0.5);
    let medium = Medium::from_desc(&MediumDesc::Homogeneous(HomogeneousDesc {
        sigma_a,
        sigma_s,
        scale: 2.0,
        le: Rgb::ZERO,
        le_scale: 1.0,
        g: 0.0,
    }));
    let d = 1.5;
    let sigma_t = crate::math::rgb_lanes((sigma_a + sigma_s) * 2.0);
    let expected = majorant_transmittance(sigma_t, d);
    // The closed form the integrator uses for homogeneous stretches is the same number.
    let closed = medium
        .uniform_transmittance(Vec3::new(0.0, 0.0, 3.0), 0.5, None)
        .unwrap();
    assert!((closed - expected).abs().max_element() < 1e-6);
    assert!((expected[0] - (-(0.5f32 * 2.0 * 1.5)).exp()).abs() < 1e-6);
    let n = 400_000;
    for hero in [0usize, 2] {
        let mut rng = Pcg32::new(1, hero as u64);
        // A direction of length 3: t_max = 0.5 in its units is distance 1.5.
        let mean = ratio_tracked(
            &medium,
            (Vec3::ZERO, Vec3::new(0.0, 0.0, 3.0), 0.5),
            hero,
            n,
            &mut rng,
        );
        for lane in 0..4 {
            // Binomial-like error of a rare-event weight: loose but meaningful.
            let tol = 4.0 * (expected[lane] * expected[hero]).sqrt()
                / (expected[hero] * (n as f32).sqrt())
                + 1e-3;
            assert!(
                (mean[lane] - expected[lane]).abs() < tol.max(0.01 * expected[lane]),
                "hero {hero}, lane {lane}: {} vs exp(−σd) = {}",
                mean[lane],
                expected[lane]
            );
        }
    }
}

#[test]
fn medium_interface_sides_follow_the_normal() {
    let mi = MediumInterface {
        inside: Some(1),
        outside: None,
    };
    assert!(mi.is_transition());
    let n = Vec3::Z;
    assert_eq!(mi.towards(n, Vec3::new(0.0, 0.3, 1.0)), None);
    assert_eq!(mi.towards(n, Vec3::new(0.0, 0.3, -1.0)), Some(1));
    assert!(
        !MediumInterface {
            inside: Some(2),
            outside: Some(2)
        }
        .is_transition()
    );
}

/// A `uniformgrid` whose density varies along x (two samples, a and b, cell-centred and
/// falling to zero half a cell beyond them, as pbrt-v4's SampledGrid): crossed along x at the
/// box's centre, d(x) rises from a/2 to a over [0, ¼], goes linearly to b over [¼, ¾] and
/// falls to b/2 at 1, so its optical depth is σ_t·∫d(x)dx = σ_t·(0.1875a + 0.25(a + b) +
/// 0.1875b) = σ_t·0.4375(a + b). Delta tracking through the majorant grid (DDA, null collisions where
/// the density is below its cell's maximum) must average to exp of minus that in every lane.
#[test]
fn grid_transmittance_matches_the_integral_of_its_density() {
    use crate::math::{Bounds3, Transform};
    use grid::SampledGrid;
    use uniform_grid::UniformGridDesc;
    let (a, b) = (0.2f32, 1.0f32);
    let sigma_a = Rgb::new(0.5, 1.0, 2.0);
    let sigma_s = Rgb::splat(0.5);
    let medium = Medium::from_desc(&MediumDesc::Grid(Box::new(GridMediumDesc::Uniform(
        UniformGridDesc {
            medium_to_render: Transform::IDENTITY,
            bounds: Bounds3::new(Vec3::ZERO, Vec3::ONE),
            sigma_a,
            sigma_s,
            scale: 1.0,
            g: 0.0,
            density: SampledGrid::new(vec![a, b], 2, 1, 1).unwrap(),
            temperature: None,
            temperature_scale: 1.0,
            temperature_offset: 0.0,
            le: Rgb::ZERO,
            le_scale: SampledGrid::new(vec![1.0], 1, 1, 1).unwrap(),
        },
    ))));
    // The density at a few points, by the formula above (σ_a's red lane is 0.5·density).
    for (x, want) in [
        (0.0, a / 2.0),
        (0.25, a),
        (0.5, (a + b) / 2.0),
        (0.75, b),
        (1.0, b / 2.0),
    ] {
        let d = medium.sample_point(Vec3::new(x, 0.5, 0.5), None).sigma_a[0] / 0.5;
        assert!((d - want).abs() < 1e-5, "d({x}) = {d}, not {want}");
    }
    let sigma_t = crate::math::rgb_lanes(sigma_a + sigma_s);
    let expected = majorant_transmittance(sigma_t, 0.4375 * (a + b));
    let mut rng = Pcg32::new(7, 3);
    let mean = ratio_tracked(
        &medium,
        (Vec3::new(-1.0, 0.5, 0.5), Vec3::X, 3.0),
        1,
        200_000,
        &mut rng,
    );
    for lane in 0..4 {
        assert!(
            (mean[lane] - expected[lane]).abs() < 0.02 * expected[lane] + 2e-3,
            "lane {lane}: {} vs exp(−σ_t·∫d) = {}",
            mean[lane],
            expected[lane]
        );
    }
}
