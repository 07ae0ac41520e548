//! The `imagemap` texture: a filtered image lookup, scaled and optionally inverted.
//!
//! Its description ([`ImageTextureDesc`]) holds the decoded texels, plain data shared by every
//! texture of the same file; the scene build makes the MIP pyramid ([`ImageTexture`]), once per
//! distinct image and pyramid settings ([`Pyramids`]).

use super::{At, TextureDescKind, TextureKind};
use crate::image::{Image, WrapMode};
use crate::math::{Mat3, Rgb};
use crate::texture::{ImageFilter, Mapping2D, MipMap, Pyramids, TexCoord};
use std::sync::Arc;

/// An image texture as a scene gives it (float and spectrum `imagemap`, a normal map, a
/// glTF or OBJ texture), plain data.
#[derive(Clone, Debug)]
pub struct ImageTextureDesc {
    /// The texels, linear (a float texture's value in all three channels), row 0 at the top;
    /// textures of the same file (and encoding, and float channel) share them.
    pub image: Arc<Image>,
    /// The matrix that took the file's own RGB (an EXR's `chromaticities`) to linear sRGB;
    /// `None` for sRGB texels and float textures. The pyramid clamps resampled texels in the
    /// file's space, as pbrt-v4 does.
    pub to_srgb: Option<Mat3>,
    /// Whether lookups filter over a MIP pyramid of the image (pbrt-v4's `imagemap`); without
    /// one they read the image itself, bilinearly or nearest (normal maps, glTF's textures).
    pub mip: bool,
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

/// An image texture as the renderer reads it: the description's settings and its MIP pyramid.
#[derive(Clone, Debug)]
pub struct ImageTexture {
    /// The texels' MIP pyramid ([`MipMap::single`] for none), shared by the textures of the
    /// same image and pyramid settings.
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

impl TextureDescKind for ImageTextureDesc {
    type Built = ImageTexture;
    /// The texture the renderer reads: these settings and the image's pyramid, taken from
    /// `pyramids` (made there on first use).
    fn build(&self, pyramids: &mut Pyramids) -> ImageTexture {
        ImageTexture {
            mipmap: pyramids.get(&self.image, self.mip, self.wrap, self.to_srgb),
            mapping: self.mapping,
            wrap: self.wrap,
            scale: self.scale,
            invert: self.invert,
            filter: self.filter,
        }
    }
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
