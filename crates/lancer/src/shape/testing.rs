//! Helpers of the shapes' unit tests (a leaf module: it uses no shape).

use super::placement::Placement;
use crate::math::{Transform, Vec3};
use crate::ray::Ray;
use glam::DVec3;

/// The identity placement: object space is world space, normals as the shape defines them.
pub(crate) fn identity() -> Placement {
    Placement::new(Transform::IDENTITY, false)
}

/// Asserts that `got` is within `tol` of `want` on every axis.
#[track_caller]
pub(crate) fn assert_near(got: Vec3, want: Vec3, tol: f32) {
    assert!(
        (got - want).abs().max_element() <= tol,
        "{got} but expected {want} (± {tol})"
    );
}

/// Asserts that `got` is within `rel`·|want| of `want`.
#[track_caller]
pub(crate) fn assert_rel(got: f32, want: f64, rel: f64) {
    assert!(
        (got as f64 - want).abs() <= rel * want.abs(),
        "{got} but expected {want} (± {rel} relative)"
    );
}

/// Asserts that rays aimed at `p` along the surface normal `grad`, from 0.3 away on either
/// side, hit nothing within 10⁻² of it (`hit_point` gives the hit point of a ray, if any):
/// for points that satisfy a shape's implicit equation but lie beyond one of its cuts.
#[track_caller]
pub(crate) fn assert_cut_away(p: DVec3, grad: DVec3, hit_point: impl Fn(&Ray) -> Option<Vec3>) {
    let n = grad.normalize();
    for side in [1.0, -1.0] {
        let o = (p + 0.3 * side * n).as_vec3a();
        let ray = Ray::new(o, p.as_vec3a() - o);
        if let Some(q) = hit_point(&ray) {
            assert!(
                (q.as_dvec3() - p).length() > 1e-2,
                "hit at {q}, beyond the cut at {p}"
            );
        }
    }
}
