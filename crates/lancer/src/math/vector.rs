//! The vector types and the vector helpers everything else builds on (a leaf: it depends on
//! nothing else in the crate but [`super::float`]).

use super::float::{next_float_down, next_float_up};
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

/// Radiance, throughput and every colour inside light transport (BSDF values, emission): four
/// `f32` lanes in one SSE register (glam's `Vec4`), so that an operation on it costs what one on
/// an [`Rgb`] costs.
///
/// In spectral mode lane i is the value at the path's wavelength λᵢ
/// ([`crate::spectrum::sampled::SampledWavelengths`], four per camera sample as pbrt-v4's
/// `NSpectrumSamples`). In RGB mode the lanes are (r, g, b, b) ([`rgb_lanes`]): every lane-wise
/// operation then keeps lane 3 equal to lane 2, so lanes 0–2 hold exactly the bits an [`Rgb`]
/// computation would, and `max_element`, `min_element`, `is_finite` and `== ZERO` answer as
/// they would on the [`Rgb`]. Sums and averages over lanes are not mode-independent: take them
/// through [`crate::spectrum::sampled`] or on [`lanes_rgb`].
pub type SampledSpectrum = glam::Vec4;

/// An RGB colour as transport lanes: (r, g, b, b) (see [`SampledSpectrum`]).
#[inline(always)]
pub fn rgb_lanes(c: Rgb) -> SampledSpectrum {
    c.extend(c.z)
}

/// The RGB colour held by RGB-mode lanes (r, g, b, b): the first three.
#[inline(always)]
pub fn lanes_rgb(s: SampledSpectrum) -> Rgb {
    Rgb::from_vec4(s)
}

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

#[cfg(test)]
mod tests {
    use super::*;

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
