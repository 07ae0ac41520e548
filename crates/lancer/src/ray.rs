//! The ray of the course: p(t) = o + t·d.

// One item per line: the vocabulary lives in math's leaf modules, not in `math` itself.
use crate::math::SHADOW_EPSILON;
use crate::math::Vec3;
use crate::math::offset_ray_origin;

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
