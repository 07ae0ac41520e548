//! Area lights: points sampled on every shape carry the normal the intersection code gives
//! there, light sampling's density agrees with `pdf_li`, and the irradiance it estimates from
//! a disk and from a sphere equals the closed forms.

use lancer::Scene;
use lancer::light::{Light, LightSampleContext};
use lancer::math::{PackedVec3, Rgb, Transform, Vec2, Vec3};
use lancer::ray::Ray;
use lancer::scene::desc::{AreaLightDesc, Geometry, SceneDesc, ShapeDesc};
use lancer::shape::{CylinderDesc, DiskDesc, SphereDesc, TriangleMesh};
use std::f32::consts::PI;
use std::sync::Arc;

fn emitter(geometry: Geometry, to_world: Transform, reverse: bool, l: f32) -> ShapeDesc {
    ShapeDesc {
        medium_interface: None,
        geometry,
        object_to_world: to_world,
        reverse_orientation: reverse,
        material: 0,
        area_light: Some(AreaLightDesc {
            l: Rgb::splat(l),
            two_sided: false,
            spectrum: None,
            power: None,
            image: None,
        }),
        alpha: None,
    }
}

fn scene_of(shapes: Vec<ShapeDesc>) -> Scene {
    Scene::build(&SceneDesc {
        shapes,
        ..SceneDesc::default()
    })
    .unwrap()
}

/// A low-discrepancy point set inside (0, 1)² (Hammersley, both axes shifted by half a
/// stratum so that no point lies on a shape's boundary).
fn points(n: u32) -> impl Iterator<Item = Vec2> {
    (0..n).map(move |i| {
        let y = (i.reverse_bits() as f64 / 4294967296.0 + 0.5 / n as f64).fract();
        Vec2::new((i as f32 + 0.5) / n as f32, y as f32)
    })
}

fn all_shapes() -> Vec<ShapeDesc> {
    let mirror = Transform::scale(Vec3::new(-1.0, 2.0, 2.0)).unwrap();
    let moved = Transform::translate(Vec3::new(0.3, -0.2, 0.5))
        * Transform::rotate(30.0, Vec3::new(1.0, 1.0, 0.0)).unwrap();
    let quad = TriangleMesh {
        positions: vec![
            PackedVec3::new(-1.0, -1.0, 0.0),
            PackedVec3::new(1.0, -1.0, 0.0),
            PackedVec3::new(1.0, 1.0, 0.0),
            PackedVec3::new(-1.0, 1.0, 0.0),
        ],
        normals: vec![],
        uvs: vec![],
        indices: vec![0, 1, 2, 0, 2, 3],
        flip_normal: false,
    };
    let mut with_normals = quad.clone();
    with_normals.normals = vec![PackedVec3::new(0.0, 0.0, -1.0); 4];
    let mut out = Vec::new();
    for (xf, reverse) in [
        (Transform::IDENTITY, false),
        (moved, true),
        (mirror, false),
        (mirror, true),
    ] {
        out.push(emitter(
            Geometry::Sphere(SphereDesc {
                radius: 0.8,
                z_min: -0.5,
                z_max: 0.7,
                phi_max: 270.0,
            }),
            xf,
            reverse,
            1.0,
        ));
        out.push(emitter(
            Geometry::Disk(DiskDesc {
                height: 0.2,
                radius: 1.0,
                inner_radius: 0.3,
                phi_max: 300.0,
            }),
            xf,
            reverse,
            1.0,
        ));
        out.push(emitter(
            Geometry::Cylinder(CylinderDesc {
                radius: 0.6,
                z_min: -0.4,
                z_max: 0.9,
                phi_max: 200.0,
            }),
            xf,
            reverse,
            1.0,
        ));
        out.push(emitter(
            Geometry::TriangleMesh(Arc::new(quad.clone())),
            xf,
            reverse,
            1.0,
        ));
        out.push(emitter(
            Geometry::TriangleMesh(Arc::new(with_normals.clone())),
            xf,
            reverse,
            1.0,
        ));
    }
    out
}

