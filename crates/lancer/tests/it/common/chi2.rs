//! Chi-square goodness-of-fit machinery shared by the statistical tests (as Mitsuba's `chi2`
//! test does it): directions binned in (cos θ, φ) over the sphere, bin integrals of a density
//! by quadrature, Pearson's statistic with low-expectation cells pooled, and its p-value.

#![allow(dead_code)]

use lancer::math::Vec3;
use std::f64::consts::PI;

// ---------------------------------------------------------------------------------------------
// The chi-square distribution.

/// ln Γ(x) for x > 0 by Lanczos' approximation (g = 7, 9 terms; relative error ~1e-15).
pub fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1 − x) = π / sin(πx).
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    for (i, &c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    let t = x + 7.5;
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised upper incomplete gamma function Q(a, x) = Γ(a, x)/Γ(a): by its power series
/// (through P = 1 − Q) when x < a + 1, else by its continued fraction (modified Lentz).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        // P(a, x) = e^(−x) x^a / Γ(a) · Σ xⁿ / (a (a + 1) … (a + n)).
        let (mut ap, mut term, mut sum) = (a, 1.0 / a, 1.0 / a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        // Q(a, x) = e^(−x) x^a / Γ(a) · 1/(x + 1 − a − 1·(1 − a)/(x + 3 − a − 2·(2 − a)/…)).
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        log_prefactor.exp() * h
    }
}

/// P(X² ≥ x) for a chi-square variable with `dof` degrees of freedom: Q(dof/2, x/2).
pub fn chi2_survival(x: f64, dof: usize) -> f64 {
    gamma_q(dof as f64 / 2.0, x / 2.0)
}

#[test]
fn chi_square_tail_matches_tables() {
    // Critical values from standard tables.
    for (x, dof, p) in [
        (3.841_459, 1, 0.05),
        (6.634_897, 1, 0.01),
        (23.209_25, 10, 0.01),
        (18.307_04, 10, 0.05),
        (135.806_7, 100, 0.01),
        (124.342_1, 100, 0.05),
    ] {
        let q = chi2_survival(x, dof);
        assert!(
            (q - p).abs() < 1e-5 * p.max(0.01),
            "χ²({dof}) tail at {x}: {q} ≠ {p}"
        );
    }
    // Two degrees of freedom: an exponential, Q = e^(−x/2).
    for x in [0.1, 1.0, 5.0, 40.0] {
        let q = chi2_survival(x, 2);
        assert!((q / (-x / 2.0f64).exp() - 1.0).abs() < 1e-10);
    }
    // Γ(5) = 24, Γ(1/2) = √π.
    assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Binning the sphere and integrating over bins.

/// Bins in cos θ over [−1, 1] (equal solid angle) and in φ over [0, 2π).
pub const N_COS: usize = 10;
pub const N_PHI: usize = 20;
pub const N_BINS: usize = N_COS * N_PHI;

/// Family-wise significance level.
pub const ALPHA: f64 = 0.01;

pub fn bin_of(w: Vec3) -> usize {
    let c = ((w.z as f64 + 1.0) / 2.0 * N_COS as f64).floor() as isize;
    let mut phi = (w.y as f64).atan2(w.x as f64);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let p = (phi / (2.0 * PI) * N_PHI as f64).floor() as isize;
    let c = c.clamp(0, N_COS as isize - 1) as usize;
    let p = p.clamp(0, N_PHI as isize - 1) as usize;
    c * N_PHI + p
}

pub fn dir(cos_theta: f64, phi: f64) -> Vec3 {
    let s = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(
        (s * phi.cos()) as f32,
        (s * phi.sin()) as f32,
        cos_theta as f32,
    )
}

/// ∫ g over each bin by composite 3-point Gauss–Legendre quadrature with `sub` panels per bin
/// and dimension (no node on a bin edge, so nothing is evaluated exactly on the horizon).
/// dω = d(cos θ) dφ, so no Jacobian is needed.
pub fn integrate_bins(sub: usize, g: impl Fn(Vec3) -> f64) -> Vec<f64> {
    const X: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let nodes = |lo: f64, hi: f64| {
        let h = (hi - lo) / sub as f64;
        let mut v = Vec::with_capacity(3 * sub);
        for k in 0..sub {
            let mid = lo + (k as f64 + 0.5) * h;
            for q in 0..3 {
                v.push((mid + X[q] * h / 2.0, W[q] * h / 2.0));
            }
        }
        v
    };
    let mut out = vec![0.0; N_BINS];
    for i in 0..N_COS {
        let cs = nodes(
            -1.0 + 2.0 * i as f64 / N_COS as f64,
            -1.0 + 2.0 * (i + 1) as f64 / N_COS as f64,
        );
        for j in 0..N_PHI {
            let ps = nodes(
                2.0 * PI * j as f64 / N_PHI as f64,
                2.0 * PI * (j + 1) as f64 / N_PHI as f64,
            );
            let mut s = 0.0;
            for &(c, wc) in &cs {
                for &(p, wp) in &ps {
                    s += wc * wp * g(dir(c, p));
                }
            }
            out[i * N_PHI + j] = s;
        }
    }
    out
}

/// Mitsuba's pooled chi-square statistic of observed against expected counts: cells are taken
/// in increasing order of expectation and those expecting fewer than 5 are pooled (together with
/// following ones until the pool expects 5). Returns (statistic, degrees of freedom), or an
/// error if a cell that cannot receive samples did.
pub fn pooled_chi2(obs: &[f64], exp: &[f64]) -> Result<(f64, usize), String> {
    let mut idx: Vec<usize> = (0..obs.len()).collect();
    idx.sort_by(|&a, &b| exp[a].total_cmp(&exp[b]));
    let (mut pool_obs, mut pool_exp) = (0.0, 0.0);
    let (mut chi2, mut cells) = (0.0, 0usize);
    for &i in &idx {
        if exp[i] == 0.0 {
            if obs[i] > 0.0 {
                return Err(format!(
                    "{} samples in bin {i}, whose density is zero",
                    obs[i]
                ));
            }
            continue;
        }
        if exp[i] < 5.0 || (pool_exp > 0.0 && pool_exp < 5.0) {
            pool_obs += obs[i];
            pool_exp += exp[i];
        } else {
            chi2 += (obs[i] - exp[i]).powi(2) / exp[i];
            cells += 1;
        }
    }
    if pool_exp > 0.0 {
        chi2 += (pool_obs - pool_exp).powi(2) / pool_exp;
        cells += 1;
    }
    Ok((chi2, cells.saturating_sub(1).max(1)))
}

/// The per-test significance that keeps the family-wise one at [`ALPHA`] over `tests`
/// tests (Šidák).
pub fn sidak(tests: usize) -> f64 {
    1.0 - (1.0 - ALPHA).powf(1.0 / tests as f64)
}
