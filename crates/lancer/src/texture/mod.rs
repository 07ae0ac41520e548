//! Textures: values that vary over a surface, looked up by (u, v) or position.
//!
//! A material parameter is either a constant or a reference to a texture of the scene
//! ([`FloatTex`], [`SpectrumTex`]); the textures themselves are plain data ([`FloatTexture`],
//! [`SpectrumTexture`]) stored in the scene's lists and evaluated by [`TextureEval`].

mod eval;
mod mapping;
pub mod mipmap;
pub mod procedural;
mod spectral;

pub use crate::image::WrapMode;
use crate::math::{Rgb, Vec3};
use crate::spectrum::dense::Measured;
pub use mapping::{Mapping2D, Mapping3D, TexCoord, UvMapping};
pub use mipmap::{ImageFilter, MipMap, StFootprint};
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
    /// The same spectrum everywhere, given as a spectrum (a named spectrum, `blackbody`, an
    /// `.spd` file): RGB mode reads its reduction, spectral mode its table.
    Measured(Measured),
    /// Index into the scene's spectrum textures.
    Tex(u32),
}

/// An image texture's parameters.
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

/// A float texture (pbrt's float textures), plain data.
#[derive(Clone, Debug)]
pub enum FloatTexture {
    /// A constant.
    Constant(f32),
    /// An image holding the float value in all three channels (the scene reader chooses it as
    /// pbrt-v4 does: alpha, the average of R, G, B, or the first channel); `.x` is read.
    Image(ImageTexture),
    /// Alternates `tex1` and `tex2` on a grid of the mapped (s, t).
    Checkerboard {
        /// Texture-coordinate mapping.
        mapping: Mapping2D,
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
    /// Alternates `tex1` and `tex2` on unit cubes of texture space (`dimension` 3).
    Checkerboard3D {
        /// Texture space.
        mapping: Mapping3D,
        /// Value on even cells.
        tex1: FloatTex,
        /// Value on odd cells.
        tex2: FloatTex,
    },
    /// Bilinear interpolation of four corner values over (s, t).
    Bilerp {
        /// Texture-coordinate mapping.
        mapping: Mapping2D,
        /// Values at (0, 0), (0, 1), (1, 0), (1, 1).
        v: [f32; 4],
    },
    /// Polka dots ([`procedural::inside_polka_dot`]).
    Dots {
        /// Texture-coordinate mapping.
        mapping: Mapping2D,
        /// Value inside a dot (pbrt-v4's `outside` parameter: it swaps the two).
        dot: FloatTex,
        /// Value between the dots (pbrt-v4's `inside` parameter).
        background: FloatTex,
    },
    /// Fractional Brownian motion ([`crate::math::noise::fbm`]) in texture space.
    Fbm {
        /// Texture space.
        mapping: Mapping3D,
        /// Maximum number of octaves.
        octaves: u32,
        /// Amplitude ratio between octaves (`roughness`).
        omega: f32,
    },
    /// Turbulence ([`crate::math::noise::turbulence`]) in texture space.
    Wrinkled {
        /// Texture space.
        mapping: Mapping3D,
        /// Maximum number of octaves.
        octaves: u32,
        /// Amplitude ratio between octaves (`roughness`).
        omega: f32,
    },
    /// Wind-swept waves ([`procedural::windy`]) in texture space.
    Windy {
        /// Texture space.
        mapping: Mapping3D,
    },
    /// `a·tex1 + (1 − a)·tex2` with `a = |n·dir|` (n the geometric normal).
    DirectionMix {
        /// Seen along `dir`.
        tex1: FloatTex,
        /// Seen across it.
        tex2: FloatTex,
        /// Unit direction, world space.
        dir: Vec3,
    },
}

/// A colour texture (pbrt's spectrum textures), plain data.
#[derive(Clone, Debug)]
pub enum SpectrumTexture {
    /// A constant.
    Constant(Rgb),
    /// An image.
    Image(ImageTexture),
    /// Alternates `tex1` and `tex2` on a grid of the mapped (s, t).
    Checkerboard {
        /// Texture-coordinate mapping.
        mapping: Mapping2D,
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
    /// Alternates `tex1` and `tex2` on unit cubes of texture space (`dimension` 3).
    Checkerboard3D {
        /// Texture space.
        mapping: Mapping3D,
        /// Value on even cells.
        tex1: SpectrumTex,
        /// Value on odd cells.
        tex2: SpectrumTex,
    },
    /// Bilinear interpolation of four corner colours over (s, t).
    Bilerp {
        /// Texture-coordinate mapping.
        mapping: Mapping2D,
        /// Colours at (0, 0), (0, 1), (1, 0), (1, 1).
        v: [Rgb; 4],
    },
    /// Polka dots ([`procedural::inside_polka_dot`]).
    Dots {
        /// Texture-coordinate mapping.
        mapping: Mapping2D,
        /// Colour inside a dot (pbrt-v4's `outside` parameter: it swaps the two).
        dot: SpectrumTex,
        /// Colour between the dots (pbrt-v4's `inside` parameter).
        background: SpectrumTex,
    },
    /// Marble ([`procedural::marble`]) in texture space.
    Marble {
        /// Texture space.
        mapping: Mapping3D,
        /// Maximum number of octaves.
        octaves: u32,
        /// Amplitude ratio between octaves (`roughness`).
        omega: f32,
        /// Frequency of the veins (`scale`).
        scale: f32,
        /// Strength of the noise (`variation`).
        variation: f32,
    },
    /// `a·tex1 + (1 − a)·tex2` with `a = |n·dir|` (n the geometric normal).
    DirectionMix {
        /// Seen along `dir`.
        tex1: SpectrumTex,
        /// Seen across it.
        tex2: SpectrumTex,
        /// Unit direction, world space.
        dir: Vec3,
    },
}

/// Evaluates texture parameters against the scene's texture lists (the evaluation itself is
/// in `eval.rs`).
#[derive(Clone, Copy)]
pub struct TextureEval<'a> {
    /// The scene's float textures.
    pub floats: &'a [FloatTexture],
    /// The scene's spectrum textures.
    pub spectra: &'a [SpectrumTexture],
}
