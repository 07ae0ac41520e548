//! Transformations that move during the shutter interval (motion blur): pbrt-v4's
//! `AnimatedTransform`.
//!
//! Interpolating two matrices entry by entry would shear and shrink a rotating object, so each
//! end is decomposed as `M = T · R · S` (translation, rotation, scale) and the parts are
//! interpolated separately: T and S linearly, R along the great arc between two unit
//! quaternions (slerp), which turns at a constant angular speed.

use super::{Bounds3, Transform, Vec3};
use glam::{Mat3A, Mat4, Quat, Vec4};

/// A transformation keyframed at two times; in between, its decomposed parts are interpolated.
///
/// Before the start time it is the start transformation, after the end time the end one (as
/// pbrt-v4's `Interpolate`), so a render at the shutter's opening time sees the start pose
/// exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AnimatedTransform {
    start: Transform,
    end: Transform,
    start_time: f32,
    end_time: f32,
    /// False when both ends are equal: then nothing moves and nothing is interpolated.
    animated: bool,
    /// The decomposed ends: translations, rotations (the end's on the start's side of the
    /// quaternion sphere, for the shorter arc), scales (symmetric matrices).
    t: [Vec3; 2],
    r: [Quat; 2],
    s: [Mat3A; 2],
}

/// Time samples of the motion when bounding a rotating box (see
/// [`AnimatedTransform::motion_bounds`]): the padding shrinks as 1 / this.
const BOUND_STEPS: u32 = 32;

impl AnimatedTransform {
    /// `start` at `start_time` moving to `end` at `end_time` (pbrt's `TransformTimes`, 0 and 1
    /// by default).
    pub fn new(start: Transform, start_time: f32, end: Transform, end_time: f32) -> Self {
        // The matrices decide (a singular matrix's inverse may hold NaNs, never equal).
        let animated = start.m != end.m;
        let (t0, r0, s0) = decompose(&start.m);
        let (t1, mut r1, s1) = decompose(&end.m);
        // q and −q are the same rotation: take the end on the start's side, the shorter way.
        if r0.dot(r1) < 0.0 {
            r1 = -r1;
        }
        AnimatedTransform {
            start,
            end,
            start_time,
            end_time,
            animated,
            t: [t0, t1],
            r: [r0, r1],
            s: [s0, s1],
        }
    }

    /// A transformation that does not move.
    pub fn fixed(t: Transform) -> Self {
        Self::new(t, 0.0, t, 1.0)
    }

    /// True when the two ends differ.
    pub fn is_animated(&self) -> bool {
        self.animated
    }

    /// The transformation at the start time.
    pub fn start(&self) -> &Transform {
        &self.start
    }

    /// The transformation at the end time.
    pub fn end(&self) -> &Transform {
        &self.end
    }

    /// The start and end times.
    pub fn times(&self) -> [f32; 2] {
        [self.start_time, self.end_time]
    }

    /// The transformation at `time`: with u = (time − t₀)/(t₁ − t₀),
    /// `M(u) = Translate((1−u)T₀ + uT₁) · Rotate(slerp(u, R₀, R₁)) · ((1−u)S₀ + uS₁)`,
    /// and its inverse `S(u)⁻¹ · R(u)ᵀ · Translate(−T(u))`.
    pub fn interpolate(&self, time: f32) -> Transform {
        if !self.animated || time <= self.start_time {
            return self.start;
        }
        if time >= self.end_time {
            return self.end;
        }
        let u = (time - self.start_time) / (self.end_time - self.start_time);
        let t = (1.0 - u) * self.t[0] + u * self.t[1];
        let r = Mat3A::from_quat(slerp(u, self.r[0], self.r[1]));
        let s = self.s[0] * (1.0 - u) + self.s[1] * u;
        let lin = r * s;
        let lin_inv = s.inverse() * r.transpose();
        let affine = |l: Mat3A, t: Vec3| {
            Mat4::from_cols(
                l.x_axis.extend(0.0),
                l.y_axis.extend(0.0),
                l.z_axis.extend(0.0),
                t.extend(1.0),
            )
        };
        Transform::from_pair(affine(lin, t), affine(lin_inv, -(lin_inv * t)))
    }

