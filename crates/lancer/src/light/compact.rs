//! What the light BVH's importance needs of a node, computed once at build (pbrt-v4's
//! `CompactLightBounds`, unquantised): the box's centre, its half diagonal (and its
//! reciprocal), the radius of its bounding sphere and its square, and the cos/sin of the normal
//! cone's half-angle θ_o, so that choosing a light does no trigonometry that depends on the
//! node alone.
//!
//! The importance is pbrt-v4's formula, evaluated on the unnormalised vector v = p − centre
//! rather than on the unit direction v/|v|: every cosine and sine it needs is a length divided
//! by |v| (cos θ_w = w·v/|v|, sin θ_w = √(|v|² − (w·v)²)/|v|, cos θ_b = √(|v|² − r²)/|v|,
//! sin θ_b = r/|v|, and likewise for θᵢ), so the products cos θ′ = cos θ_x cos θ_b + sin θ_x
//! sin θ_b and cos θ′ᵢ are sums of such lengths divided by |v|² once. The square roots then
//! all start from |v|² side by side, and the one division, 1/|v|², too, where pbrt-v4's form
//! is a chain (√, then 1/x, then the dot products, then √(1 − cos²), then …, then /d²) that
//! the lighting of every shading point waits on. The two differ only by rounding.
//!
//! [`CompactLightBounds::importance`] and [`CompactLightBounds4::importance`] perform the same
//! floating-point operations in the same order, so both give the same bits.

use crate::math::Vec3;
use glam::{BVec4A, Vec4};

/// A light BVH node's bounds, prepared for [`CompactLightBounds::importance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompactLightBounds {
    /// Centre of the box (also the centre of its bounding sphere).
    pub centre: Vec3,
    /// Axis of the cone of normals.
    pub w: Vec3,
    /// Emitted power φ.
    pub phi: f32,
    /// |diagonal|/2: the least squared distance the importance divides by.
    pub min_d2: f32,
    /// 1/min_d2 (infinite for a point).
    pub inv_min_d2: f32,
    /// Radius r = |max − centre| of the box's bounding sphere.
    pub r: f32,
    /// r².
    pub r2: f32,
    /// cos θ_o of the cone of normals.
    pub cos_theta_o: f32,
    /// sin θ_o = √(1 − cos² θ_o).
    pub sin_theta_o: f32,
    /// cos θ_e, the emission spread.
    pub cos_theta_e: f32,
    /// Emits on both sides.
    pub two_sided: bool,
}

/// √max(0, x).
#[inline(always)]
pub(super) fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

impl CompactLightBounds {
    /// A conservative estimate of how much the group lights point `p` with surface normal `n`
    /// (zero for a point in a medium), pbrt-v4's (the formula is on
    /// [`super::LightBounds::importance`]): I = φ · cos θ′ / max(d², |diag|/2) · cos θ′ᵢ with
    /// θ′ = max(0, θ_w − θ_o − θ_b), θ′ᵢ = max(0, θᵢ − θ_b), sin θ_b = r/d (θ_b = π inside
    /// the sphere). Every cosine and sine below is kept multiplied by |v| = d (module doc).
    #[inline]
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let v = p - self.centre;
        let len2 = v.length_squared();
        // All from |v|², side by side: |v|, 1/|v|², |v| sin θ_w, |v| cos θ_b.
        let len = len2.sqrt();
        let inv_len2 = 1.0 / len2;
        let mut wv = self.w.dot(v);
        if self.two_sided {
            wv = wv.abs();
        }
        let sin_w = safe_sqrt(len2 - wv * wv);
        let cos_b = safe_sqrt(len2 - self.r2);
        // 1/max(d², |diag|/2).
        let inv_d2 = if len2 < self.min_d2 {
            self.inv_min_d2
        } else {
            inv_len2
        };
        // Inside the sphere (or at its centre) θ_b = π: every clamped angle is 0.
        let inside = len2 < self.r2 || len2 == 0.0;
        // θ_x = max(0, θ_w − θ_o) (0 when cos θ_w > cos θ_o, and then θ′ = 0 too), then
        // θ′ = max(0, θ_x − θ_b): cos θ′ = 1 when cos θ_x > cos θ_b, else
        // cos θ_x cos θ_b + sin θ_x sin θ_b.
        let (cos_o, sin_o) = (self.cos_theta_o, self.sin_theta_o);
        let cos_x = wv * cos_o + sin_w * sin_o;
        let sin_x = sin_w * cos_o - wv * sin_o;
        let cos_p = if wv > cos_o * len || inside || cos_x > cos_b {
            1.0
        } else {
            (cos_x * cos_b + sin_x * self.r) * inv_len2
        };
        if cos_p <= self.cos_theta_e {
            return 0.0;
        }
        let mut importance = self.phi * cos_p * inv_d2;
        // The surface at p sees the box at best at angle max(0, θᵢ − θ_b).
        if n != Vec3::ZERO {
            let cos_i = n.dot(v).abs();
            let sin_i = safe_sqrt(len2 - cos_i * cos_i);
            importance *= if inside || cos_i > cos_b {
                1.0
            } else {
                (cos_i * cos_b + sin_i * self.r) * inv_len2
            };
        }
        importance.max(0.0)
    }
}

