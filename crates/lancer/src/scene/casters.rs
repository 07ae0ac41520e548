//! Where a scene's caustics can start: the surfaces that may scatter light specularly, as
//! `path` with `caustics` aims its light paths at them ([`crate::integrator::caustics`]).

use super::prim::PrimInfo;
use super::tris::SceneTris;
use crate::material::Material;
use crate::math::{Bounds3, Vec3};
use crate::shape::Shape;

/// The surfaces of a scene that may scatter specularly ([`crate::material::Material::may_be_specular`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Casters {
    /// None: no caustics.
    None,
    /// All within this sphere (centre, radius).
    Within(Vec3, f32),
    /// Some without bounds (an infinite plane), or too many to bound cheaply: anywhere.
    Anywhere,
}

/// Where the surfaces of these primitives (`shapes` and their records `prims`, the plain
/// meshes' triangles `tris`) that may scatter specularly under `materials` are: the sphere
/// bounding them, [`Casters::Anywhere`] when one of them is unbounded or when the scene has
/// instanced or moving geometry (`bounded_whole`: bounded as a whole only), a pass over the
/// primitives and triangles.
pub(super) fn find(
    shapes: &[Shape],
    prims: &[PrimInfo],
    tris: &SceneTris,
    materials: &[Material],
    bounded_whole: bool,
) -> Casters {
    if bounded_whole {
        return Casters::Anywhere;
    }
    let specular = |prim: u32| materials[prims[prim as usize].material as usize].may_be_specular();
    let mut b = Bounds3::EMPTY;
    for (i, s) in shapes.iter().enumerate() {
        if specular(i as u32) {
            if s.is_unbounded() {
                return Casters::Anywhere;
            }
            b = b.union(&s.bounds());
        }
    }
    for slot in 0..tris.len() as u32 {
        if specular(tris.prim(slot)) {
            for v in tris.vertices(slot) {
                b = b.union_point(v);
            }
        }
    }
    if b.is_empty() {
        return Casters::None;
    }
    let (c, r) = b.bounding_sphere();
    if c.is_finite() && r.is_finite() {
        Casters::Within(c, r)
    } else {
        Casters::Anywhere
    }
}
