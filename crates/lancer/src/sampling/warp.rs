//! Warps: maps from uniform points of [0, 1)² to points distributed on shapes with known
//! densities. Each `sample_*` has a matching `*_pdf`.

use crate::math::{INV_4PI, INV_PI, PI, Vec2, Vec3, safe_sqrt};

/// A point uniform on the unit disk by Shirley–Chiu's concentric map, which keeps strata
/// compact (adjacent squares map to adjacent wedges). Density 1/π.
#[inline]
pub fn sample_uniform_disk_concentric(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    // θ = π/4·(o_y/o_x) in the left and right wedges; θ = π/2 − φ with φ = π/4·(o_x/o_y) in
    // the top and bottom ones, where (cos θ, sin θ) = (sin φ, cos φ). Either angle lies in
    // [−π/4, π/4], where short series are exact to f32 precision (no libm call).
    if o.x.abs() > o.y.abs() {
        let (c, s) = cos_sin_quarter_turn(PI / 4.0 * (o.y / o.x));
        o.x * Vec2::new(c, s)
    } else {
        let (c, s) = cos_sin_quarter_turn(PI / 4.0 * (o.x / o.y));
        o.y * Vec2::new(s, c)
    }
}

/// (cos φ, sin φ) for |φ| ≤ π/4 by their Taylor series
/// cos φ = 1 − φ²/2! + φ⁴/4! − φ⁶/6! + φ⁸/8!, sin φ = φ − φ³/3! + φ⁵/5! − φ⁷/7! + φ⁹/9!,
/// evaluated by Horner's rule in φ². The first omitted terms, (π/4)¹⁰/10! ≈ 2.5·10⁻⁸ and
/// (π/4)¹¹/11! ≈ 1.8·10⁻⁹, are below half an f32 ulp of the results there.
#[inline(always)]
fn cos_sin_quarter_turn(phi: f32) -> (f32, f32) {
    let x = phi * phi;
    let c = 1.0 + x * (-1.0 / 2.0 + x * (1.0 / 24.0 + x * (-1.0 / 720.0 + x * (1.0 / 40320.0))));
    let s = phi
        * (1.0 + x * (-1.0 / 6.0 + x * (1.0 / 120.0 + x * (-1.0 / 5040.0 + x * (1.0 / 362880.0)))));
    (c, s)
}

/// (cos 2πt, sin 2πt), without a libm call: with q the integer nearest 4t and
/// r = 4t − q ∈ [−½, ½] (exact), 2πt = qπ/2 + φ with φ = rπ/2 ∈ [−π/4, π/4], where
/// [`cos_sin_quarter_turn`]'s series is exact to f32 precision; then q quarter turns:
/// (cos, sin)(φ + qπ/2) = (c, s), (−s, c), (−c, −s), (s, −c) for q mod 4 = 0, 1, 2, 3.
/// Sampling calls it with t = u ∈ [0, 1); any |t| < 2²¹ works.
#[inline(always)]
pub fn cos_sin_turn(t: f32) -> (f32, f32) {
    let v = 4.0 * t;
    let q = v.round();
    let (c, s) = cos_sin_quarter_turn((v - q) * (PI / 2.0));
    let q = q as i32;
    // Odd quarters swap cosine and sine; quarters 1, 2 negate the cosine, 2, 3 the sine.
    let (c, s) = if q & 1 != 0 { (s, c) } else { (c, s) };
    let c = if (q + 1) & 2 != 0 { -c } else { c };
    let s = if q & 2 != 0 { -s } else { s };
    (c, s)
}

/// [`crate::math::spherical_direction`] with its azimuth in turns: (sin θ cos 2πt,
/// sin θ sin 2πt, cos θ), both clamped to [−1, 1], by [`cos_sin_turn`] (samplers draw
/// φ = 2πu).
#[inline(always)]
pub fn spherical_direction_turn(sin_theta: f32, cos_theta: f32, t: f32) -> Vec3 {
    let s = sin_theta.clamp(-1.0, 1.0);
    let (c, si) = cos_sin_turn(t);
    Vec3::new(s * c, s * si, cos_theta.clamp(-1.0, 1.0))
}

/// A point uniform on the unit disk by polar coordinates: r = √u₀, φ = 2πu₁. Density 1/π.
/// Unlike the concentric map it keeps u₁ ↦ φ linear, which visible-normal sampling relies on.
#[inline]
pub fn sample_uniform_disk_polar(u: Vec2) -> Vec2 {
    let r = u.x.max(0.0).sqrt();
    let (c, s) = cos_sin_turn(u.y);
    Vec2::new(r * c, r * s)
}

