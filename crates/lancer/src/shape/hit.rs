//! The records a shape hands back: the cheap [`ShapeHit`] of an intersection test, the full
//! [`SurfaceInteraction`] of the closest hit (with its [`Shading`] geometry), and the
//! [`ShapeSample`] of a point sampled on a surface. A leaf module: every shape file uses it,
//! it uses no shape.

use crate::math::{Transform, Vec2, Vec3, cross};
use crate::ray::Ray;

/// The result of [`Shape::intersect`](super::Shape::intersect): the distance along the ray and
/// two shape-specific values kept for [`Shape::interaction`](super::Shape::interaction)
/// (barycentrics b₁, b₂ for triangles).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeHit {
    /// Parametric distance: the hit point is `ray.at(t)`.
    pub t: f32,
    /// Shape-specific (triangles: barycentric b₁).
    pub u: f32,
    /// Shape-specific (triangles: barycentric b₂).
    pub v: f32,
}

/// The local differential geometry used for shading (may differ from the true geometry:
/// interpolated vertex normals, normal maps).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// Shading normal, unit length, on the same side as the geometric normal.
    pub n: Vec3,
    /// Shading ∂p/∂u.
    pub dpdu: Vec3,
    /// Shading ∂p/∂v.
    pub dpdv: Vec3,
}

/// Everything known about a ray's hit on a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceInteraction {
    /// The hit point, world space.
    pub p: Vec3,
    /// Bound on the absolute rounding error of `p`, per axis: the true point lies in
    /// `p ± p_error`. Spawned rays are offset by it.
    pub p_error: Vec3,
    /// Geometric normal, unit length. Its side follows pbrt: the shape's natural orientation,
    /// flipped by `ReverseOrientation` (and by handedness changes as pbrt does).
    pub n: Vec3,
    /// Surface parameterisation (u, v).
    pub uv: Vec2,
    /// ∂p/∂u.
    pub dpdu: Vec3,
    /// ∂p/∂v.
    pub dpdv: Vec3,
    /// Shading geometry.
    pub shading: Shading,
    /// Direction towards the ray's origin (−d, normalised).
    pub wo: Vec3,
    /// Parametric distance along the ray.
    pub t: f32,
}

impl SurfaceInteraction {
    /// A ray leaving this point in direction `d`.
    #[inline]
    pub fn spawn_ray(&self, d: Vec3) -> Ray {
        Ray::spawn(self.p, self.p_error, self.n, d)
    }

    /// A shadow ray from this point to `target` (stopping just short of it).
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        Ray::spawn_to(self.p, self.p_error, self.n, target)
    }

    /// Builds an interaction from object-space differential geometry, applying the pbrt rules:
    /// `n = normalize(∂p/∂u × ∂p/∂v)`, flipped when `flip` (reverse orientation xor a
    /// handedness-swapping transform), then everything moved to world space by `to_world`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn from_object(
        to_world: &Transform,
        p_obj: Vec3,
        p_err_obj: Vec3,
        uv: Vec2,
        dpdu: Vec3,
        dpdv: Vec3,
        flip: bool,
        wo: Vec3,
        t: f32,
    ) -> SurfaceInteraction {
        let mut n_obj = cross(dpdu, dpdv).normalize_or_zero();
        if flip {
            n_obj = -n_obj;
        }
        let (p, p_error) = to_world.point_with_error_in(p_obj, p_err_obj);
        let n = to_world.normal(n_obj).normalize_or_zero();
        let (dpdu, dpdv) = (to_world.vector(dpdu), to_world.vector(dpdv));
        SurfaceInteraction {
            p,
            p_error,
            n,
            uv,
            dpdu,
            dpdv,
            shading: Shading { n, dpdu, dpdv },
            wo,
            t,
        }
    }
}

/// A point on a shape's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    /// The point, world space.
    pub p: Vec3,
    /// Geometric normal there, unit length, oriented as
    /// [`Shape::interaction`](super::Shape::interaction) orients it.
    pub n: Vec3,
}
