//! Step 4 — a plane.
//!
//! The plane through a with normal n holds the points p with n·(p − a) = 0. For p(t) = o + t·d:
//! t = n·(a − o) / n·d (no hit when n·d = 0: the ray runs parallel to the plane). The library's
//! `Plane` implements exactly this; the floor here is checkered by the hit point's x and z.

use lancer::math::{Rgb, Vec3};
use lancer_examples::{Canvas, plane, primary_ray, save_or_exit};

/// The image of this step.
pub fn render(width: u32, height: u32) -> Canvas {
    let floor = plane(Vec3::new(0.0, -1.0, 0.0), Vec3::Y);
    Canvas::fill(width, height, |i, j| {
        let ray = primary_ray(i, j, width, height);
        match floor.intersect(&ray) {
            Some(hit) => {
                let p = ray.at(hit.t);
                let odd = (p.x.floor() as i64 + p.z.floor() as i64) & 1 == 1;
                if odd {
                    Rgb::splat(0.9)
                } else {
                    Rgb::new(0.2, 0.3, 0.5)
                }
            }
            None => Rgb::new(0.6, 0.8, 1.0),
        }
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(320, 200), "04-plane.png");
}
