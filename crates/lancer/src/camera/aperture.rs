//! The transmission of a shaped aperture stop, as pbrt-v4's `RealisticCamera` builds it: a
//! one-channel image over the stop's bounding square, looked up bilinearly (black outside) at
//! ((x/r + 1)/2, (y/r + 1)/2) for a point (x, y) on a stop of radius r.
//!
//! The built-in shapes are drawn on 256 × 256 texels (pixel centres at −1 + 2(i + ½)/256);
//! polygons are filled by their winding number. Every mask, built-in or from an image, is
//! flipped vertically (row 0 becomes y = −1, as pbrt-v4's `FlipY`) and scaled so that its mean
//! is π/4, the fraction of the square a circular stop covers: a shaped stop then passes as much
//! light as the circular one it replaces.

use super::lens::Aperture;
use crate::math::{PI, Rgb, Vec2};

/// Side of the built-in masks in texels.
const BUILTIN_RES: usize = 256;

/// An aperture's transmission over [0, 1]² (row 0 at v = 0).
#[derive(Clone, Debug, PartialEq)]
pub struct ApertureMask {
    width: usize,
    height: usize,
    values: Vec<f32>,
}

impl ApertureMask {
    /// The mask of `aperture`; `None` for a circular stop (no mask: the disk test is exact),
    /// an error for an image that lets no light through or holds values that are not finite.
    pub fn new(aperture: &Aperture) -> Result<Option<ApertureMask>, String> {
        let n = BUILTIN_RES;
        let centre = |i: usize| -1.0 + 2.0 * (i as f32 + 0.5) / n as f32;
        let (width, height, mut values) = match aperture {
            Aperture::Circular => return Ok(None),
            Aperture::Gaussian => {
                let mut v = Vec::with_capacity(n * n);
                for y in 0..n {
                    for x in 0..n {
                        // σ² = 1: exp(−r²) − exp(−1), zero beyond the unit circle.
                        let r2 = centre(x).powi(2) + centre(y).powi(2);
                        v.push(((-r2).exp() - (-1.0f32).exp()).max(0.0));
                    }
                }
                (n, n, v)
            }
            Aperture::Square => {
                let mut v = vec![0.0; n * n];
                for y in n / 4..3 * n / 4 {
                    for x in n / 4..3 * n / 4 {
                        v[y * n + x] = 4.0;
                    }
                }
                (n, n, v)
            }
            Aperture::Pentagon => (n, n, rasterize(&pentagon())),
            Aperture::Star => (n, n, rasterize(&star())),
            Aperture::Image(image) => {
                let v = image
                    .texels
                    .iter()
                    .map(|&t| {
                        let c = Rgb::from(t);
                        (c.x + c.y + c.z) / 3.0
                    })
                    .collect();
                (image.width as usize, image.height as usize, v)
            }
        };
        // pbrt-v4's FlipY: row 0 of the mask is the bottom (y = −1) of the stop.
        for y in 0..height / 2 {
            for x in 0..width {
                values.swap(y * width + x, (height - 1 - y) * width + x);
            }
        }
        let sum: f64 = values.iter().map(|&v| v as f64).sum();
        let avg = sum / (width * height) as f64;
        if !(avg > 0.0 && avg.is_finite()) {
            return Err(
                "the aperture image must let some light through and hold finite values only".into(),
            );
        }
        let scale = (PI as f64 / 4.0 / avg) as f32;
        for v in &mut values {
            *v *= scale;
        }
        Ok(Some(ApertureMask {
            width,
            height,
            values,
        }))
    }

    /// Bilinear lookup at `uv` ∈ [0, 1]², black outside: texel centres at ((i + ½)/w,
    /// (j + ½)/h), as pbrt-v4's `Image::Bilerp`.
    pub fn bilerp(&self, uv: Vec2) -> f32 {
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * self.height as f32 - 0.5;
        let (xf, yf) = (x.floor(), y.floor());
        let (dx, dy) = (x - xf, y - yf);
        let (xi, yi) = (xf as i64, yf as i64);
        let at = |x: i64, y: i64| {
            if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
                0.0
            } else {
                self.values[y as usize * self.width + x as usize]
            }
        };
        (1.0 - dx) * (1.0 - dy) * at(xi, yi)
            + dx * (1.0 - dy) * at(xi + 1, yi)
            + (1.0 - dx) * dy * at(xi, yi + 1)
            + dx * dy * at(xi + 1, yi + 1)
    }
}

/// A regular pentagon of circumradius 0.8, a vertex up, clockwise.
fn pentagon() -> Vec<Vec2> {
    let s5 = 5.0f32.sqrt();
    let (c1, c2) = ((s5 - 1.0) / 4.0, (s5 + 1.0) / 4.0);
    let s1 = (10.0 + 2.0 * s5).sqrt() / 4.0;
    let s2 = (10.0 - 2.0 * s5).sqrt() / 4.0;
    [(0.0, 1.0), (s1, c1), (s2, -c2), (-s2, -c2), (-s1, c1)]
        .into_iter()
        .map(|(x, y)| 0.8 * Vec2::new(x, y))
        .collect()
}

