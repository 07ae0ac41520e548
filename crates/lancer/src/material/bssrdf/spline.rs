//! Catmull–Rom splines over irregular nodes (pbrt-v4's spline helpers): interpolation
//! weights, integration with a running CDF, inversion, and sampling a 2D table along its
//! second axis. Derivatives at a node are finite differences of its neighbours, scaled to the
//! segment: d₀ = w (f₁ − f₋₁)/(x₁ − x₋₁), one-sided at the ends.

/// The largest i ∈ [0, size − 2] with `pred(i)` true (`pred` true, then false), by bisection.
pub(crate) fn find_interval(size: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0usize, size);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if pred(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo.saturating_sub(1).min(size.saturating_sub(2))
}

/// The weights of the four nodes around `x` (the first at index `offset`, which may be −1
/// with a zero weight) whose weighted sum of values is the spline at x; `None` outside the
/// nodes. With t = (x − x₀)/(x₁ − x₀) the Hermite basis is h₀₀ = 2t³ − 3t² + 1,
/// h₀₁ = −2t³ + 3t², h₁₀ = t³ − 2t² + t, h₁₁ = t³ − t², the derivative terms spread over the
/// neighbours.
pub(crate) fn catmull_rom_weights(nodes: &[f32], x: f32) -> Option<(isize, [f32; 4])> {
    let n = nodes.len();
    if n < 2 || !(x >= nodes[0] && x <= nodes[n - 1]) {
        return None;
    }
    let idx = find_interval(n, |i| nodes[i] <= x);
    let (x0, x1) = (nodes[idx], nodes[idx + 1]);
    let t = (x - x0) / (x1 - x0);
    let (t2, t3) = (t * t, t * t * t);
    let mut w = [0.0, 2.0 * t3 - 3.0 * t2 + 1.0, -2.0 * t3 + 3.0 * t2, 0.0];
    if idx > 0 {
        let w0 = (t3 - 2.0 * t2 + t) * (x1 - x0) / (x1 - nodes[idx - 1]);
        w[0] = -w0;
        w[2] += w0;
    } else {
        let w0 = t3 - 2.0 * t2 + t;
        w[0] = 0.0;
        w[1] -= w0;
        w[2] += w0;
    }
    if idx + 2 < n {
        let w3 = (t3 - t2) * (x1 - x0) / (nodes[idx + 2] - x0);
        w[1] -= w3;
        w[3] = w3;
    } else {
        let w3 = t3 - t2;
        w[1] -= w3;
        w[2] += w3;
        w[3] = 0.0;
    }
    Some((idx as isize - 1, w))
}

/// The end derivatives (d₀, d₁) of segment i of the spline through (nodes, f).
fn segment_derivatives(nodes: &[f32], f: &[f32], i: usize) -> (f32, f32) {
    let (x0, x1) = (nodes[i], nodes[i + 1]);
    let (f0, f1) = (f[i], f[i + 1]);
    let width = x1 - x0;
    let d0 = if i > 0 {
        width * (f1 - f[i - 1]) / (x1 - nodes[i - 1])
    } else {
        f1 - f0
    };
    let d1 = if i + 2 < nodes.len() {
        width * (f[i + 2] - f0) / (nodes[i + 2] - x0)
    } else {
        f1 - f0
    };
    (d0, d1)
}

/// ∫ of the spline over all its nodes, writing the running integral at each node to `cdf`:
/// each segment adds w ((f₀ + f₁)/2 + (d₀ − d₁)/12).
pub(crate) fn integrate_catmull_rom(nodes: &[f32], f: &[f32], cdf: &mut [f32]) -> f32 {
    let mut sum = 0.0;
    cdf[0] = 0.0;
    for i in 0..nodes.len() - 1 {
        let (d0, d1) = segment_derivatives(nodes, f, i);
        let width = nodes[i + 1] - nodes[i];
        sum += width * ((f[i] + f[i + 1]) / 2.0 + (d0 - d1) / 12.0);
        cdf[i + 1] = sum;
    }
    sum
}

/// The root in [0, 1] of a function given with its derivative, by Newton steps kept inside a
/// shrinking bracket (bisection when a step leaves it): |x₁ − x₀| < 10⁻⁶ or |f| < 10⁻⁶.
fn newton_bisection(mut x0: f32, mut x1: f32, f: impl Fn(f32) -> (f32, f32)) -> f32 {
    const EPS: f32 = 1e-6;
    let (fx0, fx1) = (f(x0).0, f(x1).0);
    if fx0.abs() < EPS {
        return x0;
    }
    if fx1.abs() < EPS {
        return x1;
    }
    let start_negative = fx0 < 0.0;
    let mut x = x0 + (x1 - x0) * -fx0 / (fx1 - fx0);
    for _ in 0..100 {
        if !(x0 < x && x < x1) {
            x = 0.5 * (x0 + x1);
        }
        let (fx, dfx) = f(x);
        if start_negative == (fx < 0.0) {
            x0 = x;
        } else {
            x1 = x;
        }
        if x1 - x0 < EPS || fx.abs() < EPS {
            return x;
        }
        x -= fx / dfx;
    }
    x
}