/// Four [`CompactLightBounds`] side by side, one per lane, so that one pass of 4-wide
/// arithmetic gives all four importances (the light BVH evaluates a node's two children
/// together; the unused lanes repeat a child).
#[derive(Clone, Copy, Debug)]
pub struct CompactLightBounds4 {
    cx: Vec4,
    cy: Vec4,
    cz: Vec4,
    wx: Vec4,
    wy: Vec4,
    wz: Vec4,
    phi: Vec4,
    min_d2: Vec4,
    inv_min_d2: Vec4,
    r: Vec4,
    r2: Vec4,
    cos_theta_o: Vec4,
    sin_theta_o: Vec4,
    cos_theta_e: Vec4,
    two_sided: BVec4A,
}

/// √max(0, x) per lane.
#[inline(always)]
fn safe_sqrt4(x: Vec4) -> Vec4 {
    x.max(Vec4::ZERO).sqrt()
}

impl CompactLightBounds4 {
    /// The four bounds `b`, lane i holding `b[i]`.
    pub fn new(b: [CompactLightBounds; 4]) -> CompactLightBounds4 {
        let lanes = |f: fn(&CompactLightBounds) -> f32| Vec4::from_array(b.map(|x| f(&x)));
        CompactLightBounds4 {
            cx: lanes(|b| b.centre.x),
            cy: lanes(|b| b.centre.y),
            cz: lanes(|b| b.centre.z),
            wx: lanes(|b| b.w.x),
            wy: lanes(|b| b.w.y),
            wz: lanes(|b| b.w.z),
            phi: lanes(|b| b.phi),
            min_d2: lanes(|b| b.min_d2),
            inv_min_d2: lanes(|b| b.inv_min_d2),
            r: lanes(|b| b.r),
            r2: lanes(|b| b.r2),
            cos_theta_o: lanes(|b| b.cos_theta_o),
            sin_theta_o: lanes(|b| b.sin_theta_o),
            cos_theta_e: lanes(|b| b.cos_theta_e),
            two_sided: BVec4A::from_array(b.map(|x| x.two_sided)),
        }
    }

    /// [`CompactLightBounds::importance`] of the four lanes at once: the same operations in
    /// the same order lane by lane (dot products as (x·x′ + y·y′) + z·z′, branches as
    /// selects), so each lane has exactly the bits of the one-at-a-time form.
    #[inline]
    pub fn importance(&self, p: Vec3, n: Vec3) -> Vec4 {
        let (vx, vy, vz) = (
            Vec4::splat(p.x) - self.cx,
            Vec4::splat(p.y) - self.cy,
            Vec4::splat(p.z) - self.cz,
        );
        let len2 = vx * vx + vy * vy + vz * vz;
        let len = len2.sqrt();
        let inv_len2 = Vec4::ONE / len2;
        let wv = self.wx * vx + self.wy * vy + self.wz * vz;
        let wv = Vec4::select(self.two_sided, wv.abs(), wv);
        let sin_w = safe_sqrt4(len2 - wv * wv);
        let cos_b = safe_sqrt4(len2 - self.r2);
        let inv_d2 = Vec4::select(len2.cmplt(self.min_d2), self.inv_min_d2, inv_len2);
        let inside = len2.cmplt(self.r2) | len2.cmpeq(Vec4::ZERO);
        let (cos_o, sin_o) = (self.cos_theta_o, self.sin_theta_o);
        let cos_x = wv * cos_o + sin_w * sin_o;
        let sin_x = sin_w * cos_o - wv * sin_o;
        let one_p = wv.cmpgt(cos_o * len) | inside | cos_x.cmpgt(cos_b);
        let cos_p = Vec4::select(
            one_p,
            Vec4::ONE,
            (cos_x * cos_b + sin_x * self.r) * inv_len2,
        );
        let mut importance = self.phi * cos_p * inv_d2;
        if n != Vec3::ZERO {
            let cos_i = (vx * n.x + vy * n.y + vz * n.z).abs();
            let sin_i = safe_sqrt4(len2 - cos_i * cos_i);
            importance *= Vec4::select(
                inside | cos_i.cmpgt(cos_b),
                Vec4::ONE,
                (cos_i * cos_b + sin_i * self.r) * inv_len2,
            );
        }
        Vec4::select(
            cos_p.cmple(self.cos_theta_e),
            Vec4::ZERO,
            importance.max(Vec4::ZERO),
        )
    }
}
