//! In-memory images: linear float texels, for textures and environment maps.

use crate::math::{Rgb, Vec2};
use crate::texture::WrapMode;

/// A linear RGB image, row 0 at the top, stored row-major as `width × height` texels.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels, `y·width + x`.
    pub texels: Vec<Rgb>,
}

impl Image {
    /// An image from its texels; `None` if the sizes disagree or the image is empty.
    pub fn new(width: u32, height: u32, texels: Vec<Rgb>) -> Option<Image> {
        (width > 0 && height > 0 && texels.len() == width as usize * height as usize).then_some(
            Image {
                width,
                height,
                texels,
            },
        )
    }

    /// The texel at integer coordinates, with the wrap mode applied.
    pub fn texel(&self, x: i64, y: i64, wrap: WrapMode) -> Rgb {
        let (w, h) = (self.width as i64, self.height as i64);
        let fix = |v: i64, n: i64| -> Option<i64> {
            match wrap {
                WrapMode::Repeat => Some(v.rem_euclid(n)),
                WrapMode::Clamp => Some(v.clamp(0, n - 1)),
                WrapMode::Black => (0..n).contains(&v).then_some(v),
                WrapMode::Mirror => {
                    let m = v.rem_euclid(2 * n);
                    Some(if m < n { m } else { 2 * n - 1 - m })
                }
            }
        };
        match (fix(x, w), fix(y, h)) {
            (Some(x), Some(y)) => self.texels[(y * w + x) as usize],
            _ => Rgb::ZERO,
        }
    }

    /// Bilinear (or nearest) lookup at texture coordinates `st`, where (0, 0) is the image's
    /// bottom-left corner and (1, 1) its top-right (pbrt's convention: v grows upwards).
    pub fn lookup(&self, st: Vec2, wrap: WrapMode, nearest: bool) -> Rgb {
        let x = st.x * self.width as f32 - 0.5;
        let y = (1.0 - st.y) * self.height as f32 - 0.5;
        if !x.is_finite() || !y.is_finite() {
            return Rgb::ZERO;
        }
        if nearest {
            return self.texel((x + 0.5).floor() as i64, (y + 0.5).floor() as i64, wrap);
        }
        let (x0, y0) = (x.floor(), y.floor());
        let (dx, dy) = (x - x0, y - y0);
        let (xi, yi) = (x0 as i64, y0 as i64);
        (1.0 - dx) * (1.0 - dy) * self.texel(xi, yi, wrap)
            + dx * (1.0 - dy) * self.texel(xi + 1, yi, wrap)
            + (1.0 - dx) * dy * self.texel(xi, yi + 1, wrap)
            + dx * dy * self.texel(xi + 1, yi + 1, wrap)
    }
}
