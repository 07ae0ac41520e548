//! The `bilerp` texture: bilinear interpolation of four corner values.

use super::{At, PlainKind, TextureKind};
use crate::math::Vec2;
use crate::texture::Mapping2D;
use std::ops::{Add, Mul};

/// Bilinear interpolation of four corner values over (s, t), plain data; `V` is `f32` or
/// [`crate::math::Rgb`].
#[derive(Clone, Debug)]
pub struct BilerpTexture<V> {
    /// Texture-coordinate mapping.
    pub mapping: Mapping2D,
    /// Values at (0, 0), (0, 1), (1, 0), (1, 1).
    pub v: [V; 4],
}

/// Bilinear interpolation of four corner values at (s, t) (not clamped: pbrt-v4 extrapolates
/// outside [0, 1]²): `(1−s)(1−t)·v00 + s(1−t)·v10 + (1−s)t·v01 + st·v11`.
#[inline]
pub fn bilerp<T>(st: Vec2, v00: T, v01: T, v10: T, v11: T) -> T
where
    T: Mul<f32, Output = T> + Add<Output = T>,
{
    let (s, t) = (st.x, st.y);
    v00 * ((1.0 - s) * (1.0 - t)) + v10 * (s * (1.0 - t)) + v01 * ((1.0 - s) * t) + v11 * (s * t)
}

impl<V: Copy + Mul<f32, Output = V> + Add<Output = V>> TextureKind<V> for BilerpTexture<V> {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> V {
        let v = &self.v;
        bilerp(self.mapping.map(at.tc), v[0], v[1], v[2], v[3])
    }
}

/// Its description is what the renderer reads.
impl<V: Clone> PlainKind for BilerpTexture<V> {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rgb;

    #[test]
    fn bilerp_hits_the_corners_and_the_centre_average() {
        let f = |s, t| bilerp(Vec2::new(s, t), 1.0f32, 2.0, 3.0, 4.0);
        assert_eq!(
            (f(0.0, 0.0), f(0.0, 1.0), f(1.0, 0.0), f(1.0, 1.0)),
            (1.0, 2.0, 3.0, 4.0)
        );
        assert_eq!(f(0.5, 0.5), 2.5);
        // v10 at s = 1: red at (1, 0).
        let c = bilerp(Vec2::new(1.0, 0.0), Rgb::X, Rgb::Y, Rgb::Z, Rgb::ONE);
        assert_eq!(c, Rgb::Z);
    }
}
