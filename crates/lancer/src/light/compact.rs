//! What the light BVH's importance needs of a node, computed once at build (pbrt-v4's
//! `CompactLightBounds`, unquantised): the box's centre, its half diagonal, the squared radius
//! of its bounding sphere, and the cos/sin of the normal cone's half-angle θ_o, so that choosing
//! a light does no square root or trigonometry that depends on the node alone.
//!
//! [`CompactLightBounds::importance`] performs exactly the floating-point operations of
//! [`super::LightBounds::importance`] on these stored values, so both give the same bits (the light
//! BVH's choices and probabilities do not change by being made cheaper).

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
    /// r² of the box's bounding sphere, r = |max − centre|.
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

/// cos(θ_a − θ_b), 1 when θ_a < θ_b, from sines and cosines.
#[inline(always)]
fn cos_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        1.0
    } else {
        cos_a * cos_b + sin_a * sin_b
    }
}

/// sin(θ_a − θ_b), 0 when θ_a < θ_b.
#[inline(always)]
fn sin_sub_clamped(sin_a: f32, cos_a: f32, sin_b: f32, cos_b: f32) -> f32 {
    if cos_a > cos_b {
        0.0
    } else {
        sin_a * cos_b - cos_a * sin_b
    }
}

impl CompactLightBounds {
    /// A conservative estimate of how much the group lights point `p` with surface normal `n`
    /// (zero for a point in a medium); the formula is on [`super::LightBounds::importance`]:
    /// I = φ · cos θ′ / max(d², |diag|/2) · cos θ′ᵢ with θ′ = max(0, θ_w − θ_o − θ_b),
    /// θ′ᵢ = max(0, θᵢ − θ_b), cos θ_b = √(1 − r²/d²) (−1 inside the sphere).
    #[inline]
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        let v = p - self.centre;
        let len2 = v.length_squared();
        let d2 = len2.max(self.min_d2);
        // The direction from the light towards p: v/|v| rounded as glam's `normalize_or_zero`
        // (v · (1/√|v|²)), reusing |v|².
        let rcp = 1.0 / len2.sqrt();
        let wi = if rcp.is_finite() && rcp > 0.0 {
            v * rcp
        } else {
            Vec3::ZERO
        };
        let mut cos_theta_w = self.w.dot(wi);
        if self.two_sided {
            cos_theta_w = cos_theta_w.abs();
        }
        let sin_theta_w = safe_sqrt(1.0 - cos_theta_w * cos_theta_w);
        // The half-angle of the cone from p holding the bounding sphere.
        let cos_theta_b = if len2 < self.r2 {
            -1.0
        } else {
            safe_sqrt(1.0 - self.r2 / len2)
        };
        let sin_theta_b = safe_sqrt(1.0 - cos_theta_b * cos_theta_b);
        // θ_x = max(0, θ_w − θ_o), then θ′ = max(0, θ_x − θ_b).
        let (cos_o, sin_o) = (self.cos_theta_o, self.sin_theta_o);
        let cos_theta_x = cos_sub_clamped(sin_theta_w, cos_theta_w, sin_o, cos_o);
        let sin_theta_x = sin_sub_clamped(sin_theta_w, cos_theta_w, sin_o, cos_o);
        let cos_theta_p = cos_sub_clamped(sin_theta_x, cos_theta_x, sin_theta_b, cos_theta_b);
        if cos_theta_p <= self.cos_theta_e {
            return 0.0;
        }
        let mut importance = self.phi * cos_theta_p / d2;
        // The surface at p sees the box at best at angle max(0, θᵢ − θ_b).
        if n != Vec3::ZERO {
            let cos_theta_i = wi.dot(n).abs();
            let sin_theta_i = safe_sqrt(1.0 - cos_theta_i * cos_theta_i);
            importance *= cos_sub_clamped(sin_theta_i, cos_theta_i, sin_theta_b, cos_theta_b);
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
    r2: Vec4,
    cos_theta_o: Vec4,
    sin_theta_o: Vec4,
    cos_theta_e: Vec4,
    two_sided: BVec4A,
}

/// cos(θ_a − θ_b) per lane, 1 where θ_a < θ_b.
#[inline(always)]
fn cos_sub_clamped4(sin_a: Vec4, cos_a: Vec4, sin_b: Vec4, cos_b: Vec4) -> Vec4 {
    Vec4::select(cos_a.cmpgt(cos_b), Vec4::ONE, cos_a * cos_b + sin_a * sin_b)
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
        let d2 = len2.max(self.min_d2);
        // wi = v/|v|, zero where 1/|v| is not a finite positive number.
        let rcp = Vec4::ONE / len2.sqrt();
        let ok = rcp.cmpgt(Vec4::ZERO) & rcp.cmplt(Vec4::INFINITY);
        let wix = Vec4::select(ok, vx * rcp, Vec4::ZERO);
        let wiy = Vec4::select(ok, vy * rcp, Vec4::ZERO);
        let wiz = Vec4::select(ok, vz * rcp, Vec4::ZERO);
        let cos_w = self.wx * wix + self.wy * wiy + self.wz * wiz;
        let cos_w = Vec4::select(self.two_sided, cos_w.abs(), cos_w);
        let sin_w = safe_sqrt4(Vec4::ONE - cos_w * cos_w);
        let cos_b = Vec4::select(
            len2.cmplt(self.r2),
            Vec4::NEG_ONE,
            safe_sqrt4(Vec4::ONE - self.r2 / len2),
        );
        let sin_b = safe_sqrt4(Vec4::ONE - cos_b * cos_b);
        // θ_x = max(0, θ_w − θ_o), then θ′ = max(0, θ_x − θ_b).
        let (cos_o, sin_o) = (self.cos_theta_o, self.sin_theta_o);
        let behind = cos_w.cmpgt(cos_o);
        let cos_x = Vec4::select(behind, Vec4::ONE, cos_w * cos_o + sin_w * sin_o);
        let sin_x = Vec4::select(behind, Vec4::ZERO, sin_w * cos_o - cos_w * sin_o);
        let cos_p = cos_sub_clamped4(sin_x, cos_x, sin_b, cos_b);
        let mut importance = self.phi * cos_p / d2;
        if n != Vec3::ZERO {
            let cos_i = (wix * n.x + wiy * n.y + wiz * n.z).abs();
            let sin_i = safe_sqrt4(Vec4::ONE - cos_i * cos_i);
            importance *= cos_sub_clamped4(sin_i, cos_i, sin_b, cos_b);
        }
        Vec4::select(
            cos_p.cmple(self.cos_theta_e),
            Vec4::ZERO,
            importance.max(Vec4::ZERO),
        )
    }
}
