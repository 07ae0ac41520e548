//! The animated transform against hand-computed poses, and its motion bounds against sampled
//! ones.

use super::*;
use crate::sampling::Pcg32;

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}

/// `m · m⁻¹ = I`: the interpolated inverse is the inverse.
fn inverse_ok(t: &Transform) -> bool {
    (t.m * t.m_inv).abs_diff_eq(Mat4::IDENTITY, 1e-5)
}

#[test]
fn a_translation_moves_linearly_and_clamps_outside_the_times() {
    let a = AnimatedTransform::new(
        Transform::translate(Vec3::new(1.0, 0.0, 0.0)),
        2.0,
        Transform::translate(Vec3::new(3.0, 4.0, -6.0)),
        4.0,
    );
    assert!(a.is_animated());
    // A quarter of the way (time 2.5 of [2, 4]): (1, 0, 0) + ¼ (2, 4, −6).
    let t = a.interpolate(2.5);
    assert!(close(t.point(Vec3::ZERO), Vec3::new(1.5, 1.0, -1.5)));
    assert!(inverse_ok(&t));
    // Before the start and after the end: the ends themselves, bit for bit.
    assert_eq!(a.interpolate(-1.0), *a.start());
    assert_eq!(a.interpolate(2.0), *a.start());
    assert_eq!(a.interpolate(9.0), *a.end());
}

#[test]
fn a_quarter_turn_is_an_eighth_turn_halfway() {
    let a = AnimatedTransform::new(
        Transform::IDENTITY,
        0.0,
        Transform::rotate(90.0, Vec3::Z).unwrap(),
        1.0,
    );
    let t = a.interpolate(0.5);
    let h = std::f32::consts::FRAC_1_SQRT_2;
    // Rotate 45° about z: x → (√½, √½, 0), y → (−√½, √½, 0); lengths kept (no shrinking, as
    // entry-by-entry interpolation of the matrices would give).
    assert!(close(t.vector(Vec3::X), Vec3::new(h, h, 0.0)));
    assert!(close(t.vector(Vec3::Y), Vec3::new(-h, h, 0.0)));
    assert!(close(t.vector(Vec3::Z), Vec3::Z));
    assert!(inverse_ok(&t));
    // A quarter of the way: 22.5°.
    let q = a.interpolate(0.25).vector(Vec3::X);
    let c = 22.5f32.to_radians();
    assert!(close(q, Vec3::new(c.cos(), c.sin(), 0.0)));
}

#[test]
fn a_scale_interpolates_each_factor() {
    let a = AnimatedTransform::new(
        Transform::IDENTITY,
        0.0,
        Transform::scale(Vec3::new(3.0, 1.0, 2.0)).unwrap(),
        1.0,
    );
    let t = a.interpolate(0.5);
    assert!(close(t.point(Vec3::ONE), Vec3::new(2.0, 1.0, 1.5)));
    assert!(inverse_ok(&t));
}

#[test]
fn decomposition_recovers_translation_rotation_and_scale() {
    let m = Transform::translate(Vec3::new(1.0, 2.0, 3.0))
        * Transform::rotate(30.0, Vec3::new(1.0, 1.0, 0.0)).unwrap()
        * Transform::scale(Vec3::new(2.0, 3.0, 4.0)).unwrap();
    let (t, r, s) = decompose(&m.m);
    assert!(close(t, Vec3::new(1.0, 2.0, 3.0)));
    let q = Quat::from_axis_angle(
        glam::Vec3::new(1.0, 1.0, 0.0).normalize(),
        30f32.to_radians(),
    );
    assert!(r.dot(q).abs() > 1.0 - 1e-6, "{r} vs {q}");
    assert!(s.abs_diff_eq(Mat3A::from_diagonal(glam::Vec3::new(2.0, 3.0, 4.0)), 1e-5));
}

#[test]
fn a_mirrored_transform_keeps_its_mirror_while_moving() {
    let mirror = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap();
    let a = AnimatedTransform::new(
        mirror,
        0.0,
        Transform::translate(Vec3::new(2.0, 0.0, 0.0)) * mirror,
        1.0,
    );
    let t = a.interpolate(0.5);
    // Halfway: Translate(1, 0, 0) · Scale(−1, 1, 1).
    assert!(close(
        t.point(Vec3::new(1.0, 2.0, 3.0)),
        Vec3::new(0.0, 2.0, 3.0)
    ));
    assert!(inverse_ok(&t));
}

#[test]
fn motion_bounds_hold_every_sampled_pose_and_stay_tight() {
    let mut rng = Pcg32::new(7, 0);
    let mut v = || Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
    for _ in 0..20 {
        let start = Transform::translate(v() * 4.0 - 2.0)
            * Transform::rotate(360.0 * v().x, v() - 0.5).unwrap()
            * Transform::scale(v() + 0.5).unwrap();
        let end = Transform::translate(v() * 4.0 - 2.0)
            * Transform::rotate(360.0 * v().x, v() - 0.5).unwrap()
            * Transform::scale(v() + 0.5).unwrap();
        let a = AnimatedTransform::new(start, 0.0, end, 1.0);
        let b = Bounds3::new(v() - 1.0, v() + 0.1);
        let mb = a.motion_bounds(&b);
        let mut seen = Bounds3::EMPTY;
        for k in 0..=400 {
            let t = a.interpolate(k as f32 / 400.0);
            for i in 0..8 {
                let p = t.point(b.corner(i));
                assert!(mb.contains(p), "{p} outside {mb:?}");
                seen = seen.union_point(p);
            }
            let inner = b.min + (b.max - b.min) * v();
            assert!(mb.contains(t.point(inner)));
        }
        // Tight: no side more than 10 % of the swept extent beyond what the poses reach.
        let slack = (mb.max - seen.max).max(seen.min - mb.min).max_element();
        assert!(slack < 0.1 * seen.diagonal().max_element(), "slack {slack}");
    }
}

#[test]
fn motion_bounds_without_rotation_are_the_ends_boxes() {
    let a = AnimatedTransform::new(
        Transform::IDENTITY,
        0.0,
        Transform::translate(Vec3::new(0.0, 5.0, 0.0)),
        1.0,
    );
    let b = Bounds3::new(Vec3::ZERO, Vec3::ONE);
    let mb = a.motion_bounds(&b);
    assert_eq!(mb, Bounds3::new(Vec3::ZERO, Vec3::new(1.0, 6.0, 1.0)));
    assert_eq!(
        AnimatedTransform::fixed(Transform::IDENTITY).motion_bounds(&b),
        b
    );
}
