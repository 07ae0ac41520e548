//! What the course's example programs share: a canvas addressed the lecture's way (pixel (0, 0)
//! at the bottom-left) and the mapping from a pixel to the image plane.
//!
//! Each example in this folder is one step of the lecture "lancer de rayons"; run one with
//! `cargo run --release -p lancer-examples --example 03_sphere`. It writes a PNG into the
//! current folder (or into `$LANCER_EXAMPLES_OUT` when set).

use lancer::math::{Rgb, Vec3};
use std::path::{Path, PathBuf};

/// An image being drawn, pixel (0, 0) at the bottom-left as in the lecture.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Rows from the bottom up: `pixels[j * width + i]` is pixel (i, j).
    pixels: Vec<Rgb>,
}

impl Canvas {
    /// A black canvas.
    pub fn new(width: u32, height: u32) -> Canvas {
        Canvas {
            width,
            height,
            pixels: vec![Rgb::ZERO; (width * height) as usize],
        }
    }

    /// Fills every pixel (i, j) with `f(i, j)`: the lecture's image loop.
    pub fn fill(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> Rgb) -> Canvas {
        let mut c = Canvas::new(width, height);
        for j in 0..height {
            for i in 0..width {
                c.pixels[(j * width + i) as usize] = f(i, j);
            }
        }
        c
    }

    /// Pixel (i, j), counted from the bottom-left.
    pub fn get(&self, i: u32, j: u32) -> Rgb {
        self.pixels[(j * self.width + i) as usize]
    }

    /// Writes the canvas as a PNG (rows flipped: image files store the top row first).
    pub fn save(&self, path: &Path) -> Result<(), lancer::image_io::ImageWriteError> {
        let mut top_down = Vec::with_capacity(self.pixels.len());
        for j in (0..self.height).rev() {
            let row = (j * self.width) as usize;
            top_down.extend_from_slice(&self.pixels[row..row + self.width as usize]);
        }
        lancer::image_io::write_image(path, self.width, self.height, &top_down)
    }
}

/// The point of the image plane z = −1 seen through the centre of pixel (i, j): the plane spans
/// [−1, 1] on the image's shorter axis, so a square image covers exactly [−1, 1]².
///
/// x = (−1 + (2i + 1)/w)·(w/s), y = (−1 + (2j + 1)/h)·(h/s) with s = min(w, h).
pub fn image_plane_point(i: u32, j: u32, width: u32, height: u32) -> Vec3 {
    let s = width.min(height) as f32;
    let x = (-1.0 + (2 * i + 1) as f32 / width as f32) * (width as f32 / s);
    let y = (-1.0 + (2 * j + 1) as f32 / height as f32) * (height as f32 / s);
    Vec3::new(x, y, -1.0)
}

/// The ray of the lecture for pixel (i, j): from the eye at the origin through the image plane.
pub fn primary_ray(i: u32, j: u32, width: u32, height: u32) -> lancer::ray::Ray {
    lancer::ray::Ray::new(Vec3::ZERO, image_plane_point(i, j, width, height))
}

/// Where an example writes its image: `$LANCER_EXAMPLES_OUT/name` or `./name`.
pub fn out_path(name: &str) -> PathBuf {
    std::env::var_os("LANCER_EXAMPLES_OUT")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("."))
        .join(name)
}

/// Saves a canvas where [`out_path`] says and prints the path; the examples' `main`.
pub fn save_or_exit(canvas: &Canvas, name: &str) {
    let path = out_path(name);
    match canvas.save(&path) {
        Ok(()) => println!("wrote {}", path.display()),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}

/// A sphere of radius `r` centred at `c` (the library's shape, placed by a translation).
pub fn sphere(c: Vec3, r: f32) -> lancer::shape::Shape {
    use lancer::shape::{Placement, Shape, Sphere};
    let placement = Placement::new(lancer::math::Transform::translate(c), false);
    Shape::Sphere(Box::new(Sphere::new(placement, r, -r, r, 360.0)))
}

/// The infinite plane through `a` with normal `n`.
pub fn plane(a: Vec3, n: Vec3) -> lancer::shape::Shape {
    lancer::shape::Shape::Plane(Box::new(
        lancer::shape::Plane::new(a, n).expect("non-zero normal"),
    ))
}

/// The nearest valid hit of `ray` among `objects`: the smallest t with t > 0, as the index of
/// the object and the surface found there.
pub fn nearest_hit(
    objects: &[lancer::shape::Shape],
    ray: &lancer::ray::Ray,
) -> Option<(usize, lancer::shape::SurfaceInteraction)> {
    let mut best: Option<(usize, lancer::shape::ShapeHit)> = None;
    for (k, object) in objects.iter().enumerate() {
        if let Some(hit) = object.intersect(ray)
            && best.is_none_or(|(_, b)| hit.t < b.t)
        {
            best = Some((k, hit));
        }
    }
    best.map(|(k, hit)| (k, objects[k].interaction(ray, &hit, &[])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn image_plane_spans_minus_one_to_one() {
        // Pixel centres of a 2×2 image sit at ±1/2.
        assert_eq!(image_plane_point(0, 0, 2, 2), Vec3::new(-0.5, -0.5, -1.0));
        assert_eq!(image_plane_point(1, 1, 2, 2), Vec3::new(0.5, 0.5, -1.0));
        // A wide image keeps [−1, 1] vertically and widens horizontally.
        let p = image_plane_point(3, 0, 4, 2);
        assert_eq!((p.x, p.y), (1.5, -0.5));
    }
}
