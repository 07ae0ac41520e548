//! Shapes: what a ray can hit. A kind is a file: each kind's file holds its description (the
//! plain data a reader fills in, a payload of [`Geometry`]), its rules, its build into
//! primitives, and every operation of the family on those primitives (a payload of
//! [`Shape`]): bounds, intersection, area, area sampling, power and memory share, as the
//! two traits of `kind` ([`GeometryKind`], [`ShapeKind`]) state them. The one list below
//! makes both enums and their `match`es; dispatch is static (no trait objects in the hot
//! loop).
//!
//! Intersection is split in two, as in PBRT: [`Shape::intersect`] finds the nearest parametric
//! distance `t` (and whatever the shape needs later, such as barycentrics) as cheaply as
//! possible; [`Shape::interaction`] then computes the full [`SurfaceInteraction`] (point, error
//! bounds, normals, (u, v), derivatives) once, for the closest hit only. The normal's
//! derivatives, which only a bump map reads, come third and only when one asks
//! ([`Shape::shading_derivatives`]).
//!
//! The vocabulary every shape file shares lives in leaf modules, re-exported here: `hit` (the
//! hit and interaction records, [`ShapeSample`]), `placement` ([`Placement`] and the quadrics'
//! numeric helpers), `mesh` ([`IndexedMesh`], [`RuleError`]), `triangle_ray`
//! ([`TriangleRay`]) and `kind` (the two traits).
//!
//! Adding a kind: its file (description with [`GeometryKind`], primitive with
//! [`ShapeKind`]), its `mod` and `pub use` lines and one line in the list below, and its
//! reader in `lancer-scene` (`pbrt/shapes.rs` for its pbrt name).

mod bilinear;
mod cone;
mod cuboid;
mod curve;
mod cylinder;
mod disk;
mod displace;
mod hit;
mod hyperboloid;
mod kind;
mod loop_subdiv;
mod mesh;
mod paraboloid;
mod placement;
mod plane;
pub mod sdf;
mod sphere;
#[cfg(test)]
mod testing;
#[cfg(test)]
mod tests;
mod triangle;
mod triangle_ray;
mod voxels;