#[test]
fn sampled_points_carry_the_intersection_normal() {
    // One shape per scene, so that the ray can only meet the one sampled.
    for (k, sd) in all_shapes().into_iter().enumerate() {
        let scene = scene_of(vec![sd]);
        let (mut checked, mut tried) = (0, 0);
        for prim in 0..scene.shapes().len() {
            let shape = &scene.shapes()[prim];
            for u in points(64) {
                let s = shape.sample_area(u, scene.meshes()).expect("samples");
                // Aim at the sampled point from a little way off the surface along the normal,
                // from outside whichever side faces the ray.
                for side in [1.0f32, -1.0] {
                    tried += 1;
                    let o = s.p + s.n * (0.05 * side);
                    let ray = Ray::new(o, s.p - o);
                    let Some(hit) = scene.intersect(&ray) else {
                        panic!("shape {k}: ray at a sampled point missed");
                    };
                    if (hit.si.p - s.p).length() > 1e-3 {
                        continue; // another part of the same shape is in the way
                    }
                    checked += 1;
                    assert!(
                        hit.si.n.dot(s.n) > 0.999,
                        "shape {k}: sampled normal {} but intersection normal {}",
                        s.n,
                        hit.si.n
                    );
                }
            }
        }
        // The ray from the side the normal faces always reaches the point first, so at
        // least half the tries compare normals.
        assert!(
            2 * checked >= tried,
            "shape {k}: only {checked} of {tried} compared"
        );
    }
}

#[test]
fn areas_match_closed_forms() {
    let scene = scene_of(vec![
        emitter(
            Geometry::Disk(DiskDesc {
                height: 0.0,
                radius: 2.0,
                inner_radius: 1.0,
                phi_max: 180.0,
            }),
            Transform::scale(Vec3::splat(3.0)).unwrap(),
            false,
            1.0,
        ),
        emitter(
            Geometry::Sphere(SphereDesc {
                radius: 1.0,
                z_min: -1.0,
                z_max: 1.0,
                phi_max: 360.0,
            }),
            Transform::IDENTITY,
            false,
            1.0,
        ),
        emitter(
            Geometry::Cylinder(CylinderDesc {
                radius: 0.5,
                z_min: 0.0,
                z_max: 2.0,
                phi_max: 90.0,
            }),
            Transform::IDENTITY,
            false,
            1.0,
        ),
    ]);
    let a: Vec<f32> = scene.shapes().iter().map(|s| s.area()).collect();
    // Half annulus × 9: π(4 − 1)/2 · 9; unit sphere 4π; quarter cylinder 2π·0.5·2/4.
    let want = [PI * 1.5 * 9.0, 4.0 * PI, 0.5 * PI];
    for (got, want) in a.iter().zip(want) {
        assert!((got - want).abs() < 1e-4 * want, "{got} vs {want}");
    }
}

/// Irradiance at `p` (normal `n`) estimated by sampling light `light` of `scene`, and the
/// largest disagreement between each sample's pdf and `pdf_li` for the same direction.
fn irradiance(scene: &Scene, light: usize, p: Vec3, n: Vec3, count: u32) -> (f32, f32) {
    let ctx = LightSampleContext { p, n, ns: n };
    let l = &scene.lights()[light];
    let mut sum = 0.0f64;
    let mut worst = 0.0f32;
    let mut misses = 0;
    for u in points(count) {
        let Some(ls) = l.sample_li(&ctx, u, scene.shapes(), scene.meshes()) else {
            continue;
        };
        let cos = ls.wi.dot(n).max(0.0);
        sum += (ls.l.x * cos / ls.pdf) as f64;
        // The light's point and its normal, as a BSDF-sampled ray would find them.
        // Rays grazing the silhouette may round to a miss; they must stay rare.
        let Some(hit) = scene.intersect(&Ray::new(p, ls.wi)) else {
            misses += 1;
            continue;
        };
        let pdf = l.pdf_li(&ctx, ls.wi, Some((hit.si.p, hit.si.n)));
        // Near the silhouette the density ∝ 1/cos θ_light is too ill-conditioned to compare.
        if hit.si.n.dot(ls.wi).abs() > 0.05 {
            worst = worst.max((pdf - ls.pdf).abs() / ls.pdf);
        }
    }
    assert!(
        misses * 1000 < count,
        "{misses} of {count} light samples not visible"
    );
    ((sum / count as f64) as f32, worst)
}

