//! Shapes moving inside an object definition (`ObjectBegin` with an animated shape), as pbrt-v4
//! has them: each such shape moves by its own animated transformation A(t) in the object, and
//! every instance T places it, so in the world it stands at T·A(t).
//!
//! lancer keeps them out of the object's (static) acceleration structure and makes each instance
//! of them a moving shape of the world, moving by the animated transformation from T·A(t₀) to
//! T·A(t₁). That is T·A(t) exactly when T is a similarity (a rotation, a uniform scale and a
//! translation): the decomposed interpolation of translation, rotation and scale commutes with
//! them. A moving instance of such an object would move by T(t)·A(t), which no single animated
//! transformation gives: there (and for a non-uniform T) lancer warns.

use super::Builder;
use crate::error::Location;
use lancer::math::{AnimatedTransform, Transform};
use lancer::scene::desc::MovingShapeDesc;

impl Builder {
    /// The moving shapes of `object` placed by the instance transformation `ctm`, added to the
    /// scene's moving shapes.
    pub(super) fn place_moving_object_shapes(
        &mut self,
        object: u32,
        ctm: &AnimatedTransform,
        loc: &Location,
    ) {
        let shapes: Vec<MovingShapeDesc> = self
            .object_moving
            .iter()
            .filter(|(o, _)| *o == object)
            .map(|(_, m)| m.clone())
            .collect();
        if shapes.is_empty() {
            return;
        }
        let t = *ctm.start();
        if ctm.is_animated() || !is_similarity(&t) {
            self.warn_once(
                "object-motion",
                loc,
                "this instance moves or scales unevenly and its object holds moving shapes: \
                 lancer uses the shapes' motion under the instance's start pose",
            );
        }
        for m in shapes {
            let [t0, t1] = m.world_from_object.times();
            self.desc.motion.shapes.push(MovingShapeDesc {
                world_from_object: AnimatedTransform::new(
                    t * *m.world_from_object.start(),
                    t0,
                    t * *m.world_from_object.end(),
                    t1,
                ),
                shape: m.shape,
            });
        }
    }
}

/// Whether `t`'s linear part is a rotation (or reflection) times a uniform scale: its columns
/// orthogonal and of one length (relative tolerance 1e-4).
fn is_similarity(t: &Transform) -> bool {
    let m = t.m;
    let col = |j: usize| [m.col(j).x, m.col(j).y, m.col(j).z];
    let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let (a, b, c) = (col(0), col(1), col(2));
    let s = dot(a, a);
    let tol = 1e-4 * s.max(f32::MIN_POSITIVE);
    (dot(b, b) - s).abs() <= tol
        && (dot(c, c) - s).abs() <= tol
        && dot(a, b).abs() <= tol
        && dot(a, c).abs() <= tol
        && dot(b, c).abs() <= tol
}

#[cfg(test)]
mod tests {
    use super::*;
    use lancer::math::Vec3;

    #[test]
    fn similarities() {
        let r = Transform::rotate(30.0, Vec3::new(0.0, 1.0, 1.0)).unwrap();
        let s = Transform::scale(Vec3::splat(2.0)).unwrap();
        let tr = Transform::translate(Vec3::new(1.0, 2.0, 3.0));
        assert!(is_similarity(&(tr * r * s)));
        let squash = Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap();
        assert!(!is_similarity(&(r * squash)));
    }
}