/// The x at which the (monotone) spline through (nodes, f) takes the value u, clamped to the
/// nodes' range.
pub(crate) fn invert_catmull_rom(nodes: &[f32], f: &[f32], u: f32) -> f32 {
    let n = nodes.len();
    if u.is_nan() || u <= f[0] {
        return nodes[0];
    } else if u >= f[n - 1] {
        return nodes[n - 1];
    }
    let i = find_interval(n, |i| f[i] <= u);
    let (x0, x1) = (nodes[i], nodes[i + 1]);
    let (f0, f1) = (f[i], f[i + 1]);
    let (d0, d1) = segment_derivatives(nodes, f, i);
    let t = newton_bisection(0.0, 1.0, |t| {
        let (t2, t3) = (t * t, t * t * t);
        let fhat = (2.0 * t3 - 3.0 * t2 + 1.0) * f0
            + (-2.0 * t3 + 3.0 * t2) * f1
            + (t3 - 2.0 * t2 + t) * d0
            + (t3 - t2) * d1;
        let dfhat = (6.0 * t2 - 6.0 * t) * f0
            + (-6.0 * t2 + 6.0 * t) * f1
            + (3.0 * t2 - 4.0 * t + 1.0) * d0
            + (3.0 * t2 - 2.0 * t) * d1;
        (fhat - u, dfhat)
    });
    x0 + t * (x1 - x0)
}

/// Samples x along `nodes2` from the table `values` (rows along `nodes1`, interpolated at
/// `alpha` with [`catmull_rom_weights`]) in proportion to the spline, using the rows' running
/// integrals `cdf`: u scaled to the interpolated total, the segment found by bisection, then
/// the segment's integral F(t) = f₀t + d₀t²/2 + (−(2d₀ + d₁)/3 + f₁ − f₀)t³ +
/// ((d₀ + d₁)/4 + (f₀ − f₁)/2)t⁴ inverted by Newton–bisection. 0 when alpha is outside nodes1.
pub(crate) fn sample_catmull_rom_2d(
    nodes1: &[f32],
    nodes2: &[f32],
    values: &[f32],
    cdf: &[f32],
    alpha: f32,
    u: f32,
) -> f32 {
    let Some((offset, weights)) = catmull_rom_weights(nodes1, alpha) else {
        return 0.0;
    };
    let n2 = nodes2.len();
    let interpolate = |array: &[f32], idx: usize| {
        let mut v = 0.0;
        for (i, &w) in weights.iter().enumerate() {
            if w != 0.0 {
                v += array[(offset + i as isize) as usize * n2 + idx] * w;
            }
        }
        v
    };
    let maximum = interpolate(cdf, n2 - 1);
    let u = u * maximum;
    let idx = find_interval(n2, |i| interpolate(cdf, i) <= u);
    let (f0, f1) = (interpolate(values, idx), interpolate(values, idx + 1));
    let (x0, x1) = (nodes2[idx], nodes2[idx + 1]);
    let width = x1 - x0;
    let d0 = if idx > 0 {
        width * (f1 - interpolate(values, idx - 1)) / (x1 - nodes2[idx - 1])
    } else {
        f1 - f0
    };
    let d1 = if idx + 2 < n2 {
        width * (interpolate(values, idx + 2) - f0) / (nodes2[idx + 2] - x0)
    } else {
        f1 - f0
    };
    let u = (u - interpolate(cdf, idx)) / width;
    let t = newton_bisection(0.0, 1.0, |t| {
        let big_f = t
            * (f0
                + t * (0.5 * d0
                    + t * ((1.0 / 3.0) * (-2.0 * d0 - d1) + f1 - f0
                        + t * (0.25 * (d0 + d1) + 0.5 * (f0 - f1)))));
        let small_f = f0
            + t * (d0 + t * (-2.0 * d0 - d1 + 3.0 * (f1 - f0) + t * (d0 + d1 + 2.0 * (f0 - f1))));
        (big_f - u, small_f)
    });
    x0 + width * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_reproduce_a_cubic_inside_and_a_line_at_the_ends() {
        // Catmull–Rom with finite-difference slopes is exact for quadratics on uniform nodes.
        let nodes: Vec<f32> = (0..6).map(|i| i as f32).collect();
        let f: Vec<f32> = nodes.iter().map(|x| x * x).collect();
        let (off, w) = catmull_rom_weights(&nodes, 2.5).unwrap();
        let v: f32 = (0..4).map(|i| w[i] * f[(off + i as isize) as usize]).sum();
        assert!((v - 6.25).abs() < 1e-5, "{v}");
        assert!(catmull_rom_weights(&nodes, 5.5).is_none());
        assert!(catmull_rom_weights(&nodes, -0.1).is_none());
        // The weights always sum to 1.
        let (_, w) = catmull_rom_weights(&nodes, 0.3).unwrap();
        assert!((w.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn integration_inversion_and_sampling_agree() {
        // f(x) = x² on [0, 3]: ∫ = 9 (the spline's slopes at the ends are one-sided, so a
        // little off), and inverting x ↦ x² finds √u.
        let nodes: Vec<f32> = (0..=30).map(|i| i as f32 * 0.1).collect();
        let f: Vec<f32> = nodes.iter().map(|x| x * x).collect();
        let mut cdf = vec![0.0; nodes.len()];
        let total = integrate_catmull_rom(&nodes, &f, &mut cdf);
        assert!((total - 9.0).abs() < 2e-3, "{total}");
        let x = invert_catmull_rom(&nodes, &f, 2.0);
        assert!((x - 2f32.sqrt()).abs() < 1e-4, "{x}");
        assert_eq!(invert_catmull_rom(&nodes, &f, -1.0), 0.0);
        assert_eq!(invert_catmull_rom(&nodes, &f, 100.0), 3.0);
        // Sampling x ∝ x² on [0, 3] (two identical rows): the CDF is x³/27, so u = 1/8 gives
        // x = 1.5.
        let values = [f.clone(), f.clone()].concat();
        let cdfs = [cdf.clone(), cdf.clone()].concat();
        let x = sample_catmull_rom_2d(&[0.0, 1.0], &nodes, &values, &cdfs, 0.5, 0.125);
        assert!((x - 1.5).abs() < 2e-3, "{x}");
    }
}
