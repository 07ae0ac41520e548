use super::*;
use crate::camera::lens::{Aperture, LensInterface};

/// The double-Gauss 50 mm f/2 of `shared/scenes/cameras/lenses/dgauss.50mm.dat`.
const DGAUSS: [[f32; 4]; 11] = [
    [29.475, 3.76, 1.67, 25.2],
    [84.83, 0.12, 1.0, 25.2],
    [19.275, 4.025, 1.67, 23.0],
    [40.77, 3.275, 1.699, 23.0],
    [12.75, 5.705, 1.0, 18.0],
    [0.0, 4.5, 0.0, 17.1],
    [-14.495, 1.18, 1.603, 17.0],
    [40.77, 6.065, 1.658, 20.0],
    [-20.385, 0.19, 1.0, 20.0],
    [437.065, 3.22, 1.717, 20.0],
    [-39.73, 5.0, 1.0, 20.0],
];

fn dgauss(aperture_mm: f32, focus: f32, aperture: Aperture) -> LensDesc {
    LensDesc {
        interfaces: DGAUSS
            .iter()
            .map(|r| LensInterface {
                curvature_radius: r[0],
                thickness: r[1],
                eta: r[2],
                aperture_diameter: r[3],
            })
            .collect(),
        aperture_diameter: aperture_mm,
        focus_distance: focus,
        aperture,
    }
}

fn camera(aperture_mm: f32, focus: f32) -> RealisticCamera {
    RealisticCamera::new(
        &dgauss(aperture_mm, focus, Aperture::Circular),
        35.0,
        64,
        64,
        1 << 14,
    )
    .unwrap()
}

/// Where a camera-space ray crosses the plane x = 0 (the axis, for rays in the xz plane).
fn axis_crossing(r: &LensRay) -> f32 {
    r.at(-r.o.x / r.d.x).z
}

#[test]
fn the_focal_length_is_fifty_millimetres() {
    // A ray parallel to the axis from the scene crosses the axis at the film-side focal point;
    // the film-side principal plane is 50 mm before it (the lens file is scaled to 50 mm).
    let c = camera(17.1, 10.0);
    let [(pf, ff), (ps, fs)] = c.thick_lens().unwrap();
    // Camera space: the film-side focal point is nearer the film (smaller z) than its
    // principal plane.
    let f = pf - ff;
    assert!((f - 0.050).abs() < 0.001, "f = {f}");
    // Symmetric on the scene side: the focal point 50 mm in front of its principal plane.
    assert!(((fs - ps) - 0.050).abs() < 0.001, "{fs} − {ps}");
    // Focused at 10 m, the film (z = 0) is the object's image: by Newton's x·x′ = f², with
    // x = 10 − fs the object's distance to the scene-side focal point, the film-side focal
    // point lies x′ = f²/x in front of the film.
    let x_img = f * f / (10.0 - fs);
    assert!((ff - x_img).abs() < 0.02 * x_img, "{ff} vs {x_img}");
}

#[test]
fn a_point_at_the_focus_distance_images_to_a_point_on_the_film() {
    for focus in [3.0f32, 0.8] {
        let c = camera(4.0, focus);
        // Rays from an axial point at the focus distance through the front element, a little
        // off the axis (paraxial): after the lens they cross the axis on the film, z = 0.
        for h in [0.2e-3f32, 0.5e-3, 1.0e-3] {
            let p = Vec3::new(0.0, 0.0, focus);
            let front = Vec3::new(h, 0.0, c.front_z());
            let r = LensRay { o: p, d: front - p };
            let out = c.trace_from_scene(&r).expect("through the lens");
            let z = axis_crossing(&out);
            assert!(z.abs() < 2e-4, "focus {focus}, h {h}: image at z = {z}");
        }
        // An off-axis point at that distance: of the rays towards a grid of points on the front
        // element, those that get through meet on the film within a few micrometres (a pixel
        // of a 256-pixel image on a 35 mm diagonal is 97 µm), at the inverted position.
        let p = Vec3::new(0.04 * focus, 0.03 * focus, focus);
        let mut hits = Vec::new();
        for j in -16..=16 {
            for i in -16..=16 {
                let target = Vec3::new(0.5e-3 * i as f32, 0.5e-3 * j as f32, c.front_z());
                let r = LensRay {
                    o: p,
                    d: target - p,
                };
                if let Some(out) = c.trace_from_scene(&r) {
                    let t = -out.o.z / out.d.z;
                    hits.push(out.at(t));
                }
            }
        }
        assert!(hits.len() > 10, "{} rays through", hits.len());
        for q in &hits {
            assert!((*q - hits[0]).length() < 10e-6, "{q} vs {}", hits[0]);
        }
        // Inverted and magnified by about −f/(focus − f).
        let m = -0.05 / (focus - 0.05);
        assert!(
            (hits[0].x - m * p.x).abs() < 0.1 * (m * p.x).abs(),
            "{} vs {}",
            hits[0].x,
            m * p.x
        );
        assert!(hits[0].y < 0.0);
    }
}

