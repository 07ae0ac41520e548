//! Helpers of the analytic-shape tests: a one-shape scene, a shape's placement, azimuths.

use lancer::Scene;
use lancer::math::{Transform, Vec3, normalize};
use lancer::sampling::Pcg32;
use lancer::scene::desc::{Geometry, SceneDesc, ShapeDesc};
use lancer::shape::{Placement, Shape};
use std::f64::consts::PI;

/// A scene holding only `geometry`, placed by `to_world` (orientation reversed if asked).
pub fn scene_of(geometry: Geometry, to_world: Transform, reverse: bool) -> Scene {
    Scene::build(&SceneDesc {
        shapes: vec![ShapeDesc {
            medium_interface: None,
            geometry,
            object_to_world: to_world,
            reverse_orientation: reverse,
            material: 0,
            area_light: None,
            alpha: None,
        }],
        ..SceneDesc::default()
    })
    .unwrap()
}

/// The placement (object ↔ world transforms) of an analytic shape.
pub fn placement(s: &Shape) -> &Placement {
    match s {
        Shape::Sphere(x) => &x.placement,
        Shape::Disk(x) => &x.placement,
        Shape::Cylinder(x) => &x.placement,
        Shape::Cone(x) => &x.placement,
        Shape::Paraboloid(x) => &x.placement,
        Shape::Hyperboloid(x) => &x.placement,
        Shape::Box(x) => &x.placement,
        _ => unreachable!("not an analytic shape"),
    }
}

/// Azimuth φ = atan2(y, x) in [0, 2π).
pub fn azimuth(x: f64, y: f64) -> f64 {
    let a = y.atan2(x);
    if a < 0.0 { a + 2.0 * PI } else { a }
}

/// A point uniform in the cube [lo, hi)³.
pub fn uniform3(rng: &mut Pcg32, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(
        lo + (hi - lo) * rng.uniform(),
        lo + (hi - lo) * rng.uniform(),
        lo + (hi - lo) * rng.uniform(),
    )
}

/// A uniformly random unit direction (rejection from the cube into the ball; near-zero
/// vectors are rejected too, so the normalisation is accurate).
pub fn random_unit(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = uniform3(rng, -1.0, 1.0);
        if v.length_squared() <= 1.0 && v.length_squared() > 1e-4 {
            return normalize(v);
        }
    }
}
