//! Runs every step of the course and checks what each image must show.

#![allow(dead_code)]

mod common;

use common::ScratchDir;
use lancer::math::{INV_PI, Rgb, Vec3, cross, normalize};
use lancer_examples::Canvas;

#[path = "../01_image.rs"]
mod step1;
#[path = "../02_image_plane.rs"]
mod step2;
#[path = "../03_sphere.rs"]
mod step3;
#[path = "../04_plane.rs"]
mod step4;
#[path = "../05_nearest.rs"]
mod step5;
#[path = "../08_renderer.rs"]
mod step8;
#[path = "../09_sdf.rs"]
mod step9;
use step8::step7;
use step8::step7::step6;

fn close(a: Rgb, b: Rgb, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

/// Saves a canvas in a temporary folder, reads the PNG back and returns its top-left pixel.
fn saved_top_left(c: &Canvas, name: &str) -> [u8; 3] {
    let dir = ScratchDir::new(&format!("save-{name}"));
    let path = dir.join(name);
    c.save(&path).unwrap();
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut buf).unwrap();
    [buf[0], buf[1], buf[2]]
}

#[test]
fn step1_pixel_zero_is_bottom_left() {
    let c = step1::render(64, 32);
    assert!(c.get(0, 0).x < 0.02 && c.get(0, 0).y < 0.05);
    assert!(c.get(63, 31).x > 0.98 && c.get(63, 31).y > 0.95);
    // In the file the first row is the top one: pixel (0, h − 1), no red, full green.
    let tl = saved_top_left(&c, "01.png");
    assert!(tl[0] < 40 && tl[1] > 240, "{tl:?}");
}

#[test]
fn step2_directions_point_through_the_image_plane() {
    let c = step2::render(65, 65);
    // The centre pixel looks straight down −z: colour (0.5, 0.5, 0).
    assert!(close(c.get(32, 32), Rgb::new(0.5, 0.5, 0.0), 1e-6));
    // The bottom-left corner looks towards (−1, −1, −1) (minus half a pixel).
    let d = normalize(Vec3::new(-1.0 + 1.0 / 65.0, -1.0 + 1.0 / 65.0, -1.0));
    assert!(close(c.get(0, 0), (d + Rgb::ONE) * 0.5, 1e-6));
}

#[test]
fn step3_formula_agrees_with_the_library_sphere() {
    let (w, h) = (96, 96);
    let c = step3::render(w, h);
    // Straight ahead the sphere's normal is +z: colour (0.5, 0.5, 1).
    assert!(close(c.get(48, 48), Rgb::new(0.5, 0.5, 1.0), 0.02));
    assert_eq!(c.get(0, 0), Rgb::splat(0.1));
    let lib = lancer_examples::sphere(Vec3::new(0.0, 0.0, -3.0), 1.0);
    let mut hits = 0;
    for j in 0..h {
        for i in 0..w {
            let ray = lancer_examples::primary_ray(i, j, w, h);
            let ours = step3::hit_sphere(&ray, Vec3::new(0.0, 0.0, -3.0), 1.0);
            let theirs = lib.intersect(&ray).map(|hit| hit.t);
            match (ours, theirs) {
                (Some(a), Some(b)) => {
                    hits += 1;
                    assert!((a - b).abs() <= 1e-5 * a, "pixel ({i}, {j}): {a} vs {b}");
                }
                (None, None) => {}
                other => panic!("pixel ({i}, {j}) disagrees: {other:?}"),
            }
        }
    }
    // The sphere subtends asin(1/3): a disc of radius tan(asin(1/3)) ≈ 0.354 on the plane.
    let expected = std::f32::consts::PI * 0.3536f32.powi(2) / 4.0 * (w * h) as f32;
    assert!(
        (hits as f32 - expected).abs() < 0.03 * expected,
        "{hits} vs {expected}"
    );
}

