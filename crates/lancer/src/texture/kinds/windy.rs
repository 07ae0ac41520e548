//! The `windy` texture: wind-swept waves in texture space.

use super::{At, PlainKind, TextureKind};
use crate::math::Vec3;
use crate::math::noise::fbm;
use crate::texture::Mapping3D;

/// Wind-swept waves ([`windy`]) in texture space, plain data.
#[derive(Clone, Debug)]
pub struct WindyTexture {
    /// Texture space.
    pub mapping: Mapping3D,
}

/// pbrt-v4's `WindyTexture`: `|fbm(p/10, ω = ½, 3 octaves)| · fbm(p, ω = ½, 6 octaves)`, wind
/// strength times wave height (no footprint: every octave).
pub fn windy(p: Vec3) -> f32 {
    let z = Vec3::ZERO;
    let wind = fbm(0.1 * p, z, z, 0.5, 3);
    let wave = fbm(p, z, z, 0.5, 6);
    wind.abs() * wave
}

impl TextureKind<f32> for WindyTexture {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> f32 {
        windy(self.mapping.map(at.tc))
    }
}

/// Its description is what the renderer reads.
impl PlainKind for WindyTexture {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windy_is_zero_where_the_wind_is() {
        // At the origin every octave of both fbm sums is noise at a lattice point: 0.
        assert_eq!(windy(Vec3::ZERO), 0.0);
        let v = windy(Vec3::new(3.3, 1.2, -0.7));
        assert!(v.is_finite() && v.abs() < 2.0);
    }
}
