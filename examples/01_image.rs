//! Step 1 — an image is a grid of pixels, filled by a loop.
//!
//! Pixel (0, 0) is the bottom-left one: red grows to the right (with i), green upwards (with j).

use lancer::math::Rgb;
use lancer_examples::{Canvas, save_or_exit};

/// The image of this step.
pub fn render(width: u32, height: u32) -> Canvas {
    Canvas::fill(width, height, |i, j| {
        Rgb::new(
            (i as f32 + 0.5) / width as f32,
            (j as f32 + 0.5) / height as f32,
            0.25,
        )
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(256, 192), "01-image.png");
}