/// A distance with density a·e^(−a·x) on [0, ∞): x = −ln(1 − u)/a.
#[inline]
pub fn sample_exponential(u: f32, a: f32) -> f32 {
    -(1.0 - u).ln() / a
}

/// The Henyey–Greenstein phase function for the cosine between `wo` and `wi`, both pointing
/// away from the scattering point (pbrt-v4's convention, so forward scattering, g > 0, peaks
/// at cos = −1): p = (1 − g²) / (4π (1 + g² + 2g·cos)^{3/2}).
#[inline]
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g + 2.0 * g * cos_theta;
    INV_4PI * (1.0 - g * g) / (denom * safe_sqrt(denom))
}

/// Samples `wi` from the Henyey–Greenstein phase function around `wo` (same convention as
/// [`henyey_greenstein`]) by inverting its CDF in cos θ:
/// cos θ = −(1 + g² − ((1 − g²)/(1 + g − 2g·u₀))²) / (2g) (uniform when |g| < 10⁻³), φ = 2πu₁.
/// Returns the direction and its density, which equals the phase function value.
#[inline]
pub fn sample_henyey_greenstein(wo: Vec3, g: f32, u: Vec2) -> (Vec3, f32) {
    let cos_theta = if g.abs() < 1e-3 {
        1.0 - 2.0 * u.x
    } else {
        let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
        (-(1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
    };
    let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
    let frame = crate::math::Frame::from_z(wo);
    let wi = frame.from_local(spherical_direction_turn(sin_theta, cos_theta, u.y));
    (wi, henyey_greenstein(cos_theta, g))
}

/// A direction in the +z hemisphere with density cos θ / π (Malley's method: a uniform disk
/// point lifted onto the hemisphere).
#[inline]
pub fn sample_cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = sample_uniform_disk_concentric(u);
    let z = safe_sqrt(1.0 - d.x * d.x - d.y * d.y);
    Vec3::new(d.x, d.y, z)
}

/// Density of [`sample_cosine_hemisphere`].
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * INV_PI
}

/// A direction uniform on the unit sphere: z = 1 − 2u₀, φ = 2πu₁. Density 1/(4π).
#[inline]
pub fn sample_uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = safe_sqrt(1.0 - z * z);
    let (c, s) = cos_sin_turn(u.y);
    Vec3::new(r * c, r * s, z)
}

/// Density of [`sample_uniform_sphere`].
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    INV_4PI
}

/// A direction uniform in the +z hemisphere. Density 1/(2π).
#[inline]
pub fn sample_uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = safe_sqrt(1.0 - z * z);
    let (c, s) = cos_sin_turn(u.y);
    Vec3::new(r * c, r * s, z)
}

/// Density of [`sample_uniform_hemisphere`].
#[inline]
pub fn uniform_hemisphere_pdf() -> f32 {
    0.5 * INV_PI
}

/// A direction uniform in the cone of half-angle θmax around +z. Density 1/(2π(1 − cos θmax)).
#[inline]
pub fn sample_uniform_cone(u: Vec2, cos_theta_max: f32) -> Vec3 {
    let cos_theta = (1.0 - u.x) + u.x * cos_theta_max;
    let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
    let (c, s) = cos_sin_turn(u.y);
    Vec3::new(sin_theta * c, sin_theta * s, cos_theta)
}

/// Density of [`sample_uniform_cone`].
#[inline]
pub fn uniform_cone_pdf(cos_theta_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_theta_max))
}

/// Barycentrics (b₀, b₁, b₂) of a point uniform on a triangle, by the area-preserving map of
/// Heitz 2019 (no square root, keeps strata compact).
#[inline]
pub fn sample_uniform_triangle(u: Vec2) -> [f32; 3] {
    let (b0, b1);
    if u.x < u.y {
        b0 = u.x / 2.0;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0;
        b0 = u.x - b1;
    }
    [b0, b1, 1.0 - b0 - b1]
}

