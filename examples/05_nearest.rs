//! Step 5 — several objects: keep the nearest valid hit.
//!
//! Every object is intersected; a hit counts when t > 0 (in front of the eye) and the one with
//! the smallest t is what the pixel sees. The yellow sphere sits behind the camera: its hits
//! have t < 0 and it never appears.

use lancer::math::{Rgb, Vec3};
use lancer::shape::Shape;
use lancer_examples::{Canvas, nearest_hit, plane, primary_ray, save_or_exit, sphere};

/// The objects of this step and their colours.
pub fn scene() -> (Vec<Shape>, Vec<Rgb>) {
    let objects = vec![
        plane(Vec3::new(0.0, -1.0, 0.0), Vec3::Y),
        sphere(Vec3::new(-0.8, -0.2, -3.0), 0.8),
        sphere(Vec3::new(0.3, 0.0, -4.0), 1.0),
        sphere(Vec3::new(1.6, 0.5, -5.5), 1.5),
        sphere(Vec3::new(0.0, 0.0, 2.0), 1.0),
    ];
    let colours = vec![
        Rgb::splat(0.5),
        Rgb::new(0.8, 0.2, 0.2),
        Rgb::new(0.2, 0.8, 0.2),
        Rgb::new(0.2, 0.2, 0.8),
        Rgb::new(0.9, 0.9, 0.1),
    ];
    (objects, colours)
}

/// The image of this step: each pixel takes the flat colour of the nearest object.
pub fn render(width: u32, height: u32) -> Canvas {
    let (objects, colours) = scene();
    Canvas::fill(width, height, |i, j| {
        let ray = primary_ray(i, j, width, height);
        nearest_hit(&objects, &ray).map_or(Rgb::ZERO, |(k, _)| colours[k])
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(320, 200), "05-nearest.png");
}
