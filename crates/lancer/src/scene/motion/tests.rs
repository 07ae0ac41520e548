//! Moving shapes, instances and cameras hit where their pose at the ray's time puts them.

use super::*;
use crate::Scene;
use crate::camera::Camera;
use crate::math::{Vec2, Vec3};
use crate::scene::desc::{
    CameraDesc, InstanceDesc, MotionDesc, MovingInstanceDesc, MovingShapeDesc,
};
use crate::shape::SphereDesc;
use std::sync::Arc;

fn shape(geometry: Geometry, material: u32) -> ShapeDesc {
    ShapeDesc {
        medium_interface: None,
        geometry,
        object_to_world: Transform::IDENTITY,
        reverse_orientation: false,
        material,
        area_light: None,
        alpha: None,
    }
}

fn unit_sphere() -> Geometry {
    Geometry::Sphere(SphereDesc {
        radius: 1.0,
        z_min: -1.0,
        z_max: 1.0,
        phi_max: 360.0,
    })
}

/// The square [−1, 1]² in the plane z = 0: two triangles.
fn square() -> Geometry {
    let mut m = TriangleMesh::default();
    for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        m.positions.push(Vec3::new(x, y, 0.0).into());
    }
    m.indices.extend([0, 1, 2, 0, 2, 3]);
    Geometry::TriangleMesh(Arc::new(m))
}

fn moving(start: Transform, end: Transform) -> AnimatedTransform {
    AnimatedTransform::new(start, 0.0, end, 1.0)
}

fn scene_with(motion: MotionDesc, desc: SceneDesc) -> Scene {
    Scene::build(&SceneDesc {
        materials: vec![Default::default(); 3],
        motion,
        ..desc
    })
    .unwrap()
}

/// The hit of a ray from `o` along `d` at `time`: (t, p, n, record's material).
fn hit_at(scene: &Scene, o: Vec3, d: Vec3, time: f32) -> Option<(f32, Vec3, Vec3, u32)> {
    let r = Ray::new(o, d).at_time(time);
    let any = scene.intersect_p(&r);
    let h = scene.intersect(&r);
    assert_eq!(any, h.is_some(), "intersect_p agrees with intersect");
    assert!(
        h.is_none_or(|h| h.si.time == time),
        "the hit takes the ray's time"
    );
    h.map(|h| {
        let m = scene.prims[h.prim as usize].material;
        (h.si.t, h.si.p, h.si.n, m)
    })
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-4
}

#[test]
fn a_moving_sphere_is_hit_where_it_is_at_the_ray_time() {
    // The unit sphere moves from the origin to x = 4 over [0, 1].
    let m = MotionDesc {
        shapes: vec![MovingShapeDesc {
            shape: shape(unit_sphere(), 2),
            world_from_object: moving(
                Transform::IDENTITY,
                Transform::translate(Vec3::new(4.0, 0.0, 0.0)),
            ),
        }],
        ..MotionDesc::default()
    };
    let scene = scene_with(m, SceneDesc::default());
    let z = Vec3::Z;
    // Time 0: at the origin; the ray from z = −5 meets it at t = 4, point (0, 0, −1).
    let (t, p, n, mat) = hit_at(&scene, Vec3::new(0.0, 0.0, -5.0), z, 0.0).unwrap();
    assert!((t - 4.0).abs() < 1e-4 && close(p, Vec3::new(0.0, 0.0, -1.0)));
    assert!(close(n, -Vec3::Z) && mat == 2);
    assert!(hit_at(&scene, Vec3::new(4.0, 0.0, -5.0), z, 0.0).is_none());
    // Time 1: at x = 4.
    assert!(hit_at(&scene, Vec3::new(0.0, 0.0, -5.0), z, 1.0).is_none());
    let (t, p, n, _) = hit_at(&scene, Vec3::new(4.0, 0.0, -5.0), z, 1.0).unwrap();
    assert!((t - 4.0).abs() < 1e-4 && close(p, Vec3::new(4.0, 0.0, -1.0)));
    assert!(close(n, -Vec3::Z));
    // Halfway: at x = 2; a ray through x = 2.5 meets it at z = −√(1 − 0.25).
    let (_, p, _, _) = hit_at(&scene, Vec3::new(2.5, 0.0, -5.0), z, 0.5).unwrap();
    assert!(close(p, Vec3::new(2.5, 0.0, -(0.75f32).sqrt())));
    // The scene's bounds hold the whole sweep.
    assert!(scene.bounds().contains(Vec3::new(5.0, 1.0, 1.0)));
    assert!(scene.bounds().contains(Vec3::new(-1.0, -1.0, -1.0)));
}

