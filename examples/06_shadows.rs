//! Step 6 — how a point is lit: a point light, Lambert's law, and shadows.
//!
//! A point light of intensity I at position l lights a diffuse surface point p (albedo ρ,
//! normal n) with radiance L = ρ/π · I · cos θ / r², where r = |l − p| and cos θ = n·(l − p)/r,
//! provided nothing lies between p and l: a shadow ray from p towards l must reach it.
//! The shadow ray starts just off the surface (by the hit point's rounding-error bound), so it
//! cannot find the surface it leaves.

use lancer::math::{INV_PI, Rgb, Vec3};
use lancer::shape::{Shape, SurfaceInteraction};
use lancer_examples::{Canvas, nearest_hit, plane, primary_ray, save_or_exit, sphere};

/// A point light.
#[derive(Clone, Copy, Debug)]
pub struct PointLight {
    /// Position.
    pub at: Vec3,
    /// Intensity (per colour channel).
    pub intensity: Rgb,
}

/// True when nothing among `objects` blocks the segment from the surface point to `target`.
pub fn visible(objects: &[Shape], si: &SurfaceInteraction, target: Vec3) -> bool {
    let shadow_ray = si.spawn_ray_to(target);
    !objects.iter().any(|o| o.intersect(&shadow_ray).is_some())
}

/// Radiance leaving a diffuse point towards the eye, lit by `lights`:
/// Σ ρ/π · I · max(0, cos θ) / r² over the lights that the point sees.
pub fn shade(
    objects: &[Shape],
    si: &SurfaceInteraction,
    albedo: Rgb,
    lights: &[PointLight],
) -> Rgb {
    // Light the side the eye sees.
    let n = if si.n.dot(si.wo) < 0.0 { -si.n } else { si.n };
    let mut l = Rgb::ZERO;
    for light in lights {
        let to_light = light.at - si.p;
        let r2 = to_light.length_squared();
        let cos_theta = n.dot(to_light) / r2.sqrt();
        if cos_theta > 0.0 && visible(objects, si, light.at) {
            l += albedo * INV_PI * light.intensity * cos_theta / r2;
        }
    }
    l
}

/// The objects, their albedos and the light of this step.
pub fn scene() -> (Vec<Shape>, Vec<Rgb>, Vec<PointLight>) {
    let objects = vec![
        plane(Vec3::new(0.0, -1.0, 0.0), Vec3::Y),
        sphere(Vec3::new(-0.7, -0.3, -3.0), 0.7),
        sphere(Vec3::new(0.9, -0.5, -2.5), 0.5),
    ];
    let albedos = vec![
        Rgb::splat(0.7),
        Rgb::new(0.8, 0.5, 0.2),
        Rgb::new(0.3, 0.6, 0.9),
    ];
    let lights = vec![PointLight {
        at: Vec3::new(3.0, 4.0, 0.0),
        intensity: Rgb::splat(15.0),
    }];
    (objects, albedos, lights)
}

/// The image of this step.
pub fn render(width: u32, height: u32) -> Canvas {
    let (objects, albedos, lights) = scene();
    Canvas::fill(width, height, |i, j| {
        let ray = primary_ray(i, j, width, height);
        nearest_hit(&objects, &ray).map_or(Rgb::ZERO, |(k, si)| {
            shade(&objects, &si, albedos[k], &lights)
        })
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(320, 240), "06-shadows.png");
}
