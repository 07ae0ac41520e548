//! Shapes: what a ray can hit. One file per shape; [`Shape`] is the closed set the accelerator
//! and the integrators match on (no trait objects in the hot loop).
//!
//! Intersection is split in two, as in PBRT: [`Shape::intersect`] finds the nearest parametric
//! distance `t` (and whatever the shape needs later, such as barycentrics) as cheaply as
//! possible; [`Shape::interaction`] then computes the full [`SurfaceInteraction`] (point, error
//! bounds, normals, (u, v), derivatives) once, for the closest hit only.
//!
//! The vocabulary every shape file shares lives in two leaf modules, re-exported here: `hit`
//! (the hit and interaction records, [`ShapeSample`]) and `placement` ([`Placement`] and the
//! quadrics' numeric helpers). This file only gathers the shapes into [`Shape`]; `sample`
//! adds its area and area sampling.

mod bilinear;
mod cone;
mod cuboid;
mod curve;
mod cylinder;
mod disk;
mod hit;
mod hyperboloid;
mod loop_subdiv;
mod mesh;
mod paraboloid;
mod placement;
mod plane;
mod sample;
pub mod sdf;
mod sphere;
#[cfg(test)]
mod testing;
mod triangle;
mod voxels;

pub use bilinear::{BilinearMesh, BilinearPatch, bilinear_point, intersect_bilinear};
pub use cone::Cone;
pub use cuboid::Cuboid;
pub use curve::{Curve, CurveBasis, CurveCommon, CurveDesc, CurveType, bezier_eval, bezier_piece};
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use hit::{Shading, ShapeHit, ShapeSample, SurfaceInteraction};
pub use hyperboloid::Hyperboloid;
pub use loop_subdiv::loop_subdivide;
pub use mesh::{IndexedMesh, RuleError};
pub use paraboloid::Paraboloid;
pub use placement::Placement;
pub use plane::Plane;
pub use sdf::{Sdf, SdfFunction};
pub use sphere::Sphere;
pub use triangle::{
    Triangle, TriangleFrame, TriangleMesh, TriangleRay, intersect_triangle,
    intersect_triangle_with, is_degenerate, triangle_interaction,
};
pub use voxels::{BRICK, VoxelGrid, Voxels, srgb8_to_linear};

use crate::math::{Bounds3, Vec3};
use crate::ray::Ray;

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
