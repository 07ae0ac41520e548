//! The ray of the course: p(t) = o + t·d.

// One item per line: the vocabulary lives in math's leaf modules, not in `math` itself.
use crate::math::SHADOW_EPSILON;
use crate::math::Vec3;
use crate::math::gamma;
use crate::math::offset_ray_origin;
use crate::math::{Bounds3, Transform};

/// A half-line `p(t) = o + t·d` for `0 < t < t_max`, at an instant `time`.
///
/// `d` need not be normalised: `t` then measures in units of `|d|`. Shadow rays use a finite
/// `t_max` so that nothing beyond the light counts as an occluder. The time is the camera
/// sample's (within the shutter interval, with motion blur): every ray of a path inherits it
/// (pbrt-v4's spawned rays do), through the surface interactions it spawns from
/// ([`crate::shape::SurfaceInteraction::spawn_ray`]); moving geometry is posed at it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin `o`.
    pub o: Vec3,
    /// Direction `d`.
    pub d: Vec3,
    /// Hits are valid for `t < t_max`.
    pub t_max: f32,
    /// The instant the ray is traced at (0 for a still scene, where nothing reads it).
    pub time: f32,
}

impl Ray {
    /// An unbounded ray at time 0.
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Ray {
        Ray {
            o,
            d,
            t_max: f32::INFINITY,
            time: 0.0,
        }
    }

    /// The same ray at instant `time`.
    #[inline]
    pub fn at_time(self, time: f32) -> Ray {
        Ray { time, ..self }
    }

    /// The point `p(t) = o + t·d`.
    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + t * self.d
    }

    /// A ray leaving a surface point `p` (with error bound `p_error` and geometric normal `n`)
    /// in direction `d`, its origin offset so that it cannot re-hit that surface (at time 0:
    /// see [`Ray::at_time`]).
    #[inline]
    pub fn spawn(p: Vec3, p_error: Vec3, n: Vec3, d: Vec3) -> Ray {
        Ray::new(offset_ray_origin(p, p_error, n, d), d)
    }

    /// A shadow ray from a surface point towards the point `target`: it stops just short of
    /// the target (by [`SHADOW_EPSILON`] of the segment), so `t ∈ (0, 1 − ε)` covers exactly
    /// the open segment between them.
    #[inline]
    pub fn spawn_to(p: Vec3, p_error: Vec3, n: Vec3, target: Vec3) -> Ray {
        let o = offset_ray_origin(p, p_error, n, target - p);
        Ray {
            o,
            d: target - o,
            t_max: 1.0 - SHADOW_EPSILON,
            time: 0.0,
        }
    }
}

// The operations of math's types on rays live here, with the ray: math knows nothing of rays.

impl Transform {
    /// Transforms a ray: origin as a point, direction as a vector; `t_max` is kept, so that
    /// `p(t)` is the same point in both spaces.
    #[inline]
    pub fn ray(&self, r: &Ray) -> Ray {
        Ray {
            o: self.point(r.o),
            d: self.vector(r.d),
            t_max: r.t_max,
            time: r.time,
        }
    }
}

impl Bounds3 {
    /// Slab test: the parametric range `[t0, t1]` of the ray inside the box, clipped to
    /// `[0, ray.t_max]`, or `None` if it misses. Per axis, the ray crosses the planes
    /// `x = min.x` and `x = max.x` at `t = (min.x − o.x)/d.x` and `(max.x − o.x)/d.x`; the ray is
    /// inside the box where all three intervals overlap. The far bound is enlarged by 2γ₃ so
    /// that rounding never culls a real hit (PBRT §6.1.2).
    pub fn intersect_p(&self, ray: &Ray) -> Option<(f32, f32)> {
        let mut t0 = 0.0f32;
        let mut t1 = ray.t_max;
        for i in 0..3 {
            let inv = 1.0 / ray.d[i];
            let mut t_near = (self.min[i] - ray.o[i]) * inv;
            let mut t_far = (self.max[i] - ray.o[i]) * inv;
            if t_near > t_far {
                std::mem::swap(&mut t_near, &mut t_far);
            }
            t_far *= 1.0 + 2.0 * gamma(3);
            // NaN (0·∞ when the origin lies on a slab and d is 0 on that axis) keeps the interval.
            t0 = if t_near > t0 { t_near } else { t0 };
            t1 = if t_far < t1 { t_far } else { t1 };
            if t0 > t1 {
                return None;
            }
        }
        Some((t0, t1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slab_test_finds_entry_and_exit() {
        let b = Bounds3::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let r = Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
        let (t0, t1) = b.intersect_p(&r).unwrap();
        assert!((t0 - 2.0).abs() < 1e-6 && (t1 - 4.0).abs() < 1e-5);
        let miss = Ray::new(Vec3::new(-3.0, 2.0, 0.0), Vec3::X);
        assert!(b.intersect_p(&miss).is_none());
        let axis_parallel = Ray::new(Vec3::new(0.5, 0.5, -5.0), Vec3::Z);
        assert!(b.intersect_p(&axis_parallel).is_some());
    }
}
