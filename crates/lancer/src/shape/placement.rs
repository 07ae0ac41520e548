//! Where a shape sits in the world ([`Placement`]), and the helpers the quadrics share: the
//! azimuth of a point, the double-precision hit distance carried in a [`ShapeHit`], the error
//! bound of a quadric's hit point, and moving object-space samples to the world. A leaf module
//! beside [`super::hit`]: the shape files use it, it uses no shape.

use super::hit::{ShapeHit, ShapeSample};
use crate::math::{Transform, Vec3, gamma};
use crate::ray::Ray;
use glam::{DMat4, DVec3};

/// Where a quadric sits: its object-to-world transform and orientation.
///
/// Rays are moved into object space in double precision: the rounding error of that transform
/// is then negligible next to the single-precision error bounds by which spawned rays are
/// offset, so a ray leaving a quadric can never find it again at a tiny positive `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Object space → world space.
    pub to_world: Transform,
    /// World space → object space, in double precision.
    pub to_object: DMat4,
    /// Normals flipped (reverse orientation xor the transform swaps handedness).
    pub flip_normal: bool,
}

impl Placement {
    /// A placement from a transform and pbrt's `ReverseOrientation` state.
    pub fn new(to_world: Transform, reverse_orientation: bool) -> Placement {
        Placement {
            to_world,
            to_object: to_world.m.as_dmat4().inverse(),
            flip_normal: reverse_orientation ^ to_world.swaps_handedness(),
        }
    }

    /// The ray in object space, double precision: (origin, direction).
    #[inline]
    pub fn object_ray(&self, ray: &Ray) -> (DVec3, DVec3) {
        (
            self.to_object.transform_point3(ray.o.as_dvec3()),
            self.to_object.transform_vector3(ray.d.as_dvec3()),
        )
    }

    /// The factor by which the placement scales areas: |det M|^(2/3) for the linear part M of
    /// object-to-world (exact for similarities, which is what the quadrics' area sampling
    /// assumes, like pbrt's).
    pub fn area_scale(&self) -> f32 {
        let det = glam::Mat3::from_mat4(self.to_world.m).determinant().abs();
        det.powf(2.0 / 3.0)
    }

    /// An object-space point and outward normal moved to the world, the normal flipped as
    /// [`SurfaceInteraction::from_object`](super::SurfaceInteraction::from_object) flips it.
    pub fn place(&self, p: Vec3, n: Vec3) -> ShapeSample {
        let n = if self.flip_normal { -n } else { n };
        ShapeSample {
            p: self.to_world.point(p),
            n: self.to_world.normal(n).normalize_or_zero(),
        }
    }
}

/// The azimuth φ = atan2(y, x) of an object-space point, in [0, 2π).
#[inline]
pub(crate) fn phi_of(p: DVec3) -> f64 {
    let phi = p.y.atan2(p.x);
    if phi < 0.0 {
        phi + 2.0 * std::f64::consts::PI
    } else {
        phi
    }
}

/// A quadric's hit at the double-precision distance `t`: `t` rounded to `f32`, and the
/// rounding residual kept in `u` so that [`quadric_t`] recovers `t` to about 48 bits.
#[inline]
pub(crate) fn quadric_hit(t: f64) -> ShapeHit {
    let tf = t as f32;
    ShapeHit {
        t: tf,
        u: (t - tf as f64) as f32,
        v: 0.0,
    }
}

/// The double-precision distance stored by [`quadric_hit`].
#[inline]
pub(crate) fn quadric_t(hit: &ShapeHit) -> f64 {
    hit.t as f64 + hit.u as f64
}

/// Error bound of the object-space point p = o + t·d computed in double precision from the
/// root t and rounded to `f32`, for quadrics whose hit points are not reprojected onto the
/// surface: γ₃·|p| covers the rounding to `f32` with room to spare, and 10⁻¹²·(|o| + |t·d|)
/// the double-precision error of the root and of o + t·d, per axis.
#[inline]
pub(crate) fn quadric_error(o: DVec3, d: DVec3, t: f64, p: Vec3) -> Vec3 {
    gamma(3) * p.abs() + (1e-12 * (o.abs() + (t * d).abs())).as_vec3a()
}