#[test]
fn a_rotating_mesh_and_a_moving_instance_turn_and_move() {
    // A square turning a quarter about y: facing z at time 0, facing x at time 1.
    let turn = moving(
        Transform::IDENTITY,
        Transform::rotate(90.0, Vec3::Y).unwrap(),
    );
    let m = MotionDesc {
        shapes: vec![MovingShapeDesc {
            shape: shape(square(), 1),
            world_from_object: turn,
        }],
        ..MotionDesc::default()
    };
    let scene = scene_with(m, SceneDesc::default());
    let from_z = Vec3::new(0.5, 0.5, -5.0);
    let from_x = Vec3::new(-5.0, 0.5, 0.5);
    assert!(hit_at(&scene, from_z, Vec3::Z, 0.0).is_some());
    assert!(hit_at(&scene, from_x, Vec3::X, 0.0).is_none());
    // At time 1 the square spans z ∈ [−1, 1] in the plane x = 0 (Rotate 90 about y maps
    // x → −z).
    let (t, _, n, mat) = hit_at(&scene, from_x, Vec3::X, 1.0).unwrap();
    assert!((t - 5.0).abs() < 1e-4 && n.x.abs() > 0.999 && mat == 1);
    // At time 0.5 (45°) x maps to (1, 0, −1)/√2, so the square's plane is x = −z: the ray
    // along x at z = 0.5 meets it at x = −0.5.
    let (t, ..) = hit_at(&scene, from_x, Vec3::X, 0.5).unwrap();
    assert!((t - 4.5).abs() < 1e-4, "{t}");

    // The same square as an object, one still instance and one moving from y = 0 to y = 10.
    let object = ObjectDesc {
        name: "sq".into(),
        shapes: vec![shape(square(), 2)],
    };
    let lift = moving(
        Transform::translate(Vec3::new(10.0, 0.0, 0.0)),
        Transform::translate(Vec3::new(10.0, 10.0, 0.0)),
    );
    let m = MotionDesc {
        instances: vec![MovingInstanceDesc {
            object: 0,
            object_to_world: lift,
        }],
        ..MotionDesc::default()
    };
    let desc = SceneDesc {
        objects: vec![object],
        instances: vec![InstanceDesc {
            object: 0,
            object_to_world: Transform::IDENTITY,
        }],
        ..SceneDesc::default()
    };
    let scene = scene_with(m, desc);
    let at = |x: f32, y: f32| Vec3::new(x, y, -3.0);
    for time in [0.0, 0.5, 1.0] {
        // The still instance stays; the moving one is at y = 10 · time.
        assert!(hit_at(&scene, at(0.0, 0.0), Vec3::Z, time).is_some());
        let (t, p, _, mat) = hit_at(&scene, at(10.0, 10.0 * time), Vec3::Z, time).unwrap();
        assert!((t - 3.0).abs() < 1e-4 && close(p, Vec3::new(10.0, 10.0 * time, 0.0)));
        assert_eq!(mat, 2);
    }
    assert!(hit_at(&scene, at(10.0, 0.0), Vec3::Z, 1.0).is_none());
    assert!(hit_at(&scene, at(10.0, 10.0), Vec3::Z, 0.0).is_none());
}

/// Every kind of hit takes its ray's time, which the rays spawned from it inherit: a still
/// triangle (its record returned as the triangle writes it), a still sphere (completed by
/// `finish_hit`), a moving shape and an instance.
#[test]
fn every_kind_of_hit_carries_its_ray_time() {
    let at = |x: f32| Transform::translate(Vec3::new(x, 0.0, 0.0));
    let m = MotionDesc {
        shapes: vec![MovingShapeDesc {
            shape: shape(unit_sphere(), 2),
            world_from_object: moving(at(10.0), at(10.0)),
        }],
        ..MotionDesc::default()
    };
    let desc = SceneDesc {
        shapes: vec![
            shape(square(), 1),
            ShapeDesc {
                object_to_world: at(5.0),
                ..shape(unit_sphere(), 0)
            },
        ],
        objects: vec![ObjectDesc {
            name: "sq".into(),
            shapes: vec![shape(square(), 2)],
        }],
        instances: vec![InstanceDesc {
            object: 0,
            object_to_world: at(-5.0),
        }],
        ..SceneDesc::default()
    };
    let scene = scene_with(m, desc);
    for x in [0.0, 5.0, 10.0, -5.0] {
        for time in [0.0, 0.37, 1.0] {
            let r = Ray::new(Vec3::new(x, 0.2, -5.0), Vec3::Z).at_time(time);
            let h = scene.intersect(&r).unwrap_or_else(|| panic!("x {x}"));
            assert_eq!(h.si.time, time, "x {x}");
            assert_eq!(h.si.spawn_ray(Vec3::Z).time, time, "x {x}");
        }
    }
}

#[test]
fn a_moving_camera_looks_from_its_pose_at_the_ray_time() {
    let mut camera = Camera::from_desc(
        &CameraDesc::default(),
        (8, 8),
        crate::camera::DEFAULT_DIAGONAL,
    )
    .unwrap();
    camera.set_motion(Some(moving(
        Transform::IDENTITY,
        Transform::translate(Vec3::new(0.0, 2.0, 0.0)),
    )));
    assert!(camera.moves());
    let centre = Vec2::new(4.0, 4.0);
    let at = |t: f32| camera.generate_ray_at(centre, Vec2::ZERO, t).unwrap().ray;
    assert!(close(at(0.0).o, Vec3::ZERO) && close(at(0.0).d, Vec3::Z));
    assert!(close(at(0.25).o, Vec3::new(0.0, 0.5, 0.0)));
    assert!(close(at(1.0).o, Vec3::new(0.0, 2.0, 0.0)) && close(at(1.0).d, Vec3::Z));
    // generate_ray is the pose at the shutter's opening.
    assert_eq!(
        camera.generate_ray(centre, Vec2::ZERO).unwrap().ray,
        at(0.0)
    );
}

#[test]
fn a_still_scene_has_no_motion_and_samples_the_shutter_only_when_moving() {
    let still = scene_with(MotionDesc::default(), SceneDesc::default());
    assert!(still.motion.is_none());
    let m = MotionDesc {
        camera: Some(moving(Transform::IDENTITY, Transform::translate(Vec3::X))),
        ..MotionDesc::default()
    };
    let mut desc = SceneDesc::default();
    desc.camera.shutter = [0.25, 0.75];
    let scene = scene_with(m, desc);
    let motion = scene.motion.as_ref().unwrap();
    assert_eq!(motion.sample_time(0.0), 0.25);
    assert_eq!(motion.sample_time(0.5), 0.5);
    assert_eq!(motion.sample_time(1.0), 0.75);
    assert!(scene.camera.moves());
}
