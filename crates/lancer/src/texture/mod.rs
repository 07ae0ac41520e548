//! Textures: values that vary over a surface, looked up by (u, v) or position.
//!
//! A material parameter is either a constant or a reference to a texture of the scene
//! ([`FloatTex`], [`SpectrumTex`]); the textures themselves are plain data ([`FloatTexture`],
//! [`SpectrumTexture`]) stored in the scene's lists and evaluated by [`TextureEval`].

use crate::image::Image;
pub use crate::image::WrapMode;
use crate::math::{Rgb, Vec2, Vec3};
use std::sync::Arc;

/// A float-valued material parameter: a constant, or the index of a float texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FloatTex {
    /// The same value everywhere.
    Const(f32),
    /// Index into the scene's float textures.
    Tex(u32),
}

/// A colour-valued material parameter: a constant, or the index of a spectrum texture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SpectrumTex {
    /// The same colour everywhere.
    Const(Rgb),
    /// Index into the scene's spectrum textures.
    Tex(u32),
}

/// The (u, v) mapping of pbrt's textures: `(su·u + du, sv·v + dv)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvMapping {
    /// Scale of u (`uscale`).
    pub su: f32,
    /// Scale of v (`vscale`).
    pub sv: f32,
    /// Offset of u (`udelta`).
    pub du: f32,
    /// Offset of v (`vdelta`).
    pub dv: f32,
}

impl Default for UvMapping {
    fn default() -> Self {
        UvMapping {
            su: 1.0,
            sv: 1.0,
            du: 0.0,
            dv: 0.0,
        }
    }
}

impl UvMapping {
    /// The mapped texture coordinates.
    #[inline]
    pub fn map(&self, uv: Vec2) -> Vec2 {
        Vec2::new(self.su * uv.x + self.du, self.sv * uv.y + self.dv)
    }
}

/// An image texture's parameters.
#[derive(Clone, Debug)]
pub struct ImageTexture {
    /// Decoded texels, linear.
    pub image: Arc<Image>,
    /// (u, v) mapping.
    pub mapping: UvMapping,
    /// Behaviour outside [0, 1].
    pub wrap: WrapMode,
    /// Multiplies every value (`scale`).
    pub scale: f32,
    /// `1 − value` (`invert`).
    pub invert: bool,
    /// Nearest-texel lookup instead of bilinear (`filter "point"`).
    pub nearest: bool,
}

/// A float texture (pbrt's float textures), plain data.
#[derive(Clone, Debug)]
pub enum FloatTexture {
    /// A constant.
    Constant(f32),
    /// An image holding the float value in all three channels (the scene reader chooses it as
    /// pbrt-v4 does: alpha, the average of R, G, B, or the first channel); `.x` is read.
    Image(ImageTexture),
    /// Alternates `tex1` and `tex2` on a grid of the mapped (u, v).
    Checkerboard {
        /// (u, v) mapping.
        mapping: UvMapping,
        /// Value on even cells.
        tex1: FloatTex,
        /// Value on odd cells.
        tex2: FloatTex,
    },
    /// `tex · scale`.
    Scale {
        /// The texture scaled.
        tex: FloatTex,
        /// The factor.
        scale: FloatTex,
    },
    /// `(1 − amount)·tex1 + amount·tex2`.
    Mix {
        /// First.
        tex1: FloatTex,
        /// Second.
        tex2: FloatTex,
        /// Blend factor.
        amount: FloatTex,
    },
}

/// A colour texture (pbrt's spectrum textures), plain data.
#[derive(Clone, Debug)]
pub enum SpectrumTexture {
    /// A constant.
    Constant(Rgb),
    /// An image.
    Image(ImageTexture),
    /// Alternates `tex1` and `tex2` on a grid of the mapped (u, v).
    Checkerboard {
        /// (u, v) mapping.
        mapping: UvMapping,
        /// Value on even cells.
        tex1: SpectrumTex,
        /// Value on odd cells.
        tex2: SpectrumTex,
    },
    /// `tex · scale`.
    Scale {
        /// The texture scaled.
        tex: SpectrumTex,
        /// The factor.
        scale: FloatTex,
    },
    /// `(1 − amount)·tex1 + amount·tex2`.
    Mix {
        /// First.
        tex1: SpectrumTex,
        /// Second.
        tex2: SpectrumTex,
        /// Blend factor.
        amount: FloatTex,
    },
}