/// pbrt-v4's equal-area octahedral map from the unit square to the unit sphere (Clarberg,
/// "Fast equal-area mapping of the (hemi)sphere using SIMD", 2008). With (u, v) = 2p − 1,
/// r = 1 − |1 − |u| − |v||, φ = π/4·((|v| − |u|)/r + 1) in the first quadrant:
/// z = ±(1 − r²) (+ inside the diamond |u| + |v| < 1), (x, y) = r·√(2 − r²)·(cos φ, sin φ)
/// with the signs of u and v. Every cell of the square covers the same solid angle: dω = 4π·du·dv.
#[inline]
pub fn equal_area_square_to_sphere(p: Vec2) -> Vec3 {
    let u = 2.0 * p.x - 1.0;
    let v = 2.0 * p.y - 1.0;
    let (up, vp) = (u.abs(), v.abs());
    let signed_distance = 1.0 - (up + vp);
    let r = 1.0 - signed_distance.abs();
    // φ/(2π) = ((|v| − |u|)/r + 1)/8.
    let turn = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } / 8.0;
    let z = (1.0 - r * r).copysign(signed_distance);
    let (cos_phi, sin_phi) = cos_sin_turn(turn);
    let cos_phi = cos_phi.copysign(u);
    let sin_phi = sin_phi.copysign(v);
    let s = r * safe_sqrt(2.0 - r * r);
    Vec3::new(cos_phi * s, sin_phi * s, z)
}