pub use bilinear::{BilinearMesh, BilinearPatch, bilinear_point, intersect_bilinear};
pub use cone::{Cone, ConeDesc};
pub use cuboid::{BoxDesc, Cuboid};
pub use curve::{Curve, CurveBasis, CurveCommon, CurveDesc, CurveType, bezier_eval, bezier_piece};
pub use cylinder::{Cylinder, CylinderDesc};
pub use disk::{Disk, DiskDesc};
pub use displace::{
    DisplaceError, MAX_DISPLACED_TRIANGLES, Refinement, displace, refine, vertex_normals,
};
pub use hit::{Shading, ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
pub use hyperboloid::{Hyperboloid, HyperboloidDesc};
pub use kind::{GeometryKind, HeldBytes, Placing, ShapeKind};
pub use loop_subdiv::loop_subdivide;
pub use mesh::{IndexedMesh, RuleError, TriangleMesh};
pub use paraboloid::{Paraboloid, ParaboloidDesc};
pub use placement::Placement;
pub use plane::{Plane, PlaneDesc};
pub use sdf::{Sdf, SdfDesc, SdfFunction};
pub use sphere::{Sphere, SphereDesc};
pub use triangle::{
    Triangle, TriangleFrame, intersect_triangle, intersect_triangle_with, is_degenerate,
    mesh_triangles, triangle_interaction, triangle_normal_derivatives,
    triangle_shading_derivatives,
};
pub use triangle_ray::TriangleRay;
pub use voxels::{BRICK, VoxelGrid, Voxels, srgb8_to_linear};

use crate::math::{Bounds3, PackedVec3, Vec2};
use crate::ray::Ray;
use std::collections::HashSet;
use std::sync::Arc;

/// Makes the family from its list: [`Geometry`] (descriptions) and [`Shape`] (primitives),
/// one variant each per kind in the list's order, and the macros that match on them
/// (`shape_dispatch!`, `geometry_dispatch!`, in the manner of the BxDFs' `dispatch!`), and the
/// build of a description into its primitives' variant. `$d` is a `$` passed in, so that the
/// macros made here can have variables of their own.
macro_rules! shape_family {
    ($d:tt $(
        $(#[$doc:meta])*
        $geometry:ident($desc:ty) => $shape:ident($prim:ty);
    )*) => {
        /// A shape's geometry, in object space: the description of one kind (see each kind's
        /// file), as the readers make it.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Geometry {
            $( $(#[$doc])* $geometry($desc), )*
        }

        /// Every kind of shape lancer intersects: one primitive of a built scene.
        ///
        /// Quadrics carry two 4×4 matrices each and are boxed, so that the enum stays the size
        /// of a triangle (48 bytes rather than 320): scenes are mostly triangles, and the
        /// intersection loop walks arrays of shapes.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Shape {
            $( $(#[$doc])* $shape($prim), )*
        }

        /// `$body` with `$s` bound to the primitive of `$x`, whatever its kind.
        macro_rules! shape_dispatch {
            ($d x:expr, $d s:ident => $d body:expr) => {
                match $d x { $( Shape::$shape($d s) => $d body, )* }
            };
        }

        /// `$body` with `$g` bound to the description of `$x`, whatever its kind.
        macro_rules! geometry_dispatch {
            ($d x:expr, $d g:ident => $d body:expr) => {
                match $d x { $( Geometry::$geometry($d g) => $d body, )* }
            };
        }

        impl Geometry {
            /// The world-space primitives of a geometry already validated, placed by `at`
            /// (a triangle mesh also appends its world-space mesh to `at.meshes`), appended
            /// to `out`. Errors left are those only the constructors find.
            pub fn build(&self, at: &mut Placing<'_>, out: &mut Vec<Shape>) -> Result<(), String> {
                match self {
                    $( Geometry::$geometry(g) => GeometryKind::build(g, at, &mut AsShapes {
                        out: &mut *out,
                        variant: Shape::$shape,
                    }), )*
                }
            }
        }
    };
}

shape_family! {$
    /// pbrt's `sphere`: a (partial) sphere.
    Sphere(SphereDesc) => Sphere(Box<Sphere>);
    /// pbrt's `disk`: a (partial) disk or annulus.
    Disk(DiskDesc) => Disk(Box<Disk>);
    /// pbrt's `cylinder`: a (partial) open cylinder.
    Cylinder(CylinderDesc) => Cylinder(Box<Cylinder>);
    /// pbrt's `cone`: a (partial) open cone.
    Cone(ConeDesc) => Cone(Box<Cone>);
    /// pbrt's `paraboloid`: a (partial) paraboloid.
    Paraboloid(ParaboloidDesc) => Paraboloid(Box<Paraboloid>);
    /// pbrt's `hyperboloid`: a line segment swept around the z axis.
    Hyperboloid(HyperboloidDesc) => Hyperboloid(Box<Hyperboloid>);
    /// lancer's `box`: a box, axis-aligned in object space.
    Box(BoxDesc) => Box(Box<Cuboid>);
    /// lancer's infinite `plane`.
    Plane(PlaneDesc) => Plane(Box<Plane>);
    /// A triangle mesh (`trianglemesh`, `plymesh`, `objmesh`, glTF, …), one triangle a
    /// primitive.
    TriangleMesh(Arc<TriangleMesh>) => Triangle(Triangle);
    /// lancer's `voxels`: a voxel grid (shared, never copied per voxel).
    Voxels(Arc<VoxelGrid>) => Voxels(Box<Voxels>);
    /// lancer's `sdf`: a signed-distance object, sphere-traced.
    Sdf(SdfDesc) => Sdf(Box<Sdf>);
    /// pbrt's `curve`: a spline with a width, split into pieces when the scene is built.
    Curve(Arc<CurveDesc>) => Curve(Curve);
    /// pbrt's `bilinearmesh`: bilinear patches, four vertex indices each, one a primitive.
    BilinearMesh(Arc<BilinearMesh>) => Bilinear(Box<BilinearPatch>);
}

/// A kind's primitives appended to the scene's list as their variant of [`Shape`].
struct AsShapes<'a, P> {
    out: &'a mut Vec<Shape>,
    variant: fn(P) -> Shape,
}

impl<P> Extend<P> for AsShapes<'_, P> {
    fn extend<I: IntoIterator<Item = P>>(&mut self, iter: I) {
        self.out.extend(iter.into_iter().map(self.variant));
    }
}

impl Shape {
    /// World-space bounds (infinite for planes).
    pub fn bounds(&self) -> Bounds3 {
        shape_dispatch!(self, s => ShapeKind::bounds(s))
    }

    /// True for shapes without finite bounds, which are kept out of the BVH.
    pub fn is_unbounded(&self) -> bool {
        shape_dispatch!(self, s => ShapeKind::is_unbounded(s))
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
        shape_dispatch!(self, s => ShapeKind::intersect(s, ray, pre))
    }

    /// The full interaction for a hit found by [`Shape::intersect`] on the same ray.
    pub fn interaction(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        meshes: &[TriangleMesh],
    ) -> SurfaceInteraction {
        shape_dispatch!(self, s => ShapeKind::interaction(s, ray, hit, meshes))
    }

    /// The hit `next` of a ray spawned from the hit `first` in the same direction, as a hit of
    /// `first`'s ray ([`ShapeKind::hit_after`]).
    #[inline]
    pub fn hit_after(&self, first: &ShapeHit, next: &ShapeHit) -> ShapeHit {
        shape_dispatch!(self, s => ShapeKind::hit_after(s, first, next))
    }

    /// pbrt-v4's shading ∂p/∂u, ∂p/∂v, ∂n/∂u, ∂n/∂v at a hit found by [`Shape::intersect`] on
    /// the same ray, whose interaction is `si`: what a bump map reads, computed only when one
    /// asks (the intersection and the interaction never pay for it).
    #[inline]
    pub fn shading_derivatives(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        meshes: &[TriangleMesh],
        si: &SurfaceInteraction,
    ) -> ShadingDerivatives {
        shape_dispatch!(self, s => ShapeKind::shading_derivatives(s, ray, hit, meshes, si))
    }

    /// The reflectance the shape itself gives a hit found by [`Shape::intersect`], which a
    /// `diffuse` material uses instead of its own: a voxel's palette colour. `None` for
    /// every other shape.
    #[inline]
    pub fn hit_albedo(&self, hit: &ShapeHit) -> Option<crate::math::Rgb> {
        shape_dispatch!(self, s => ShapeKind::hit_albedo(s, hit))
    }

    /// Surface area, world space (0 for the shapes that cannot emit: planes, sdf objects,
    /// voxel grids). Quadrics are scaled from object space; like pbrt, their world area
    /// assumes the transform scales uniformly.
    pub fn area(&self) -> f32 {
        shape_dispatch!(self, s => ShapeKind::area(s))
    }

    /// A point uniform by area on the shape (density 1/A), with the geometric normal the
    /// intersection code gives at that point, which decides the side an area light emits
    /// from; `None` for planes, voxel grids, SDF objects and curves (which pbrt-v4 cannot
    /// sample either).
    pub fn sample_area(&self, u: Vec2, meshes: &[TriangleMesh]) -> Option<ShapeSample> {
        shape_dispatch!(self, s => ShapeKind::sample_area(s, u, meshes))
    }

    /// The area pbrt-v4 divides an area light's power by: the object-space area of a quadric
    /// (pbrt-v4's `Sphere::Area`, `Disk::Area` and `Cylinder::Area` ignore the
    /// transformation; lancer's other quadrics follow them), the world-space area of anything
    /// else (a triangle, a bilinear patch).
    pub fn emission_area(&self) -> f32 {
        shape_dispatch!(self, s => ShapeKind::emission_area(s))
    }

    /// The world centre and radius of a shape that is a whole sphere (no cut, full sweep).
    pub fn whole_sphere(&self) -> Option<(PackedVec3, f32)> {
        shape_dispatch!(self, s => ShapeKind::whole_sphere(s))
    }

    /// Bytes the primitive holds outside the scene's array of shapes (its box, what it owns,
    /// shared buffers the first time `seen` meets them).
    pub fn held_bytes(&self, seen: &mut HashSet<usize>) -> HeldBytes {
        shape_dispatch!(self, s => ShapeKind::held_bytes(s, seen))
    }
}

impl Geometry {
    /// The pbrt-v4 name of this shape (`Shape "…"`); lancer's extensions by their own names
    /// (`box`, `plane`, `voxels`, `sdf`).
    pub fn pbrt_name(&self) -> &'static str {
        geometry_dispatch!(self, g => GeometryKind::pbrt_name(g))
    }

    /// Checks the rules without which the geometry means nothing, and returns the first one
    /// broken (one message per rule, the same whoever asks: the scene readers and
    /// [`crate::Scene::build`]), with the fields it is about; each kind's rules are in its
    /// file.
    pub fn validate(&self) -> Result<(), RuleError> {
        geometry_dispatch!(self, g => GeometryKind::validate(g))
    }

    /// The rule on emission: an sdf shape, a curve or a voxel grid cannot be an area light
    /// (none of them can be sampled by area). Checked by
    /// [`crate::scene::desc::ShapeDesc::validate`] when the shape emits, and by readers for
    /// the shapes that would.
    pub fn validate_emitter(&self) -> Result<(), RuleError> {
        match geometry_dispatch!(self, g => GeometryKind::emitter_refusal(g)) {
            Some(refusal) => Err(RuleError::on(&[], refusal)),
            None => Ok(()),
        }
    }

    /// True for the mesh geometries, whose errors [`crate::Scene::build`] reports as
    /// [`crate::scene::BuildError::BadMesh`].
    pub fn is_mesh(&self) -> bool {
        geometry_dispatch!(self, g => GeometryKind::is_mesh(g))
    }
}
