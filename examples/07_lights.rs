//! Step 7 — several lights, several colours.
//!
//! Light adds up: the radiance at a point is the sum of what each light gives it, each with its
//! own shadow ray. Colours are handled channel by channel (red light on a green surface gives
//! nothing).

use lancer::math::{Rgb, Vec3};
use lancer_examples::{Canvas, nearest_hit, primary_ray, save_or_exit};

#[path = "06_shadows.rs"]
#[allow(dead_code)]
pub mod step6;
use step6::{PointLight, shade};

/// The lights of this step: a red, a blue and a white light.
pub fn lights() -> Vec<PointLight> {
    vec![
        PointLight {
            at: Vec3::new(-3.0, 3.0, 0.0),
            intensity: Rgb::new(12.0, 3.0, 3.0),
        },
        PointLight {
            at: Vec3::new(3.0, 3.0, -4.0),
            intensity: Rgb::new(3.0, 3.0, 12.0),
        },
        PointLight {
            at: Vec3::new(0.0, 6.0, -1.0),
            intensity: Rgb::splat(8.0),
        },
    ]
}

/// The image of this step: step 6's objects under three lights.
pub fn render(width: u32, height: u32) -> Canvas {
    let (objects, albedos, _) = step6::scene();
    let lights = lights();
    Canvas::fill(width, height, |i, j| {
        let ray = primary_ray(i, j, width, height);
        nearest_hit(&objects, &ray).map_or(Rgb::ZERO, |(k, si)| {
            shade(&objects, &si, albedos[k], &lights)
        })
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(320, 240), "07-lights.png");
}