/// The inverse of [`equal_area_square_to_sphere`]: r = √(1 − |z|), φ' = atan(min/max of |x|,
/// |y|)·2/π (mirrored to 1 − φ' when |x| < |y|), v' = φ'·r, u' = r − v'; the lower hemisphere
/// swaps and reflects them (u', v') → (1 − v', 1 − u'); the signs of x and y pick the quadrant.
#[inline]
pub fn equal_area_sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = safe_sqrt(1.0 - z);
    let a = x.max(y);
    let b = if a == 0.0 { 0.0 } else { x.min(y) / a };
    let mut phi = b.atan() * (2.0 / PI);
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    u = u.copysign(d.x);
    v = v.copysign(d.y);
    Vec2::new(0.5 * (u + 1.0), 0.5 * (v + 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::normalize;

    /// cos 2πt and sin 2πt over whole turns, both signs, against f64: within 2·2⁻²⁴ (a wrong
    /// quarter or sign would be off by up to 2). The quarter boundaries and their neighbours
    /// are in the sweep.
    #[test]
    fn turns_match_f64() {
        let mut ts: Vec<f32> = (-4000..=4000).map(|i| i as f32 / 2000.0 + 1e-4).collect();
        for k in (-8..=8).filter(|&k| k != 0) {
            let b = k as f32 / 8.0;
            ts.extend([
                b,
                f32::from_bits(b.to_bits() + 1),
                f32::from_bits(b.to_bits() - 1),
            ]);
        }
        ts.push(0.999_999_94);
        for t in ts {
            let (c, s) = cos_sin_turn(t);
            let a = 2.0 * std::f64::consts::PI * t as f64;
            assert!(
                (c as f64 - a.cos()).abs() <= 2.0 * 6e-8,
                "cos turn {t}: {c}"
            );
            assert!(
                (s as f64 - a.sin()).abs() <= 2.0 * 6e-8,
                "sin turn {t}: {s}"
            );
        }
    }

    /// The series agree with libm's cos and sin over [−π/4, π/4] to within 2 ulp, and the
    /// concentric map with the polar formula it replaces.
    #[test]
    fn quarter_turn_series_match_libm() {
        for i in -1000..=1000 {
            let phi = PI / 4.0 * i as f32 / 1000.0;
            let (c, s) = cos_sin_quarter_turn(phi);
            assert!(
                (c - phi.cos()).abs() <= 2.0 * f32::EPSILON,
                "cos {phi}: {c}"
            );
            assert!(
                (s - phi.sin()).abs() <= 2.0 * f32::EPSILON * phi.abs().max(1e-3),
                "sin {phi}: {s}"
            );
        }
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.37) / 64.0, (j as f32 + 0.61) / 64.0);
                let o = 2.0 * u - Vec2::ONE;
                let (r, theta) = if o.x.abs() > o.y.abs() {
                    (o.x, PI / 4.0 * (o.y / o.x))
                } else {
                    (o.y, PI / 2.0 - PI / 4.0 * (o.x / o.y))
                };
                let d = sample_uniform_disk_concentric(u) - r * Vec2::new(theta.cos(), theta.sin());
                assert!(d.length() < 4e-7, "{u:?}: {d:?}");
            }
        }
    }

    #[test]
    fn equal_area_map_matches_pbrt_corners_and_centre() {
        // pbrt-v4's layout: the centre is +z, the corners −z, the edge midpoints ±x and ±y.
        let at = |x: f32, y: f32| equal_area_square_to_sphere(Vec2::new(x, y));
        assert!((at(0.5, 0.5) - Vec3::Z).length() < 1e-6);
        assert!((at(0.0, 0.0) + Vec3::Z).length() < 1e-6);
        assert!((at(1.0, 1.0) + Vec3::Z).length() < 1e-6);
        assert!((at(1.0, 0.5) - Vec3::X).length() < 1e-6);
        assert!((at(0.0, 0.5) + Vec3::X).length() < 1e-6);
        assert!((at(0.5, 1.0) - Vec3::Y).length() < 1e-6);
        assert!((at(0.5, 0.0) + Vec3::Y).length() < 1e-6);
        // Equal area: the inner diamond (a half of the square) is the upper hemisphere.
        let n = 200;
        let upper = (0..n * n)
            .filter(|k| {
                at(
                    ((k % n) as f32 + 0.5) / n as f32,
                    ((k / n) as f32 + 0.5) / n as f32,
                )
                .z > 0.0
            })
            .count();
        assert!((upper as f32 / (n * n) as f32 - 0.5).abs() < 0.01);
    }

    #[test]
    fn warps_land_on_their_domains() {
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                assert!(sample_uniform_disk_concentric(u).length() <= 1.0 + 1e-6);
                let h = sample_cosine_hemisphere(u);
                assert!((h.length() - 1.0).abs() < 1e-5 && h.z >= 0.0);
                assert!((sample_uniform_sphere(u).length() - 1.0).abs() < 1e-5);
                let c = sample_uniform_cone(u, 0.8);
                assert!(c.z >= 0.8 - 1e-6);
                assert!(sample_uniform_disk_polar(u).length() <= 1.0 + 1e-6);
                let b = sample_uniform_triangle(u);
                assert!(b.iter().all(|&x| (-1e-6..=1.0 + 1e-6).contains(&x)));
                // The equal-area map lands on the sphere and inverts.
                let w = equal_area_square_to_sphere(u);
                assert!((w.length() - 1.0).abs() < 1e-5, "{w}");
                let back = equal_area_sphere_to_square(w);
                assert!((back - u).abs().max_element() < 1e-4, "{u} → {w} → {back}");
            }
        }
    }

    #[test]
    fn henyey_greenstein_is_a_density_with_mean_cosine_minus_g() {
        // ∫ p dω = 2π ∫ p(c) dc = 1, and with wo and wi both pointing away the mean of
        // wo·wi is −g. Midpoint rule in c with 20 000 steps is accurate to well below 10⁻³
        // even for g = 0.9, whose density peaks at 1.9/(4π·0.001) ≈ 151.
        for g in [-0.7f32, 0.0, 0.3, 0.9] {
            let n = 20_000;
            let (mut total, mut mean) = (0.0f64, 0.0f64);
            for i in 0..n {
                let c = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                let p = henyey_greenstein(c as f32, g) as f64 * 2.0 * std::f64::consts::PI;
                total += p * 2.0 / n as f64;
                mean += c * p * 2.0 / n as f64;
            }
            assert!((total - 1.0).abs() < 2e-3, "g={g}: ∫p = {total}");
            assert!((mean + g as f64).abs() < 2e-3, "g={g}: mean cos {mean}");
            // Sampling reproduces the mean and reports the density it used.
            let wo = normalize(Vec3::new(0.3, -0.4, 0.866));
            let m = 256;
            let mut s = 0.0f64;
            for i in 0..m {
                for j in 0..m {
                    let u = Vec2::new((i as f32 + 0.5) / m as f32, (j as f32 + 0.5) / m as f32);
                    let (wi, pdf) = sample_henyey_greenstein(wo, g, u);
                    assert!((wi.length() - 1.0).abs() < 1e-4);
                    assert!((pdf - henyey_greenstein(wo.dot(wi), g)).abs() <= 1e-3 * pdf + 1e-4);
                    s += wo.dot(wi) as f64;
                }
            }
            let sm = s / (m * m) as f64;
            assert!((sm + g as f64).abs() < 3e-3, "g={g}: sampled mean cos {sm}");
        }
    }
}