/// Where a texture is looked up.
#[derive(Clone, Copy, Debug, Default)]
pub struct TexCoord {
    /// Surface (u, v).
    pub uv: Vec2,
    /// World-space position.
    pub p: Vec3,
}

/// Evaluates texture parameters against the scene's texture lists.
#[derive(Clone, Copy)]
pub struct TextureEval<'a> {
    /// The scene's float textures.
    pub floats: &'a [FloatTexture],
    /// The scene's spectrum textures.
    pub spectra: &'a [SpectrumTexture],
}

fn checker(mapping: &UvMapping, uv: Vec2) -> bool {
    let st = mapping.map(uv);
    (st.x.floor() as i64 + st.y.floor() as i64) & 1 == 0
}

impl TextureEval<'_> {
    /// The value of a float parameter at `tc`.
    #[inline(always)]
    pub fn float(&self, t: FloatTex, tc: &TexCoord) -> f32 {
        // Constants inline (most parameters), textures out of line.
        match t {
            FloatTex::Const(v) => v,
            FloatTex::Tex(i) => self.float_texture(i, tc),
        }
    }

    /// The value of texture `i` at `tc`.
    #[inline(never)]
    fn float_texture(&self, i: u32, tc: &TexCoord) -> f32 {
        match &self.floats[i as usize] {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Image(it) => {
                let v = it
                    .image
                    .lookup(it.mapping.map(tc.uv), it.wrap, it.nearest)
                    .x
                    * it.scale;
                if it.invert { (1.0 - v).max(0.0) } else { v }
            }
            FloatTexture::Checkerboard {
                mapping,
                tex1,
                tex2,
            } => {
                if checker(mapping, tc.uv) {
                    self.float(*tex1, tc)
                } else {
                    self.float(*tex2, tc)
                }
            }
            FloatTexture::Scale { tex, scale } => self.float(*tex, tc) * self.float(*scale, tc),
            FloatTexture::Mix { tex1, tex2, amount } => {
                let a = self.float(*amount, tc);
                (1.0 - a) * self.float(*tex1, tc) + a * self.float(*tex2, tc)
            }
        }
    }

    /// The value of a colour parameter at `tc`.
    #[inline(always)]
    pub fn spectrum(&self, t: SpectrumTex, tc: &TexCoord) -> Rgb {
        // Constants inline (most parameters), textures out of line.
        match t {
            SpectrumTex::Const(v) => v,
            SpectrumTex::Tex(i) => self.spectrum_texture(i, tc),
        }
    }

    /// The value of texture `i` at `tc`.
    #[inline(never)]
    fn spectrum_texture(&self, i: u32, tc: &TexCoord) -> Rgb {
        match &self.spectra[i as usize] {
            SpectrumTexture::Constant(v) => *v,
            SpectrumTexture::Image(it) => {
                // pbrt-v4: max(0, invert ? 1 − scale·c : scale·c), in the image's own colour
                // space: texels of a wider space than sRGB may be negative here (their spectra
                // come from `spectrum::uplift`), so only an inverted value is clamped.
                let v = it.image.lookup(it.mapping.map(tc.uv), it.wrap, it.nearest) * it.scale;
                if it.invert {
                    (Rgb::ONE - v).max(Rgb::ZERO)
                } else {
                    v
                }
            }
            SpectrumTexture::Checkerboard {
                mapping,
                tex1,
                tex2,
            } => {
                if checker(mapping, tc.uv) {
                    self.spectrum(*tex1, tc)
                } else {
                    self.spectrum(*tex2, tc)
                }
            }
            SpectrumTexture::Scale { tex, scale } => {
                self.spectrum(*tex, tc) * self.float(*scale, tc)
            }
            SpectrumTexture::Mix { tex1, tex2, amount } => {
                let a = self.float(*amount, tc);
                (1.0 - a) * self.spectrum(*tex1, tc) + a * self.spectrum(*tex2, tc)
            }
        }
    }
}