#[test]
fn step4_plane_hit_distance_is_the_formula() {
    let (w, h) = (40, 20);
    let c = step4::render(w, h);
    let sky = Rgb::new(0.6, 0.8, 1.0);
    assert_eq!(c.get(20, 19), sky, "the upper half sees the sky");
    assert_ne!(c.get(20, 0), sky, "the lower half sees the floor");
    let floor = lancer_examples::plane(Vec3::new(0.0, -1.0, 0.0), Vec3::Y);
    let ray = lancer_examples::primary_ray(20, 2, w, h);
    // t = n·(a − o)/n·d with n = +y, a = (0, −1, 0), o = 0.
    let expected = -1.0 / ray.d.y;
    let t = floor.intersect(&ray).unwrap().t;
    assert!((t - expected).abs() < 1e-6 * expected);
}

#[test]
fn step5_only_the_nearest_hit_in_front_is_seen() {
    let (w, h) = (160, 100);
    let c = step5::render(w, h);
    let (_, colours) = step5::scene();
    let mut seen = [0usize; 5];
    for j in 0..h {
        for i in 0..w {
            if let Some(k) = colours.iter().position(|&col| col == c.get(i, j)) {
                seen[k] += 1;
            }
        }
    }
    assert_eq!(seen[4], 0, "the sphere behind the eye must not appear");
    assert!(
        seen[0] > 0 && seen[1] > 0 && seen[2] > 0 && seen[3] > 0,
        "{seen:?}"
    );
    // The red sphere's centre projects to (−0.8/3, −0.2/3) on the image plane, and it is in
    // front of the green one there.
    let (i, j) = (
        ((-0.8f32 / 3.0 * 0.625 + 1.0) * 80.0) as u32,
        ((-0.2f32 / 3.0 + 1.0) * 50.0) as u32,
    );
    assert_eq!(c.get(i, j), colours[1]);
}

#[test]
fn step6_lambert_law_and_shadows_are_exact() {
    let (w, h) = (160, 120);
    let c = step6::render(w, h);
    let (objects, albedos, lights) = step6::scene();
    let light = lights[0];
    let (mut lit, mut dark) = (0, 0);
    for j in 0..h {
        for i in 0..w {
            let ray = lancer_examples::primary_ray(i, j, w, h);
            let Some((k, si)) = lancer_examples::nearest_hit(&objects, &ray) else {
                continue;
            };
            let to_light = light.at - si.p;
            let r2 = to_light.length_squared();
            let n = if si.n.dot(si.wo) < 0.0 { -si.n } else { si.n };
            let cos = n.dot(to_light) / r2.sqrt();
            // Independent shadow test: does the segment p → light cross a sphere?
            let blocked = [
                (Vec3::new(-0.7, -0.3, -3.0), 0.7f32),
                (Vec3::new(0.9, -0.5, -2.5), 0.5),
            ]
            .iter()
            .any(|&(cen, r)| {
                let d = to_light / r2.sqrt();
                let tc = (cen - si.p).dot(d);
                let dist = (si.p + d * tc - cen).length();
                tc > 1e-3 && tc < r2.sqrt() && dist < r - 1e-3
            });
            let expected = if cos > 0.0 && !blocked {
                albedos[k] * INV_PI * light.intensity * cos / r2
            } else {
                Rgb::ZERO
            };
            let got = c.get(i, j);
            assert!(
                (got - expected).abs().max_element() <= 0.005 * expected.max_element() + 1e-7,
                "pixel ({i}, {j}): {got} vs {expected}"
            );
            if expected == Rgb::ZERO {
                dark += 1
            } else {
                lit += 1
            }
        }
    }
    assert!(lit > 1000 && dark > 100, "lit {lit}, dark {dark}");
}

#[test]
fn step7_lights_add_up() {
    let (w, h) = (80, 60);
    let c = step7::render(w, h);
    let (objects, albedos, _) = step6::scene();
    let lights = step7::lights();
    for (i, j) in [(40, 10), (20, 25), (60, 25)] {
        let ray = lancer_examples::primary_ray(i, j, w, h);
        let (k, si) = lancer_examples::nearest_hit(&objects, &ray).unwrap();
        let sum: Rgb = lights
            .iter()
            .map(|l| step6::PointLight {
                at: l.at,
                intensity: l.intensity,
            })
            .map(|l| step6::shade(&objects, &si, albedos[k], &[l]))
            .sum();
        assert!(close(c.get(i, j), sum, 1e-6));
    }
}