#[test]
fn disk_light_gives_the_closed_form_irradiance() {
    // A disk of radius r facing down at height h, on its axis: E = π·L·r²/(h² + r²).
    let (r, h, l) = (0.7f32, 1.5f32, 3.0f32);
    let flip =
        Transform::translate(Vec3::new(0.0, 0.0, h)) * Transform::rotate(180.0, Vec3::X).unwrap();
    let scene = scene_of(vec![emitter(
        Geometry::Disk(DiskDesc {
            height: 0.0,
            radius: r,
            inner_radius: 0.0,
            phi_max: 360.0,
        }),
        flip,
        false,
        l,
    )]);
    let (e, worst) = irradiance(&scene, 0, Vec3::ZERO, Vec3::Z, 40_000);
    let want = PI * l * r * r / (h * h + r * r);
    assert!(
        (e - want).abs() < 0.005 * want,
        "E = {e}, closed form {want}"
    );
    assert!(
        worst < 1e-3,
        "pdf_li disagrees with the sample's pdf by {worst}"
    );
    // Facing away (one-sided, normal up): no light at all.
    let scene = scene_of(vec![emitter(
        Geometry::Disk(DiskDesc {
            height: h,
            radius: r,
            inner_radius: 0.0,
            phi_max: 360.0,
        }),
        Transform::IDENTITY,
        false,
        l,
    )]);
    let ctx = LightSampleContext {
        p: Vec3::ZERO,
        n: Vec3::Z,
        ns: Vec3::Z,
    };
    assert!(points(256).all(|u| {
        scene.lights()[0]
            .sample_li(&ctx, u, scene.shapes(), scene.meshes())
            .is_none()
    }));
}

#[test]
fn sphere_light_gives_the_closed_form_irradiance() {
    // A sphere of radius r at distance d, straight above: E = π·L·(r/d)². The small one
    // fills a cone below 1.5°, sampled by the Taylor expansion.
    let l = 2.0f32;
    for (label, r, d, z_max) in [
        ("whole (cone sampling)", 0.5f32, 2.0f32, 0.5),
        ("cut (area sampling)", 0.5, 2.0, 0.0),
        ("whole, small (cone sampling)", 0.02, 2.0, 0.02),
    ] {
        // The cut sphere keeps its lower half, which is all the point sees anyway.
        let scene = scene_of(vec![emitter(
            Geometry::Sphere(SphereDesc {
                radius: r,
                z_min: -r,
                z_max,
                phi_max: 360.0,
            }),
            Transform::translate(Vec3::new(0.0, 0.0, d)),
            false,
            l,
        )]);
        assert_eq!(
            matches!(
                scene.lights()[0],
                Light::Area(lancer::light::AreaLight {
                    emitter: lancer::light::Emitter::Sphere { .. },
                    ..
                })
            ),
            z_max == r
        );
        let (e, worst) = irradiance(&scene, 0, Vec3::ZERO, Vec3::Z, 40_000);
        let want = PI * l * (r / d) * (r / d);
        assert!(
            (e - want).abs() < 0.005 * want,
            "{label}: E = {e}, closed form {want}"
        );
        assert!(worst < 2e-3, "{label}: pdf_li off by {worst}");
    }
}

#[test]
fn lights_are_chosen_by_power() {
    let scene = scene_of(vec![
        emitter(
            Geometry::Disk(DiskDesc {
                height: 0.0,
                radius: 1.0,
                inner_radius: 0.0,
                phi_max: 360.0,
            }),
            Transform::IDENTITY,
            false,
            1.0,
        ),
        emitter(
            Geometry::Disk(DiskDesc {
                height: 0.0,
                radius: 1.0,
                inner_radius: 0.0,
                phi_max: 360.0,
            }),
            Transform::translate(Vec3::new(5.0, 0.0, 0.0)),
            false,
            3.0,
        ),
    ]);
    let d = &scene.light_distribution();
    assert!((d.pmf(0) - 0.25).abs() < 1e-6 && (d.pmf(1) - 0.75).abs() < 1e-6);
}
