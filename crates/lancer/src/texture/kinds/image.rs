//! The `imagemap` texture: a filtered image lookup, scaled and optionally inverted.

use super::{At, TextureKind};
use crate::image::WrapMode;
use crate::math::Rgb;
use crate::texture::{ImageFilter, Mapping2D, MipMap, TexCoord};
use std::sync::Arc;

/// An image texture's parameters (float and spectrum `imagemap`), plain data.
#[derive(Clone, Debug)]
pub struct ImageTexture {
    /// Decoded texels, linear, and their MIP pyramid ([`MipMap::single`] for none).
    pub mipmap: Arc<MipMap>,
    /// Texture-coordinate mapping.
    pub mapping: Mapping2D,
    /// Behaviour outside [0, 1].
    pub wrap: WrapMode,
    /// Multiplies every value (`scale`).
    pub scale: f32,
    /// `1 − value` (`invert`).
    pub invert: bool,
    /// How lookups are filtered over their footprint (`filter`, `maxanisotropy`).
    pub filter: ImageFilter,
}

impl ImageTexture {
    /// The filtered colour at `tc` over its footprint, before `scale` and `invert`. pbrt-v4
    /// flips t (texture (0, 0) is the image's lower left); the MIP-map's lookups do that.
    #[inline]
    fn value(&self, tc: &TexCoord) -> Rgb {
        self.mipmap
            .filter(self.filter, self.wrap, &self.mapping.map_footprint(tc))
    }
}

impl TextureKind<f32> for ImageTexture {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> f32 {
        // pbrt-v4: v = scale·texel; invert gives max(0, 1 − v).
        let v = self.value(at.tc).x * self.scale;
        if self.invert { (1.0 - v).max(0.0) } else { v }
    }
}

impl TextureKind<Rgb> for ImageTexture {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> Rgb {
        // pbrt-v4: max(0, invert ? 1 − scale·c : scale·c), in the image's own colour space:
        // texels of a wider space than sRGB may be negative here (their spectra come from
        // `spectrum::uplift`), so only an inverted value is clamped.
        let v = self.value(at.tc) * self.scale;
        if self.invert {
            (Rgb::ONE - v).max(Rgb::ZERO)
        } else {
            v
        }
    }
}
