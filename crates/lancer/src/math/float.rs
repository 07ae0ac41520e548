//! Scalar constants and floating-point helpers: rounding-error bounds, next floats, safe
//! roots and inverse trigonometry, a stable quadratic solver (a leaf module).

/// π.
pub const PI: f32 = std::f32::consts::PI;
/// 1/π.
pub const INV_PI: f32 = std::f32::consts::FRAC_1_PI;
/// 1/(2π).
pub const INV_2PI: f32 = 0.5 * std::f32::consts::FRAC_1_PI;
/// 1/(4π).
pub const INV_4PI: f32 = 0.25 * std::f32::consts::FRAC_1_PI;

/// Unit roundoff of `f32` arithmetic: every correctly rounded operation is exact within a factor
/// (1 ± ε) with ε = 2⁻²⁴.
pub const MACHINE_EPSILON: f32 = f32::EPSILON * 0.5;

/// Bound on the accumulated relative error of `n` successive floating-point operations:
/// γₙ = nε / (1 − nε) (Higham; PBRT §6.8).
#[inline]
pub fn gamma(n: i32) -> f32 {
    let ne = n as f32 * MACHINE_EPSILON;
    ne / (1.0 - ne)
}

/// The smallest `f32` strictly greater than `v` (for finite `v`).
#[inline]
pub fn next_float_up(v: f32) -> f32 {
    if v.is_infinite() && v > 0.0 {
        return v;
    }
    let v = if v == -0.0 { 0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v >= 0.0 { bits + 1 } else { bits - 1 };
    f32::from_bits(bits)
}

/// The largest `f32` strictly smaller than `v` (for finite `v`).
#[inline]
pub fn next_float_down(v: f32) -> f32 {
    if v.is_infinite() && v < 0.0 {
        return v;
    }
    let v = if v == 0.0 { -0.0 } else { v };
    let bits = v.to_bits();
    let bits = if v > 0.0 { bits - 1 } else { bits + 1 };
    f32::from_bits(bits)
}

/// Error-free `a·b − c·d` via a fused multiply-add (Kahan's algorithm): used where cancellation
/// would otherwise destroy the result (cross products, discriminants).
#[inline]
pub fn difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let err = (-c).mul_add(d, cd);
    let dop = a.mul_add(b, -cd);
    dop + err
}

/// Linear interpolation `(1 − t)·a + t·b`.
#[inline]
pub fn lerp(t: f32, a: f32, b: f32) -> f32 {
    (1.0 - t) * a + t * b
}

/// `x²`.
#[inline]
pub fn sqr(x: f32) -> f32 {
    x * x
}

/// `sqrt(max(0, x))`: a square root that rounding cannot push into NaN.
#[inline]
pub fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// `asin` clamped to its domain.
#[inline]
pub fn safe_asin(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).asin()
}

/// `acos` clamped to its domain.
#[inline]
pub fn safe_acos(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).acos()
}

/// Smoothstep: 0 below `a`, 1 above `b`, the cubic 3t² − 2t³ between.
#[inline]
pub fn smooth_step(x: f32, a: f32, b: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The quadratic a·t² + b·t + c = 0 solved without catastrophic cancellation: returns its real
/// roots (t0 ≤ t1), or `None` when the discriminant is negative.
///
/// The textbook `(−b ± √Δ)/2a` loses all precision in the root where `b` and `√Δ` nearly cancel;
/// instead `q = −(b + sign(b)·√Δ)/2` and the roots are `q/a` and `c/q` (Numerical Recipes §5.6).
/// Computed in f64 so that the discriminant itself is accurate.
#[inline]
pub fn solve_quadratic(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    if a == 0.0 {
        if b == 0.0 {
            return None;
        }
        let t = -c / b;
        return Some((t, t));
    }
    let discrim = b * b - 4.0 * a * c;
    if discrim < 0.0 {
        return None;
    }
    let root = discrim.sqrt();
    let q = if b < 0.0 {
        -0.5 * (b - root)
    } else {
        -0.5 * (b + root)
    };
    let (mut t0, mut t1) = (q / a, if q != 0.0 { c / q } else { q / a });
    if t0 > t1 {
        std::mem::swap(&mut t0, &mut t1);
    }
    Some((t0, t1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_float_steps_by_one_ulp() {
        assert!(next_float_up(1.0) > 1.0);
        assert_eq!(next_float_up(1.0), 1.0 + f32::EPSILON);
        assert!(next_float_down(1.0) < 1.0);
        assert!(next_float_up(0.0) > 0.0);
        assert!(next_float_down(0.0) < 0.0);
        assert_eq!(next_float_down(next_float_up(-2.5)), -2.5);
    }

    #[test]
    fn quadratic_roots_are_accurate_under_cancellation() {
        // t² − 1e8 t + 1 = 0: roots ≈ 1e8 and 1e-8; the naive formula returns 0 for the small one.
        let (t0, t1) = solve_quadratic(1.0, -1e8, 1.0).unwrap();
        assert!((t0 - 1e-8).abs() < 1e-20);
        assert!((t1 - 1e8).abs() < 1e-4);
        assert!(solve_quadratic(1.0, 0.0, 1.0).is_none());
    }
}
