//! Shapes: what a ray can hit. One file per shape; [`Shape`] is the closed set the accelerator
//! and the integrators match on (no trait objects in the hot loop).
//!
//! Intersection is split in two, as in PBRT: [`Shape::intersect`] finds the nearest parametric
//! distance `t` (and whatever the shape needs later, such as barycentrics) as cheaply as
//! possible; [`Shape::interaction`] then computes the full [`SurfaceInteraction`] (point, error
//! bounds, normals, (u, v), derivatives) once, for the closest hit only.

mod bilinear;
mod cone;
mod cuboid;
mod curve;
mod cylinder;
mod disk;
mod hyperboloid;
mod loop_subdiv;
mod mesh;
mod paraboloid;
mod plane;
mod sample;
pub mod sdf;
mod sphere;
mod triangle;
mod voxels;

pub use bilinear::{BilinearMesh, BilinearPatch, bilinear_point, intersect_bilinear};
pub use cone::Cone;
pub use cuboid::Cuboid;
pub use curve::{Curve, CurveBasis, CurveCommon, CurveDesc, CurveType, bezier_eval, bezier_piece};
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use hyperboloid::Hyperboloid;
pub use loop_subdiv::loop_subdivide;
pub use mesh::IndexedMesh;
pub use paraboloid::Paraboloid;
pub use plane::Plane;
pub use sample::ShapeSample;
pub use sdf::{Sdf, SdfFunction};
pub use sphere::Sphere;
pub use triangle::{
    Triangle, TriangleMesh, TriangleRay, intersect_triangle, intersect_triangle_with, is_degenerate,
};
pub use voxels::{BRICK, VoxelGrid, Voxels, srgb8_to_linear};

use crate::math::{Bounds3, Transform, Vec2, Vec3, cross, gamma};
use crate::ray::Ray;
use glam::{DMat4, DVec3};

/// The result of [`Shape::intersect`]: the distance along the ray and two shape-specific
/// values kept for [`Shape::interaction`] (barycentrics b₁, b₂ for triangles).
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

/// Every kind of shape lancer intersects.
///
/// Quadrics carry two 4×4 matrices each and are boxed, so that the enum stays the size of a
/// triangle (48 bytes rather than 320): scenes are mostly triangles, and the intersection loop
/// walks arrays of shapes.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A (partial) sphere.
    Sphere(Box<Sphere>),
    /// A (partial) disk or annulus.
    Disk(Box<Disk>),
    /// A (partial) open cylinder.
    Cylinder(Box<Cylinder>),
    /// A (partial) open cone.
    Cone(Box<Cone>),
    /// A (partial) paraboloid.
    Paraboloid(Box<Paraboloid>),
    /// A (partial) hyperboloid: a line segment swept around the z axis.
    Hyperboloid(Box<Hyperboloid>),
    /// A box, axis-aligned in object space (lancer extension).
    Box(Box<Cuboid>),
    /// An infinite plane (lancer extension).
    Plane(Box<Plane>),
    /// One triangle of a mesh.
    Triangle(Triangle),
    /// A voxel grid (lancer extension).
    Voxels(Box<Voxels>),
    /// A signed-distance object, sphere-traced (lancer extension).
    Sdf(Box<Sdf>),
    /// A piece of a curve (pbrt's `curve`).
    Curve(Curve),
    /// One patch of a bilinear mesh (pbrt's `bilinearmesh`).
    Bilinear(Box<BilinearPatch>),
}

impl Shape {
    /// World-space bounds (infinite for planes).
    pub fn bounds(&self) -> Bounds3 {
        match self {
            Shape::Sphere(s) => s.bounds(),
            Shape::Disk(s) => s.bounds(),
            Shape::Cylinder(s) => s.bounds(),
            Shape::Cone(s) => s.bounds(),
            Shape::Paraboloid(s) => s.bounds(),
            Shape::Hyperboloid(s) => s.bounds(),
            Shape::Box(s) => s.bounds(),
            Shape::Plane(_) => {
                Bounds3::new(Vec3::splat(f32::NEG_INFINITY), Vec3::splat(f32::INFINITY))
            }
            Shape::Triangle(t) => t.bounds(),
            Shape::Voxels(v) => v.bounds(),
            Shape::Sdf(s) => s.bounds(),
            Shape::Curve(c) => c.bounds(),
            Shape::Bilinear(b) => b.bounds(),
        }
    }

    /// True for shapes without finite bounds, which are kept out of the BVH.
    pub fn is_unbounded(&self) -> bool {
        matches!(self, Shape::Plane(_))
    }

    /// The nearest hit with `0 < t < ray.t_max`, if any (the course's "intersect the ray with
    /// an object").
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        self.intersect_with(ray, &TriangleRay::new(ray))
    }

    /// [`Shape::intersect`] with `pre` = [`TriangleRay::new`] of the same ray, computed once
    /// for all the shapes a ray is tested against.
    #[inline]
    pub fn intersect_with(&self, ray: &Ray, pre: &TriangleRay) -> Option<ShapeHit> {
        match self {
            Shape::Triangle(t) => t.intersect(ray, pre),
            Shape::Sphere(s) => s.intersect(ray),
            Shape::Disk(s) => s.intersect(ray),
            Shape::Cylinder(s) => s.intersect(ray),
            Shape::Cone(s) => s.intersect(ray),
            Shape::Paraboloid(s) => s.intersect(ray),
            Shape::Hyperboloid(s) => s.intersect(ray),
            Shape::Box(s) => s.intersect(ray),
            Shape::Plane(s) => s.intersect(ray),
            Shape::Voxels(v) => v.intersect(ray),
            Shape::Sdf(s) => s.intersect(ray),
            Shape::Curve(c) => c.intersect(ray),
            Shape::Bilinear(b) => b.intersect(ray),
        }
    }

    /// The full interaction for a hit found by [`Shape::intersect`] on the same ray.
    pub fn interaction(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        meshes: &[TriangleMesh],
    ) -> SurfaceInteraction {
        match self {
            Shape::Sphere(s) => s.interaction(ray, hit),
            Shape::Disk(s) => s.interaction(ray, hit),
            Shape::Cylinder(s) => s.interaction(ray, hit),
            Shape::Cone(s) => s.interaction(ray, hit),
            Shape::Paraboloid(s) => s.interaction(ray, hit),
            Shape::Hyperboloid(s) => s.interaction(ray, hit),
            Shape::Box(s) => s.interaction(ray, hit),
            Shape::Plane(s) => s.interaction(ray, hit),
            Shape::Triangle(t) => t.interaction(ray, hit, &meshes[t.mesh as usize]),
            Shape::Sdf(s) => s.interaction(ray, hit),
            Shape::Curve(c) => c.interaction(ray, hit),
            Shape::Bilinear(b) => b.interaction(ray, hit),
            Shape::Voxels(v) => v.interaction(ray, hit),
        }
    }

    /// The reflectance the shape itself gives a hit found by [`Shape::intersect`], which a
    /// `diffuse` material uses instead of its own: a voxel's palette colour. `None` for
    /// every other shape.
    #[inline]
    pub fn hit_albedo(&self, hit: &ShapeHit) -> Option<crate::math::Rgb> {
        match self {
            Shape::Voxels(v) => Some(v.hit_albedo(hit)),
            _ => None,
        }
    }
}