/// A five-pointed star: points at radius 1 (odd vertices) and notches at cos 72°/cos 36°,
/// every 36°, in reverse order.
fn star() -> Vec<Vec2> {
    let inner = 72.0f32.to_radians().cos() / 36.0f32.to_radians().cos();
    let mut v: Vec<Vec2> = (0..10)
        .map(|i| {
            let r = if i & 1 == 1 { 1.0 } else { inner };
            let a = PI * i as f32 / 5.0;
            Vec2::new(r * a.cos(), r * a.sin())
        })
        .collect();
    v.reverse();
    v
}

/// 1 at the pixel centres a polygon winds around (non-zero winding number), else 0.
fn rasterize(vert: &[Vec2]) -> Vec<f32> {
    let n = BUILTIN_RES;
    let mut out = Vec::with_capacity(n * n);
    for y in 0..n {
        for x in 0..n {
            let p = Vec2::new(
                -1.0 + 2.0 * (x as f32 + 0.5) / n as f32,
                -1.0 + 2.0 * (y as f32 + 0.5) / n as f32,
            );
            let mut winding = 0;
            for i in 0..vert.len() {
                let (a, b) = (vert[i], vert[(i + 1) % vert.len()]);
                // Which side of the edge a→b the point is on.
                let e = (p.x - a.x) * (b.y - a.y) - (p.y - a.y) * (b.x - a.x);
                if a.y <= p.y {
                    if b.y > p.y && e > 0.0 {
                        winding += 1;
                    }
                } else if b.y <= p.y && e < 0.0 {
                    winding -= 1;
                }
            }
            out.push(if winding == 0 { 0.0 } else { 1.0 });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;
    use crate::math::PackedRgb;
    use std::sync::Arc;

    /// Mean of the mask's texels.
    fn mean(m: &ApertureMask) -> f32 {
        (m.values.iter().map(|&v| v as f64).sum::<f64>() / m.values.len() as f64) as f32
    }

    #[test]
    fn every_shape_passes_as_much_light_as_a_circle() {
        for a in [
            Aperture::Gaussian,
            Aperture::Square,
            Aperture::Pentagon,
            Aperture::Star,
        ] {
            let m = ApertureMask::new(&a).unwrap().unwrap();
            assert!((mean(&m) - PI / 4.0).abs() < 1e-4, "{a:?}: {}", mean(&m));
            // The centre is open, the corners closed.
            assert!(m.bilerp(Vec2::splat(0.5)) > 0.0, "{a:?}");
            assert_eq!(m.bilerp(Vec2::new(0.01, 0.01)), 0.0, "{a:?}");
            // Outside the square: black.
            assert_eq!(m.bilerp(Vec2::new(1.2, 0.5)), 0.0);
        }
        assert_eq!(ApertureMask::new(&Aperture::Circular), Ok(None));
    }

    #[test]
    fn the_square_covers_the_middle_quarter() {
        // Value 4 on a quarter of the texels: mean 1, scaled to π/4, so π inside.
        let m = ApertureMask::new(&Aperture::Square).unwrap().unwrap();
        assert!((m.bilerp(Vec2::new(0.3, 0.7)) - PI).abs() < 1e-5);
        assert_eq!(m.bilerp(Vec2::new(0.2, 0.5)), 0.0);
    }

    #[test]
    fn polygons_are_flipped_vertically_as_pbrt_does() {
        // The pentagon's apex (0, 0.8) is drawn at the top row side; after the flip it is
        // at v = 0.1 (y = −0.8): open just inside it, closed just outside the opposite edge.
        let m = ApertureMask::new(&Aperture::Pentagon).unwrap().unwrap();
        assert!(m.bilerp(Vec2::new(0.5, 0.12)) > 0.0);
        assert_eq!(m.bilerp(Vec2::new(0.5, 0.88)), 0.0);
        // The pentagon's flat edge is at y = −0.8·c2 ≈ −0.647 before the flip, 0.647 after:
        // v = (0.647 + 1)/2 ≈ 0.82.
        assert!(m.bilerp(Vec2::new(0.5, 0.80)) > 0.0);
        assert_eq!(m.bilerp(Vec2::new(0.5, 0.85)), 0.0);
    }

    #[test]
    fn images_give_their_channel_average_flipped() {
        // 2×2: top row white, bottom row black. After the flip the white row is at v > ½.
        let texels = vec![
            PackedRgb::ONE,
            PackedRgb::ONE,
            PackedRgb::ZERO,
            PackedRgb::ZERO,
        ];
        let img = Arc::new(Image::new(2, 2, texels).unwrap());
        let m = ApertureMask::new(&Aperture::Image(img)).unwrap().unwrap();
        // Mean ½ scaled to π/4: white texels hold π/2.
        assert!((m.bilerp(Vec2::new(0.25, 0.75)) - PI / 2.0).abs() < 1e-5);
        assert_eq!(m.bilerp(Vec2::new(0.25, 0.25)), 0.0);
        let black = Arc::new(Image::new(1, 1, vec![PackedRgb::ZERO]).unwrap());
        assert!(ApertureMask::new(&Aperture::Image(black)).is_err());
    }
}
