//! Where a scene's caustics can start: the surfaces that may scatter light specularly, as
//! `path` with `caustics` aims its light paths at them ([`crate::integrator::caustics`]).

use super::Scene;
use crate::math::{Bounds3, Vec3};

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

impl Scene {
    /// Where the surfaces that may scatter specularly are, found once (a pass over the
    /// primitives and triangles): the sphere bounding them, [`Casters::Anywhere`] when one of
    /// them is unbounded, instanced or moving (their geometry is bounded as a whole).
    pub fn caustic_casters(&self) -> Casters {
        *self.casters.get_or_init(|| self.find_casters())
    }

    fn find_casters(&self) -> Casters {
        let specular = |prim: u32| {
            self.materials[self.prims[prim as usize].material as usize].may_be_specular()
        };
        let mut b = Bounds3::EMPTY;
        for (i, s) in self.shapes.iter().enumerate() {
            if specular(i as u32) {
                if s.is_unbounded() {
                    return Casters::Anywhere;
                }
                b = b.union(&s.bounds());
            }
        }
        for slot in 0..self.tris.len() as u32 {
            if specular(self.tris.prim(slot)) {
                for v in self.tris.vertices(slot) {
                    b = b.union_point(v);
                }
            }
        }
        if !self.instances.is_empty() || self.motion.is_some() {
            return Casters::Anywhere;
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
}