#[test]
fn rays_leave_the_lens_towards_the_part_of_the_scene_their_pixel_shows() {
    let c = camera(17.1, 3.0);
    // The centre pixel looks along the axis.
    let s = c
        .generate(Vec2::splat(32.0), Vec2::splat(0.5))
        .expect("open centre");
    assert!(s.ray.d.z > 0.999, "{}", s.ray.d);
    assert!(s.weight > 0.0);
    // The top-left pixel looks up and to camera space's −x, as a perspective camera's does.
    let mut seen = 0;
    for i in 0..64 {
        let u = Vec2::new((i % 8) as f32 / 8.0 + 0.06, (i / 8) as f32 / 8.0 + 0.06);
        if let Some(s) = c.generate(Vec2::new(2.0, 2.0), u) {
            assert!(s.ray.d.x < 0.0 && s.ray.d.y > 0.0, "{}", s.ray.d);
            seen += 1;
        }
    }
    assert!(seen > 0);
}

#[test]
fn exit_pupil_bounds_hold_every_ray_that_gets_through() {
    // The mean weight of sampled rays estimates ∫ cos⁴θ / z_rear² dA over the rear-plane
    // points whose rays get through. Counting those points on a fine grid over the whole
    // 3r × 3r square gives the same integral: the bounds lose nothing.
    let c = camera(17.1, 3.0);
    let rear = c.rear_z();
    let r = c.interfaces.last().unwrap().aperture_radius;
    for film in [Vec2::new(0.0, 0.0), Vec2::new(-0.006, 0.004)] {
        let raster = (Vec2::new(-film.x, film.y) - c.extent.min) / (c.extent.max - c.extent.min)
            * c.resolution;
        let n = 200;
        let mut sum = 0.0f64;
        for i in 0..n * n {
            let u = Vec2::new(
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            );
            if let Some(s) = c.generate(raster, u) {
                sum += s.weight as f64;
            }
        }
        let sampled = sum / (n * n) as f64;
        let m = 600;
        let cell = 3.0 * r / m as f32;
        let p = Vec3::new(film.x, film.y, 0.0);
        let mut grid = 0.0f64;
        for j in 0..m {
            for i in 0..m {
                let q = Vec3::new(
                    -1.5 * r + (i as f32 + 0.5) * cell,
                    -1.5 * r + (j as f32 + 0.5) * cell,
                    rear,
                );
                let ray = LensRay { o: p, d: q - p };
                if c.trace_from_film(&ray).is_some() {
                    let cos = normalize(ray.d).z;
                    grid += (cos.powi(4) / (rear * rear) * cell * cell) as f64;
                }
            }
        }
        assert!(
            (sampled - grid).abs() < 0.02 * grid,
            "film {film}: sampled {sampled} vs grid {grid}"
        );
    }
}

#[test]
fn the_stop_opens_to_the_aperture_diameter_and_no_wider() {
    let small = camera(4.0, 3.0);
    let stop = |c: &RealisticCamera| c.interfaces[5].aperture_radius;
    assert_eq!(stop(&small), 0.002);
    // 30 mm is wider than the stop's 17.1 mm: it stays 17.1 mm.
    assert_eq!(stop(&camera(30.0, 3.0)), 0.00855);
}

#[test]
fn a_shaped_aperture_passes_the_light_of_a_circular_one() {
    // Mean weight at the film's centre with a square stop equals the circular one's: pbrt-v4
    // scales the masks to the disk's π/4 coverage (within the bilinear edges and noise).
    let mean = |aperture: Aperture| {
        let c = RealisticCamera::new(&dgauss(8.0, 3.0, aperture), 35.0, 64, 64, 1 << 14).unwrap();
        let n = 256;
        let mut sum = 0.0f64;
        for i in 0..n * n {
            let u = Vec2::new(
                ((i % n) as f32 + 0.5) / n as f32,
                ((i / n) as f32 + 0.5) / n as f32,
            );
            sum += c.generate(Vec2::splat(32.0), u).map_or(0.0, |s| s.weight) as f64;
        }
        sum / (n * n) as f64
    };
    let circle = mean(Aperture::Circular);
    for a in [Aperture::Square, Aperture::Pentagon, Aperture::Gaussian] {
        let m = mean(a.clone());
        assert!((m - circle).abs() < 0.03 * circle, "{a:?}: {m} vs {circle}");
    }
}

#[test]
fn focusing_too_close_is_an_error() {
    let e = RealisticCamera::new(
        &dgauss(17.1, 0.1, Aperture::Circular),
        35.0,
        64,
        64,
        1 << 10,
    )
    .unwrap_err();
    assert!(e.contains("focusdistance 0.1 is too short"), "{e}");
    let e = RealisticCamera::new(&dgauss(0.0, 3.0, Aperture::Circular), 35.0, 64, 64, 1 << 10)
        .unwrap_err();
    assert!(e.contains("aperture stop"), "{e}");
}

#[test]
fn radical_inverses_mirror_the_digits() {
    assert_eq!(radical_inverse(2, 1), 0.5);
    assert_eq!(radical_inverse(2, 6), 0.375); // 110₂ → 0.011₂
    assert!((radical_inverse(3, 5) - 7.0 / 9.0).abs() < 1e-7); // 12₃ → 0.21₃
}
