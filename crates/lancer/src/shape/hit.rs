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
    /// The time of the ray that met the surface (set by [`crate::scene::Scene::intersect`];
    /// rays spawned here inherit it).
    pub time: f32,
}

impl SurfaceInteraction {
    /// A ray leaving this point in direction `d`, at the interaction's time.
    #[inline]
    pub fn spawn_ray(&self, d: Vec3) -> Ray {
        Ray::spawn(self.p, self.p_error, self.n, d).at_time(self.time)
    }

    /// A shadow ray from this point to `target` (stopping just short of it), at the
    /// interaction's time.
    #[inline]
    pub fn spawn_ray_to(&self, target: Vec3) -> Ray {
        Ray::spawn_to(self.p, self.p_error, self.n, target).at_time(self.time)
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
            time: 0.0,
        }
    }
}

/// pbrt-v4's shading ∂p/∂u, ∂p/∂v and ∂n/∂u, ∂n/∂v at a hit: what its `BumpMap` reads
/// (`NormalBumpEvalContext::shading`). Worked out only for a hit whose material has a
/// displacement texture ([`crate::shape::Shape::shading_derivatives`]), never in the
/// intersection itself.
///
/// The ∂p/∂u, ∂p/∂v are pbrt-v4's, which lancer's [`Shading`] need not equal: a triangle with
/// vertex normals has pbrt's s = (n_s × ∂p/∂u) × n_s and t = n_s × ∂p/∂u, of the length of
/// ∂p/∂u, where lancer keeps them unit. ∂n/∂u, ∂n/∂v are of the normal as the shape defines
/// it, before any flip by `ReverseOrientation` or a handedness swap (pbrt-v4 flips n but not
/// its derivatives).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadingDerivatives {
    /// Shading ∂p/∂u.
    pub dpdu: Vec3,
    /// Shading ∂p/∂v.
    pub dpdv: Vec3,
    /// Shading ∂n/∂u.
    pub dndu: Vec3,
    /// Shading ∂n/∂v.
    pub dndv: Vec3,
}

impl ShadingDerivatives {
    /// The derivatives of a surface whose normal does not turn (∂n/∂u = ∂n/∂v = 0), with
    /// `si`'s shading tangents: planes, disks, boxes, curves (pbrt-v4 gives curves none).
    #[inline]
    pub fn flat(si: &SurfaceInteraction) -> ShadingDerivatives {
        ShadingDerivatives {
            dpdu: si.shading.dpdu,
            dpdv: si.shading.dpdv,
            dndu: Vec3::ZERO,
            dndv: Vec3::ZERO,
        }
    }

    /// Moved by `xf` as pbrt-v4's `Transform` moves a `SurfaceInteraction`: ∂p/∂u, ∂p/∂v as
    /// vectors (M·v), ∂n/∂u, ∂n/∂v as normals ((M⁻¹)ᵀ·n, not normalised).
    #[inline]
    pub fn transformed(&self, xf: &Transform) -> ShadingDerivatives {
        ShadingDerivatives {
            dpdu: xf.vector(self.dpdu),
            dpdv: xf.vector(self.dpdv),
            dndu: xf.normal(self.dndu),
            dndv: xf.normal(self.dndv),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn from_object_orients_and_places_the_normal() {
        // ∂p/∂u = (2, 0, 0), ∂p/∂v = (0, 3, 0): n = normalize(∂p/∂u × ∂p/∂v) = +z, flipped to
        // −z when asked; a translation moves p but not n, ∂p/∂u or ∂p/∂v.
        let to_world = Transform::translate(Vec3::new(1.0, 2.0, 3.0));
        let (dpdu, dpdv) = (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 3.0, 0.0));
        for (flip, n) in [(false, Vec3::Z), (true, -Vec3::Z)] {
            let si = SurfaceInteraction::from_object(
                &to_world,
                Vec3::new(0.5, 0.5, 0.0),
                Vec3::ZERO,
                Vec2::new(0.25, 0.75),
                dpdu,
                dpdv,
                flip,
                Vec3::Z,
                2.0,
            );
            assert_eq!(si.p, Vec3::new(1.5, 2.5, 3.0));
            assert_eq!((si.n, si.shading.n), (n, n));
            assert_eq!((si.dpdu, si.dpdv), (dpdu, dpdv));
            assert_eq!((si.uv, si.t, si.wo), (Vec2::new(0.25, 0.75), 2.0, Vec3::Z));
        }
    }

    #[test]
    fn spawned_rays_leave_on_the_side_of_their_direction() {
        let si = SurfaceInteraction::from_object(
            &Transform::IDENTITY,
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::splat(1e-3),
            Vec2::ZERO,
            Vec3::X,
            Vec3::Y,
            false,
            Vec3::Z,
            1.0,
        );
        // Offset by at least the error bound along ±n, towards the direction taken.
        assert!(si.spawn_ray(Vec3::Z).o.z >= 1.0 + 1e-3);
        assert!(si.spawn_ray(-Vec3::Z).o.z <= 1.0 - 1e-3);
        // Towards a target: the ray ends just short of it (t = 1 would reach it).
        let r = si.spawn_ray_to(Vec3::new(0.0, 0.0, 5.0));
        assert!(r.t_max < 1.0 && r.at(r.t_max).z > 4.9);
    }
}
