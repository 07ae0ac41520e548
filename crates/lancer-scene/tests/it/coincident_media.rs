//! Media whose boundaries coincide: `interface` boxes on the same triangles, each with its own
//! medium inside and none outside, as pbrt-v4 treats them. A ray crossing the shared surface
//! meets one of the coincident triangles (pbrt-v4's BVH keeps the nearest hit; at equal t
//! which one is an accident of its tree and of rounding); the ray spawned from it goes on
//! from an origin offset past the surface by the hit's error bound (`SpawnRay`), so the other
//! coincident triangles are behind it and are not met. Going in, the ray is in exactly one of
//! the media (`GetMedium(w)`: the inside of the triangle it met); going out, in none.

use lancer::Scene;
use lancer::integrator::Integrator;
use lancer::math::{Vec3, normalize};
use lancer::ray::Ray;
use lancer::sampling::{Sampler, SamplerKind};
use lancer_scene::load_pbrt_str;
use std::path::Path;

/// The unit box of pbrt's `trianglemesh`, scaled by ½, `copies` times over, each copy an
/// `interface` around its own homogeneous medium of absorption `sigma_a[k]`.
fn boxes(sigma_a: &[f32]) -> Scene {
    let mut text = String::from("WorldBegin\n");
    for (k, a) in sigma_a.iter().enumerate() {
        text += &format!(
            r#"AttributeBegin
            ConcatTransform [0.5 0 0 0 0 0.5 0 0 0 0 0.5 0 0 0 0 1]
            MakeNamedMedium "m{k}" "string type" "homogeneous" "rgb sigma_a" [{a} {a} {a}]
                "rgb sigma_s" [0.5 0.5 0.5]
            Material "interface"
            MediumInterface "m{k}" ""
            Shape "trianglemesh" "point3 P" [1 -1 1 -1 -1 1 1 1 1 -1 1 1 -1 -1 -1 1 -1 -1 -1 1 -1 1 1 -1]
                "integer indices" [0 3 1 0 2 3 4 7 5 4 6 7 6 2 7 6 3 2 5 1 4 5 0 1 5 2 0 5 7 2 1 6 4 1 3 6]
            AttributeEnd
            "#
        );
    }
    text += r#"LightSource "infinite" "rgb L" [1 1 1]"#;
    let desc = load_pbrt_str(&text, "boxes.pbrt", Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"))
        .desc;
    Scene::build(&desc).unwrap()
}

/// Rays from outside the box through each of its faces, towards points spread over the face.
fn rays_through_faces(n: u32) -> Vec<Ray> {
    let mut rays = Vec::new();
    for axis in 0..3 {
        for sign in [1.0f32, -1.0] {
            for i in 0..n {
                for j in 0..n {
                    let a = -0.45 + 0.9 * (i as f32 + 0.5) / n as f32;
                    let b = -0.45 + 0.9 * (j as f32 + 0.5) / n as f32;
                    let (mut o, mut t) = ([0.0f32; 3], [0.0f32; 3]);
                    o[axis] = 3.0 * sign;
                    (o[(axis + 1) % 3], o[(axis + 2) % 3]) = (0.3 * a, 0.2 * b);
                    (t[(axis + 1) % 3], t[(axis + 2) % 3]) = (a, b);
                    let o = Vec3::from(o);
                    rays.push(Ray::new(o, normalize(Vec3::from(t) - o)));
                }
            }
        }
    }
    rays
}

#[test]
fn a_ray_through_coincident_boxes_is_in_one_medium_inside_and_none_outside() {
    let s = boxes(&[0.1, 0.2, 0.3]);
    for ray in rays_through_faces(12) {
        let entry = s.intersect(&ray).expect("the box");
        let inside = s.medium_past(entry.prim, entry.si.n, ray.d, None);
        assert!(matches!(inside, Some(0..=2)), "{inside:?}");
        // The coincident triangles at the entry are behind the spawned ray's origin: the next
        // surface is the far side, a box width (1) away at least.
        let on = entry.si.spawn_ray(ray.d);
        let exit = s.intersect(&on).expect("the far side");
        assert!(exit.si.t > 0.99, "{}", exit.si.t);
        assert_eq!(s.medium_past(exit.prim, exit.si.n, on.d, inside), None);
        // And past the far side, nothing: its coincident triangles are skipped too.
        assert!(s.intersect(&exit.si.spawn_ray(on.d)).is_none());
    }
}

#[test]
fn coincident_boxes_of_one_medium_render_as_one_box() {
    // Whichever coincident triangle a ray meets, a copy of the same medium is the same path:
    // the radiance is the single box's, bit for bit.
    let (one, three) = (boxes(&[0.2]), boxes(&[0.2, 0.2, 0.2]));
    let integrator = Integrator::VolPath {
        max_depth: 5,
        regularize: false,
    };
    let mut sum = 0.0;
    for (i, ray) in rays_through_faces(4).iter().enumerate() {
        let li = |scene: &Scene| {
            let mut sampler = Sampler::new(SamplerKind::Independent, 16, 3);
            sampler.start_pixel_sample(i as i32, 0, 0);
            integrator.li(scene, ray, &mut sampler, None)
        };
        let (a, b) = (li(&one), li(&three));
        assert_eq!(a, b, "ray {i}");
        sum += a.element_sum();
    }
    assert!(sum > 0.0);
}
