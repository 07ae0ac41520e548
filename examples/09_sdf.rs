//! Step 9 — objects given by a distance function, as on Shadertoy.
//!
//! A signed distance function f tells, at any point p, how far the nearest surface is (negative
//! inside). Sphere tracing walks a ray by that distance, p ← p + f(p)·d, which can never cross a
//! surface, until f falls below a tolerance: that is the visible point. Smooth blends of
//! primitives, impossible with the analytic shapes of steps 3–8, are one line of the
//! expression language (`smooth_union(a, b, k)`). The normal is the gradient of f.
//!
//! Soft shadows come for free (Quilez): marching from the point towards the light, the
//! smallest ratio k·h/t of the distance h to the nearest surface over the distance t travelled
//! is how much of a light of angular size ~1/k is seen: 0 when a surface blocks the ray, 1 when
//! nothing comes close, and a penumbra in between.
//!
//! This program marches the library's distance function itself (`SdfFunction::eval`), as a
//! Shadertoy shader would, rather than going through the path tracer.

use lancer::math::{Rgb, Vec3, cross, normalize};
use lancer::shape::SdfFunction;
use lancer_examples::{Canvas, image_plane_point, save_or_exit};

/// The objects: a sphere blended with a rounded box and a torus, standing on the floor y = 0.
pub const OBJECTS: &str = "smooth_union(\
     smooth_union(translate([0, 0.7, 0], sphere(0.7)), \
                  translate([0.95, 0.45, 0.35], rotate(30, [0, 1, 0], round_box([0.45, 0.45, 0.45], 0.08))), 0.35), \
     translate([-0.9, 0.35, 0.4], rotate(60, [1, 0, 0], torus(0.45, 0.16))), 0.3)";

/// Direction towards the (distant) light, unit length.
pub fn light_dir() -> Vec3 {
    normalize(Vec3::new(-0.7, 0.55, 0.5))
}

/// Sharpness of the penumbra, k in k·h/t (a light about 1/k radians wide).
pub const PENUMBRA_K: f32 = 8.0;

/// The eye and the point it looks at.
pub const EYE: Vec3 = Vec3::new(0.6, 2.2, 5.5);
/// The point the camera looks at.
pub const LOOK_AT: Vec3 = Vec3::new(0.2, 0.4, 0.0);

/// The scene: the objects, and the objects on the floor (`union` with the half-space y ≤ 0).
pub fn scene() -> (SdfFunction, SdfFunction) {
    let objects = SdfFunction::parse(OBJECTS).expect("a valid expression");
    let all = SdfFunction::parse(&format!("union(plane([0, 1, 0], 0), {OBJECTS})"))
        .expect("a valid expression");
    (objects, all)
}

/// Camera basis (right, up, backward): the course's camera (looking down −z) turned to look
/// from [`EYE`] at [`LOOK_AT`].
fn basis() -> (Vec3, Vec3, Vec3) {
    let w = normalize(EYE - LOOK_AT);
    let u = normalize(cross(Vec3::Y, w));
    (u, cross(w, u), w)
}

/// Half the image plane's shorter side, at distance 1: tan(fov/2) (fov ≈ 45°).
pub const ZOOM: f32 = 0.42;

/// The primary ray direction through pixel (i, j), unit length.
pub fn ray_dir(i: u32, j: u32, width: u32, height: u32) -> Vec3 {
    let q = image_plane_point(i, j, width, height) * Vec3::new(ZOOM, ZOOM, 1.0);
    let (u, v, w) = basis();
    normalize(u * q.x + v * q.y + w * q.z)
}

/// The pixel where the world point p is seen (the inverse of [`ray_dir`]).
pub fn project(p: Vec3, width: u32, height: u32) -> Option<(u32, u32)> {
    let (u, v, w) = basis();
    let d = p - EYE;
    let z = -d.dot(w);
    if z <= 0.0 {
        return None;
    }
    let (x, y) = (d.dot(u) / z / ZOOM, d.dot(v) / z / ZOOM);
    let s = width.min(height) as f32;
    // Inverse of x = (−1 + (2i + 1)/w)·(w/s).
    let i = ((x * s / width as f32 + 1.0) * width as f32 - 1.0) / 2.0;
    let j = ((y * s / height as f32 + 1.0) * height as f32 - 1.0) / 2.0;
    let (i, j) = (i.round(), j.round());
    (i >= 0.0 && j >= 0.0 && i < width as f32 && j < height as f32).then_some((i as u32, j as u32))
}

/// Sphere tracing: the first t where f(o + t·d) < 10⁻⁴·t (a tolerance growing with distance,
/// like a pixel's footprint), within `t_max` and 300 steps.
pub fn march(f: &SdfFunction, o: Vec3, d: Vec3, t_max: f32) -> Option<f32> {
    let mut t = 0.0f32;
    for _ in 0..300 {
        let h = f.eval((o + d * t).as_dvec3()) as f32;
        if h < 1e-4 * t.max(1.0) {
            return Some(t);
        }
        t += h;
        if t > t_max {
            return None;
        }
    }
    None
}

/// Quilez's soft shadow from p towards the light direction l: min over the march of k·h/t,
/// clamped to [0, 1]; 0 when the march meets a surface. The march starts 10⁻² away so that it
/// does not find the surface p lies on.
pub fn soft_shadow(f: &SdfFunction, p: Vec3, l: Vec3, k: f32) -> f32 {
    let mut res = 1.0f32;
    let mut t = 1e-2f32;
    for _ in 0..200 {
        let h = f.eval((p + l * t).as_dvec3()) as f32;
        if h < 1e-4 {
            return 0.0;
        }
        res = res.min(k * h / t);
        t += h.clamp(0.01, 0.5);
        if t > 20.0 {
            break;
        }
    }
    res.clamp(0.0, 1.0)
}

/// Radiance seen along the ray (o, d): the sky, or a diffuse point lit by the light (with its
/// soft shadow) and a little sky light.
pub fn shade(objects: &SdfFunction, all: &SdfFunction, o: Vec3, d: Vec3) -> Rgb {
    let Some(t) = march(all, o, d, 40.0) else {
        return Rgb::new(0.55, 0.7, 0.9) - Rgb::splat(0.3 * d.y.max(0.0));
    };
    let p = o + d * t;
    let n = all.gradient(p.as_dvec3(), 1e-4).normalize().as_vec3a();
    // The nearer of the objects and the floor gives the colour.
    let albedo = if objects.eval(p.as_dvec3()) < p.y as f64 {
        Rgb::new(0.85, 0.35, 0.55)
    } else {
        Rgb::splat(0.6)
    };
    // Lift the point off the surface along n before the shadow march.
    let l = light_dir();
    let cos = n.dot(l).max(0.0);
    let shadow = if cos > 0.0 {
        soft_shadow(all, p + n * 2e-3, l, PENUMBRA_K)
    } else {
        0.0
    };
    albedo * (Rgb::splat(0.15) + Rgb::splat(1.2) * cos * shadow)
}

/// The image.
pub fn render(width: u32, height: u32) -> Canvas {
    let (objects, all) = scene();
    Canvas::fill(width, height, |i, j| {
        shade(&objects, &all, EYE, ray_dir(i, j, width, height))
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(640, 360), "09_sdf.png");
}
