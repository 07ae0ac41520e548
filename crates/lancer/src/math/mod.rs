//! Vectors, transforms, bounds and the floating-point error bounds that keep rays from finding
//! the surface they start on.
//!
//! Vectors come from [`glam`]; this module adds what a ray tracer needs on top: a [`Transform`]
//! carrying its inverse, axis-aligned [`Bounds3`], orthonormal [`Frame`]s and conservative
//! rounding-error arithmetic ([`gamma`], [`offset_ray_origin`]).

mod bounds;
mod frame;
mod transform;

pub use bounds::Bounds3;
pub use frame::Frame;
pub use glam::{Mat3, Mat4, UVec2, Vec2, Vec4};
pub use transform::Transform;

use glam::Vec3Swizzles;

/// The 3-vector that all computation uses: glam's `Vec3A`, three `f32` in one 16-byte SIMD
/// register, so that a vector add, multiply or min is one instruction instead of three.
///
/// Its arithmetic gives the same bits as three scalar operations, except for two glam methods
/// that round differently: use [`cross`] and [`normalize`] instead of `Vec3::cross` and
/// `Vec3::normalize` (clippy forbids those). Being 16 bytes, it is not used for data stored per
/// vertex, per triangle or per texel: that is [`PackedVec3`].
pub type Vec3 = glam::Vec3A;

/// A 3-vector for data stored in bulk (mesh vertices, triangles, texels): glam's `Vec3`, three
/// `f32` in 12 bytes. Convert with `Vec3::from` / `PackedVec3::from` to compute with it.
pub type PackedVec3 = glam::Vec3;

/// Linear RGB (the sRGB/Rec.709 primaries, D65 white): radiance, reflectance, any colour.
pub type Rgb = Vec3;

/// [`Rgb`] as stored in bulk (texels, per-primitive emission): 12 bytes.
pub type PackedRgb = PackedVec3;

/// The cross product `a × b`, each component rounded as two products and a difference:
/// `(a.y·b.z − b.y·a.z, a.z·b.x − b.z·a.x, a.x·b.y − b.x·a.y)`.
///
/// glam's `Vec3A::cross` fuses one product into the difference when the target has FMA (as
/// x86-64-v3 does), which rounds differently from the scalar formula and from a build without
/// FMA. This one gives the same bits everywhere, and the same as glam's scalar `Vec3::cross`.
#[inline(always)]
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    (a.zxy() * b - b.zxy() * a).zxy()
}

/// `v` scaled to unit length as `v · (1/|v|)`, the rounding of glam's scalar
/// `Vec3::normalize` (glam's `Vec3A::normalize` divides by `|v|` instead, which can differ in
/// the last bit). Infinite or NaN for a zero vector, as glam's; see `normalize_or_zero` and
/// `try_normalize`, which round the same way in both.
#[inline(always)]
pub fn normalize(v: Vec3) -> Vec3 {
    v * v.length_recip()
}

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

/// Moves a ray origin off the surface it starts on, just far enough that the ray cannot hit that
/// surface again through rounding error.
///
/// `p` is a computed hit point whose true position lies within the box `p ± p_error`. The offset is
/// along the geometric normal `n`, by the projection of that box on `n`: `d = |n|·p_error`, on the
/// side `w` leaves towards. The result is then rounded away from `p` so the offset itself cannot be
/// lost to rounding (PBRT §6.8.6). No magic epsilon: the distance is exactly what the error
/// analysis of the intersection routine allows.
#[inline(always)]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let mut offset = d * n;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    let round = |po: f32, off: f32| {
        if off > 0.0 {
            next_float_up(po)
        } else if off < 0.0 {
            next_float_down(po)
        } else {
            po
        }
    };
    Vec3::new(
        round(po.x, offset.x),
        round(po.y, offset.y),
        round(po.z, offset.z),
    )
}

/// Fraction of a segment's length that a shadow ray stops short of its end point, so that the
/// ray does not report the light's own surface, already offset by [`offset_ray_origin`], as an
/// occluder. It is relative, so it scales with the scene (PBRT's `ShadowEpsilon`).
pub const SHADOW_EPSILON: f32 = 0.0001;

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

/// `v` turned to lie in the hemisphere of `reference` (`v` or `−v`).
#[inline]
pub fn face_forward(v: Vec3, reference: Vec3) -> Vec3 {
    if v.dot(reference) < 0.0 { -v } else { v }
}

/// Luminance (CIE Y) of a linear sRGB colour.
#[inline]
pub fn luminance(c: Rgb) -> f32 {
    0.212671 * c.x + 0.715160 * c.y + 0.072169 * c.z
}

/// Spherical direction from angles: (sinθ cosφ, sinθ sinφ, cosθ).
#[inline]
pub fn spherical_direction(sin_theta: f32, cos_theta: f32, phi: f32) -> Vec3 {
    let s = sin_theta.clamp(-1.0, 1.0);
    Vec3::new(s * phi.cos(), s * phi.sin(), cos_theta.clamp(-1.0, 1.0))
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

    #[test]
    fn offset_moves_origin_to_the_side_of_w() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        let err = Vec3::splat(1e-5);
        let n = Vec3::Y;
        let up = offset_ray_origin(p, err, n, Vec3::new(0.3, 1.0, 0.0));
        let down = offset_ray_origin(p, err, n, Vec3::new(0.3, -1.0, 0.0));
        assert!(up.y > p.y + 0.9e-5 && down.y < p.y - 0.9e-5);
        assert_eq!(up.x, p.x);
    }
}