    /// A box holding every pose of `b` over the whole motion.
    ///
    /// Without rotation every point moves on a straight line (T and S are linear in u), so the
    /// box of the two ends' boxes is exact. With rotation, the boxes at u = k/N (k = 0…N) are
    /// joined and padded by V / 2N, where V bounds the speed |dp/du| of any point x of the box:
    /// `|dp/du| ≤ |T₁ − T₀| + 2Ω · max(|S₀x|, |S₁x|) + ‖S₁ − S₀‖_F · |x|` (Ω the angle between
    /// the two quaternions, so the rotation turns at 2Ω per unit u; |Sx| and |x| are convex in
    /// x, so their maxima over the box are at its corners). Every point then stays within
    /// V / 2N of its position at the nearest sample time, which the sample's box holds. This
    /// replaces pbrt-v4's exact extrema of the rotating corners by a bound as safe and, with
    /// N = 32, within a few percent of the motion's extent.
    pub fn motion_bounds(&self, b: &Bounds3) -> Bounds3 {
        if !self.animated {
            return self.start.bounds(b);
        }
        let ends = self.start.bounds(b).union(&self.end.bounds(b));
        if self.r[0] == self.r[1] {
            return ends;
        }
        let n = BOUND_STEPS;
        let mut out = ends;
        for k in 1..n {
            let u = k as f32 / n as f32;
            let time = self.start_time + u * (self.end_time - self.start_time);
            out = out.union(&self.interpolate(time).bounds(b));
        }
        let omega = self.r[0].dot(self.r[1]).clamp(-1.0, 1.0).acos();
        let ds = self.s[1] - self.s[0];
        let ds_norm =
            (ds.x_axis.length_squared() + ds.y_axis.length_squared() + ds.z_axis.length_squared())
                .sqrt();
        let mut speed: f32 = 0.0;
        for i in 0..8 {
            let c = b.corner(i);
            let sx = (self.s[0] * c).length().max((self.s[1] * c).length());
            speed = speed.max(2.0 * omega * sx + ds_norm * c.length());
        }
        speed += (self.t[1] - self.t[0]).length();
        // Plus a relative margin for the rounding of the sampled transforms.
        let magnitude = out.min.abs().max(out.max.abs()).max_element();
        let pad = speed / (2 * n) as f32 + 1e-5 * magnitude;
        Bounds3 {
            min: out.min - Vec3::splat(pad),
            max: out.max + Vec3::splat(pad),
        }
    }
}

/// pbrt's `Transform::Decompose` of an affine matrix into `M = T · R · S`: T its last column,
/// R the polar decomposition's rotation of the linear part L, found by iterating
/// `Rᵢ₊₁ = (Rᵢ + (Rᵢᵀ)⁻¹) / 2` from R₀ = L until no row changes by more than 10⁻⁴ (at most 100
/// times), and S = R⁻¹ L. A mirroring L (negative determinant) gives an orthogonal R with
/// determinant −1, which no quaternion represents: its sign goes into S instead (pbrt-v4 leaves
/// that case open).
pub fn decompose(m: &Mat4) -> (Vec3, Quat, Mat3A) {
    let t = Vec3::from_vec4(m.w_axis);
    let l = Mat3A::from_mat4(*m);
    let mut r = l;
    for _ in 0..100 {
        let next = (r + r.transpose().inverse()) * 0.5;
        let d = (r - next).transpose();
        let norm = [d.x_axis, d.y_axis, d.z_axis]
            .iter()
            .map(|row| row.abs().element_sum())
            .fold(0.0f32, f32::max);
        r = next;
        if norm <= 1e-4 || norm.is_nan() {
            break;
        }
    }
    if r.determinant() < 0.0 {
        r = -r;
    }
    let s = r.inverse() * l;
    (t, Quat::from_mat3a(&r).normalize(), s)
}

/// Spherical interpolation between unit quaternions, pbrt's form:
/// `slerp(u, q₁, q₂) = q₁ (1−u) sinc((1−u)θ)/sinc θ + q₂ u sinc(uθ)/sinc θ`, with θ the angle
/// between them and sinc x = sin x / x (1 at 0, so equal quaternions interpolate linearly).
fn slerp(u: f32, q1: Quat, q2: Quat) -> Quat {
    let theta = angle_between(q1, q2);
    let sinc_theta = sinc(theta);
    let a = (1.0 - u) * sinc((1.0 - u) * theta) / sinc_theta;
    let b = u * sinc(u * theta) / sinc_theta;
    Quat::from_vec4(Vec4::from(q1) * a + Vec4::from(q2) * b)
}

/// The angle between two unit quaternions as 4-vectors, accurate near 0 and π (pbrt's
/// `AngleBetween`: 2 asin(|q₂ − q₁| / 2), or π minus that for q₂ + q₁ when they face apart).
fn angle_between(q1: Quat, q2: Quat) -> f32 {
    let (a, b) = (Vec4::from(q1), Vec4::from(q2));
    if a.dot(b) < 0.0 {
        std::f32::consts::PI - 2.0 * ((a + b).length() / 2.0).clamp(-1.0, 1.0).asin()
    } else {
        2.0 * ((b - a).length() / 2.0).clamp(-1.0, 1.0).asin()
    }
}

/// sin x / x, 1 near 0.
fn sinc(x: f32) -> f32 {
    if 1.0 - x * x == 1.0 { 1.0 } else { x.sin() / x }
}

#[cfg(test)]
mod tests;
