//! Step 2 — from a pixel to the image plane.
//!
//! The eye sits at the origin looking down −z; the image plane is z = −1 and spans [−1, 1].
//! Pixel (i, j)'s centre maps to x = −1 + (2i + 1)/w, y = −1 + (2j + 1)/h. Here each pixel
//! shows the direction d = (x, y, −1)/|(x, y, −1)| as a colour (d + 1)/2.

use lancer::math::{Rgb, normalize};
use lancer_examples::{Canvas, image_plane_point, save_or_exit};

/// The image of this step.
pub fn render(width: u32, height: u32) -> Canvas {
    Canvas::fill(width, height, |i, j| {
        let d = normalize(image_plane_point(i, j, width, height));
        (d + Rgb::ONE) * 0.5
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render(256, 256), "02-image-plane.png");
}
