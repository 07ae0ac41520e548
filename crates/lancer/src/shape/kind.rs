//! What a shape kind provides, as two traits every kind's file implements: [`GeometryKind`] on
//! its description (the plain data a reader fills in: rules, pbrt name, the build into
//! primitives) and [`ShapeKind`] on its runtime primitive (bounds, intersection, area, area
//! sampling, power and memory share). The family's enums, [`super::Geometry`] and
//! [`super::Shape`], and their `match`es are written once, from the list in `shape/mod.rs`;
//! each arm calls one of these methods, statically.
//!
//! A leaf module beside `hit`, `mesh` and `placement`: the shape files use it, it uses no shape
//! file.

use super::hit::{ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::Placement;
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, PackedVec3, Rgb, Transform, Vec2};
use crate::ray::Ray;
use std::collections::HashSet;

/// Where the primitives of a shape go and what they need besides its description: its
/// placement (pbrt's CTM and `ReverseOrientation` at the shape) and the scene's world-space
/// triangle meshes, which a triangle mesh appends itself to.
pub struct Placing<'a> {
    /// Object space → world space.
    pub to_world: Transform,
    /// pbrt's `ReverseOrientation`.
    pub reverse_orientation: bool,
    /// The scene's world-space triangle meshes so far.
    pub meshes: &'a mut Vec<TriangleMesh>,
}

impl Placing<'_> {
    /// The placement of a shape intersected in object space (the quadrics, boxes, grids).
    pub fn placement(&self) -> Placement {
        Placement::new(self.to_world, self.reverse_orientation)
    }
}

/// A shape kind's description: plain data, object space.
pub trait GeometryKind {
    /// The runtime primitive the description becomes (its variant's payload in
    /// [`super::Shape`]).
    type Prim;

    /// The pbrt-v4 name of the kind (`Shape "…"`); lancer's extensions by their own names.
    fn pbrt_name(&self) -> &'static str;

    /// The rules without which the description means nothing: the first one broken, with the
    /// fields it is about (one message per rule, whoever asks: the readers and the build).
    fn validate(&self) -> Result<(), RuleError>;

    /// Why the kind cannot be an area light (it cannot be sampled by area), `None` when it can.
    fn emitter_refusal(&self) -> Option<&'static str> {
        None
    }

    /// True for the mesh kinds, whose rule errors the build reports as bad meshes.
    fn is_mesh(&self) -> bool {
        false
    }

    /// The world-space primitives of a description already validated, appended to `out` in
    /// the order that numbers them. Errors left are those only the constructors find (a
    /// degenerate placement).
    fn build(&self, at: &mut Placing<'_>, out: &mut impl Extend<Self::Prim>) -> Result<(), String>;
}

/// Bytes a primitive holds outside the scene's array of shapes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HeldBytes {
    /// Its own records: its box, what the box owns, shared segments (once).
    pub primitive: usize,
    /// Mesh arrays it shares with others (each mesh once).
    pub meshes: usize,
}

/// A shape kind's runtime primitive, world space. Every method has the meaning of the
/// [`super::Shape`] method of the same name.
pub trait ShapeKind {
    /// World-space bounds (infinite for an unbounded shape).
    fn bounds(&self) -> Bounds3;

    /// True for shapes without finite bounds, which are kept out of the BVH.
    fn is_unbounded(&self) -> bool {
        false
    }

    /// The nearest hit with `0 < t < ray.t_max`; `pre` is [`TriangleRay::new`] of `ray`.
    fn intersect(&self, ray: &Ray, pre: &TriangleRay) -> Option<ShapeHit>;

    /// The full interaction for a hit found by [`ShapeKind::intersect`] on the same ray.
    fn interaction(&self, ray: &Ray, hit: &ShapeHit, meshes: &[TriangleMesh])
    -> SurfaceInteraction;

    /// The hit `next`, found on a ray spawned from the hit `first` in the same direction (the
    /// search past an alpha cut-out), as a hit of `first`'s ray: at distance
    /// `first.t + next.t`, with `next`'s shape-specific values, which by default do not
    /// depend on the ray (barycentrics, patch or curve coordinates, a face). Kinds that keep
    /// the rounding residual of a double-precision distance there ([`super::placement`]'s
    /// `quadric_hit`) add the two distances in double precision instead.
    fn hit_after(&self, first: &ShapeHit, next: &ShapeHit) -> ShapeHit {
        ShapeHit {
            t: first.t + next.t,
            ..*next
        }
    }

