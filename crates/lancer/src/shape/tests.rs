//! The family's operations through [`Shape`]: world areas, placed samples, triangles.

use super::*;
use crate::math::Vec2;
use crate::math::{PackedVec3, Transform, Vec3};
use crate::ray::Ray;
use crate::shape::{
    Cone, Cuboid, Cylinder, Disk, Hyperboloid, Paraboloid, Placement, Plane, Sphere, Triangle,
};
use std::f64::consts::PI;

mod normal_derivatives;

#[test]
fn world_areas_scale_by_the_placement() {
    // Scaled by 2 about (5, 0, 0): every area ×4.
    let pl = Placement::new(
        Transform::translate(Vec3::new(5.0, 0.0, 0.0))
            * Transform::scale(Vec3::splat(2.0)).unwrap(),
        false,
    );
    let cases: Vec<(Shape, f64)> = vec![
        // 4πr², r = 1.
        (
            Shape::Sphere(Box::new(Sphere::new(pl, 1.0, -1.0, 1.0, 360.0))),
            4.0 * PI,
        ),
        // πr², r = 1.
        (
            Shape::Disk(Box::new(Disk::new(pl, 0.0, 1.0, 0.0, 360.0))),
            PI,
        ),
        // 2πr·h = 2π·1·2.
        (
            Shape::Cylinder(Box::new(Cylinder::new(pl, 1.0, -1.0, 1.0, 360.0))),
            4.0 * PI,
        ),
        // πr·√(h² + r²) = π·√2 for r = h = 1.
        (
            Shape::Cone(Box::new(Cone::new(pl, 1.0, 1.0, 360.0))),
            PI * 2f64.sqrt(),
        ),
        // π/6·(5√5 − 1).
        (
            Shape::Paraboloid(Box::new(Paraboloid::new(pl, 1.0, 0.0, 1.0, 360.0))),
            PI / 6.0 * (5.0 * 5f64.sqrt() - 1.0),
        ),
        // A cylinder r = 1, h = 2 as a hyperboloid: 4π.
        (
            Shape::Hyperboloid(Box::new(
                Hyperboloid::new(
                    pl,
                    Vec3::new(1.0, 0.0, -1.0),
                    Vec3::new(1.0, 0.0, 1.0),
                    360.0,
                )
                .unwrap(),
            )),
            4.0 * PI,
        ),
        // The unit cube: 6.
        (
            Shape::Box(Box::new(Cuboid::new(pl, Vec3::ZERO, Vec3::ONE))),
            6.0,
        ),
    ];
    for (i, (shape, object_area)) in cases.into_iter().enumerate() {
        let (got, want) = (shape.area() as f64, 4.0 * object_area);
        assert!(
            (got - want).abs() < 1e-5 * want,
            "case {i}: {got} vs {want}"
        );
    }
    let plane = Shape::Plane(Box::new(Plane::new(Vec3::ZERO, Vec3::Z).unwrap()));
    assert_eq!(plane.area(), 0.0);
    assert!(plane.sample_area(Vec2::splat(0.5), &[]).is_none());
}

#[test]
fn placed_samples_keep_the_intersection_orientation() {
    // A unit sphere at (0, 0, 10) with reverse orientation: u = (½, 0) is z = 0, φ = 0,
    // the object point (1, 0, 0), world (1, 0, 10), normal flipped inwards.
    let pl = Placement::new(Transform::translate(Vec3::new(0.0, 0.0, 10.0)), true);
    let s = Shape::Sphere(Box::new(Sphere::new(pl, 1.0, -1.0, 1.0, 360.0)));
    let smp = s.sample_area(Vec2::new(0.5, 0.0), &[]).unwrap();
    assert!(
        (smp.p - Vec3::new(1.0, 0.0, 10.0)).length() < 1e-6,
        "{}",
        smp.p
    );
    assert!((smp.n + Vec3::X).length() < 1e-6, "{}", smp.n);
}

#[test]
fn triangle_area_and_samples() {
    // (0, 0, 0), (2, 0, 0), (0, 2, 0): A = |(2, 0, 0) × (0, 2, 0)|/2 = 2; the geometric
    // normal (p₀ − p₂) × (p₁ − p₂) ∝ +z, −z when the mesh is reversed.
    let p = [
        PackedVec3::ZERO,
        PackedVec3::new(2.0, 0.0, 0.0),
        PackedVec3::new(0.0, 2.0, 0.0),
    ];
    let tri = Shape::Triangle(Triangle {
        p,
        mesh: 0,
        index: 0,
    });
    assert_eq!(tri.area(), 2.0);
    for flip in [false, true] {
        let mesh = TriangleMesh {
            positions: p.to_vec(),
            indices: vec![0, 1, 2],
            flip_normal: flip,
            ..Default::default()
        };
        for u in [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.9, 0.5),
            Vec2::new(0.5, 0.99),
        ] {
            let s = tri.sample_area(u, std::slice::from_ref(&mesh)).unwrap();
            assert!(s.p.z == 0.0 && s.p.x >= 0.0 && s.p.y >= 0.0 && s.p.x + s.p.y <= 2.0);
            assert_eq!(s.n, if flip { -Vec3::Z } else { Vec3::Z });
        }
    }
}

#[test]
fn a_hit_past_the_first_is_given_on_the_first_ray() {
    // A ray through the axis of each hollow shape meets it twice. The second hit, found on a
    // ray spawned from the first (the search past an alpha cut-out), given back on the first
    // ray by `hit_after`, is where the first ray's own far hit is: same distance, same point.
    let pl = Placement::new(
        Transform::translate(Vec3::new(0.25, -0.5, 0.125))
            * Transform::rotate(30.0, Vec3::X).unwrap(),
        false,
    );
    let shapes = [
        Shape::Sphere(Box::new(Sphere::new(pl, 1.0, -1.0, 1.0, 360.0))),
        Shape::Cylinder(Box::new(Cylinder::new(pl, 1.0, -1.0, 1.0, 360.0))),
        Shape::Paraboloid(Box::new(Paraboloid::new(pl, 1.0, 0.0, 1.0, 360.0))),
        Shape::Hyperboloid(Box::new(
            Hyperboloid::new(
                pl,
                Vec3::new(0.5, -0.5, -1.0),
                Vec3::new(0.5, 0.5, 1.0),
                360.0,
            )
            .unwrap(),
        )),
    ];
    for s in &shapes {
        // Across the shape, through a point just off its axis at mid-height.
        let centre = pl.to_world.point(Vec3::new(0.01, 0.02, 0.5));
        let o = centre + Vec3::new(-5.0, 0.3, 0.2);
        let ray = Ray::new(o, crate::math::normalize(centre - o));
        let pre = TriangleRay::new(&ray);
        let first = s.intersect_with(&ray, &pre).expect("near hit");
        let si = s.interaction(&ray, &first, &[]);
        let next_ray = si.spawn_ray(ray.d);
        let next = s
            .intersect_with(&next_ray, &TriangleRay::new(&next_ray))
            .expect("far hit");
        let on_ray = s.hit_after(&first, &next);
        let far = s.interaction(&ray, &on_ray, &[]);
        let direct = s.interaction(&next_ray, &next, &[]);
        assert!(
            (far.p - direct.p).length() < 1e-5 && (far.uv - direct.uv).length() < 1e-5,
            "{s:?}: {} {} vs {} {}",
            far.p,
            far.uv,
            direct.p,
            direct.uv
        );
        assert!(on_ray.t > first.t + 0.1, "{s:?}");
    }
}