#[test]
fn step8_renderer_reproduces_the_hand_written_loop() {
    let (w, h) = (120, 90);
    let ours = step7::render(w, h);
    let lib = step8::render_image(w, h);
    let mut differ = 0;
    for j in 0..h {
        for i in 0..w {
            let (a, b) = (ours.get(i, j), lib.get(i, j));
            if (a - b).abs().max_element() > 1e-3 * a.max_element().max(1e-3) {
                differ += 1;
            }
        }
    }
    // Silhouette pixels may differ by rounding of the ray direction; nothing else may.
    assert!(differ <= (w * h) as usize / 200, "{differ} pixels differ");
}

#[test]
fn step9_sdf_scene_has_objects_lit_floor_umbra_and_penumbra() {
    let (objects, all) = step9::scene();
    let l = step9::light_dir();
    let k = step9::PENUMBRA_K;
    // Below the sphere's centre along the light: the umbra. Far off to the side: full light.
    let c = Vec3::new(0.0, 0.7, 0.0);
    let umbra = c - l * (c.y / l.y);
    assert_eq!(step9::soft_shadow(&all, umbra, l, k), 0.0);
    let far = Vec3::new(-3.0, 0.0, 3.0);
    assert_eq!(step9::soft_shadow(&all, far, l, k), 1.0);
    // Walking from the umbra sideways out of the shadow, the estimate rises through a
    // penumbra (values strictly between 0 and 1) and never falls back.
    let side = normalize(cross(l, Vec3::Y));
    let values: Vec<f32> = (0..=60)
        .map(|i| step9::soft_shadow(&all, umbra + side * (i as f32 * 0.05), l, k))
        .collect();
    assert!(values.iter().any(|&v| v > 0.2 && v < 0.8), "{values:?}");
    assert_eq!(*values.last().unwrap(), 1.0, "{values:?}");

    // The image: pink object pixels, floor pixels fully lit, in umbra and in penumbra, each
    // checked against the shading formula (with the example's own soft-shadow function: this
    // checks the shading, while the probes above and the hard-shadow march below check the
    // shadows independently).
    let (w, h) = (160, 90);
    let img = step9::render(w, h);
    let ambient = 0.6 * 0.15;
    let lit = 0.6 * (0.15 + 1.2 * l.y);
    let (mut pink, mut full, mut dark, mut half) = (0, 0, 0, 0);
    for j in 0..h {
        for i in 0..w {
            let px = img.get(i, j);
            let d = step9::ray_dir(i, j, w, h);
            let Some(t) = step9::march(&all, step9::EYE, d, 40.0) else {
                continue;
            };
            let p = step9::EYE + d * t;
            if objects.eval(p.as_dvec3()) < p.y as f64 {
                if px.x > 1.5 * px.y {
                    pink += 1;
                }
                continue;
            }
            // A floor pixel: grey, and ambient + direct·shadow with the floor's normal +y.
            assert!((px.x - px.y).abs() < 1e-4, "floor pixel ({i}, {j}) {px}");
            let s = step9::soft_shadow(&all, p + Vec3::Y * 2e-3, l, k);
            assert!(
                (px.y - (ambient + 0.6 * 1.2 * l.y * s)).abs() < 0.02,
                "({i}, {j}) {px} vs shadow {s}"
            );
            // Independent hard shadow: a ray marched to the light meets an object.
            let blocked = step9::march(&objects, p + Vec3::Y * 2e-3, l, 20.0).is_some();
            if blocked {
                assert!(px.y < ambient + 0.05, "({i}, {j}) is blocked but lit: {px}");
            }
            if (px.y - lit).abs() < 0.01 {
                full += 1;
            } else if (px.y - ambient).abs() < 0.01 {
                dark += 1;
            } else {
                half += 1;
            }
        }
    }
    assert!(
        pink > 800 && full > 3000 && dark > 100 && half > 100,
        "pink {pink}, lit {full}, umbra {dark}, penumbra {half}"
    );
}
