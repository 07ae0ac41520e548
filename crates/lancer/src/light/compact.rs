//! What the light BVH's importance needs of a node, computed once at build (pbrt-v4's
//! `CompactLightBounds`, unquantised): the box's centre, its half diagonal, the squared radius
//! of its bounding sphere, and the cos/sin of the normal cone's half-angle θ_o, so that choosing
//! a light does no square root or trigonometry that depends on the node alone.
//!
//! [`CompactLightBounds::importance`] performs exactly the floating-point operations of
//! [`super::LightBounds::importance`] on these stored values, so both give the same bits (the light
//! BVH's choices and probabilities do not change by being made cheaper).

use crate::math::Vec3;

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