    /// pbrt-v4's shading derivatives (∂n/∂u, ∂n/∂v among them) at a hit found by
    /// [`ShapeKind::intersect`] on the same ray, whose interaction is `si`: asked only by a bump
    /// map. By default those of a surface whose normal does not turn
    /// ([`ShadingDerivatives::flat`]).
    fn shading_derivatives(
        &self,
        _ray: &Ray,
        _hit: &ShapeHit,
        _meshes: &[TriangleMesh],
        si: &SurfaceInteraction,
    ) -> ShadingDerivatives {
        ShadingDerivatives::flat(si)
    }

    /// Surface area, world space (0 for shapes that cannot emit).
    fn area(&self) -> f32;

    /// A point uniform by area, with the geometric normal the intersection gives there;
    /// `None` for shapes that cannot be sampled.
    fn sample_area(&self, u: Vec2, meshes: &[TriangleMesh]) -> Option<ShapeSample>;

    /// The area pbrt-v4 divides an area light's power by: the world area, unless the kind
    /// says otherwise (pbrt-v4's quadrics use their object-space area).
    fn emission_area(&self) -> f32 {
        self.area()
    }

    /// The reflectance the shape itself gives a hit (a voxel's palette colour), `None` for
    /// most kinds.
    fn hit_albedo(&self, _hit: &ShapeHit) -> Option<Rgb> {
        None
    }

    /// World centre and radius when the primitive is a whole sphere (no cut, full sweep),
    /// which a light samples by the cone it subtends.
    fn whole_sphere(&self) -> Option<(PackedVec3, f32)> {
        None
    }

    /// Bytes held outside the array of shapes; `seen` holds the addresses of shared buffers
    /// already counted (for the whole scene).
    fn held_bytes(&self, _seen: &mut HashSet<usize>) -> HeldBytes {
        HeldBytes::default()
    }
}

/// A boxed primitive (the list boxes the large kinds, to keep [`super::Shape`] small): the
/// kind's own operations, and its box in its held bytes.
impl<T: ShapeKind> ShapeKind for Box<T> {
    #[inline]
    fn bounds(&self) -> Bounds3 {
        (**self).bounds()
    }
    #[inline]
    fn is_unbounded(&self) -> bool {
        (**self).is_unbounded()
    }
    #[inline]
    fn intersect(&self, ray: &Ray, pre: &TriangleRay) -> Option<ShapeHit> {
        (**self).intersect(ray, pre)
    }
    #[inline]
    fn interaction(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        meshes: &[TriangleMesh],
    ) -> SurfaceInteraction {
        (**self).interaction(ray, hit, meshes)
    }
    #[inline]
    fn shading_derivatives(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        meshes: &[TriangleMesh],
        si: &SurfaceInteraction,
    ) -> ShadingDerivatives {
        (**self).shading_derivatives(ray, hit, meshes, si)
    }
    #[inline]
    fn hit_after(&self, first: &ShapeHit, next: &ShapeHit) -> ShapeHit {
        (**self).hit_after(first, next)
    }
    #[inline]
    fn area(&self) -> f32 {
        (**self).area()
    }
    #[inline]
    fn sample_area(&self, u: Vec2, meshes: &[TriangleMesh]) -> Option<ShapeSample> {
        (**self).sample_area(u, meshes)
    }
    #[inline]
    fn emission_area(&self) -> f32 {
        (**self).emission_area()
    }
    #[inline]
    fn hit_albedo(&self, hit: &ShapeHit) -> Option<Rgb> {
        (**self).hit_albedo(hit)
    }
    #[inline]
    fn whole_sphere(&self) -> Option<(PackedVec3, f32)> {
        (**self).whole_sphere()
    }
    fn held_bytes(&self, seen: &mut HashSet<usize>) -> HeldBytes {
        let inner = (**self).held_bytes(seen);
        HeldBytes {
            primitive: size_of::<T>() + inner.primitive,
            ..inner
        }
    }
}

/// `Ok` when `v` is finite and positive, else the rule on `field` (named `what` in the message)
/// broken: the quadrics' radii and heights.
pub(crate) fn positive(
    v: f32,
    field: &'static [&'static str],
    what: &str,
) -> Result<(), RuleError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(RuleError::on(
            field,
            format!("{what} must be positive, got {v}"),
        ))
    }
}
