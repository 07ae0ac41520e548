//! Step 3 — a ray and a sphere.
//!
//! The ray through a pixel is p(t) = o + t·d. A point p is on the sphere of centre c and radius
//! r when |p − c|² = r²; substituting p(t) gives the quadratic
//! (d·d)t² + 2(d·co)t + co·co − r² = 0 with co = o − c. Real roots are the hits; the visible one
//! is the smallest positive root.

use lancer::math::{Rgb, Vec3, solve_quadratic};
use lancer::ray::Ray;
use lancer_examples::{Canvas, primary_ray, save_or_exit};

/// The smallest positive root of the course's quadratic, if any.
pub fn hit_sphere(ray: &Ray, c: Vec3, r: f32) -> Option<f32> {
    let co = (ray.o - c).as_dvec3();
    let d = ray.d.as_dvec3();
    let (t0, t1) = solve_quadratic(d.dot(d), 2.0 * d.dot(co), co.dot(co) - (r as f64).powi(2))?;
    [t0, t1].into_iter().find(|&t| t > 0.0).map(|t| t as f32)
}

/// The image of this step: the sphere shaded by its normal, (n + 1)/2.
pub fn render(width: u32, height: u32) -> Canvas {
    let (c, r) = (Vec3::new(0.0, 0.0, -3.0), 1.0);
    Canvas::fill(width, height, |i, j| {
        let ray = primary_ray(i, j, width, height);
        match hit_sphere(&ray, c, r) {
            Some(t) => ((ray.at(t) - c) / r + Rgb::ONE) * 0.5,
            None => Rgb::splat(0.1),
        }
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(256, 256), "03-sphere.png");
}
