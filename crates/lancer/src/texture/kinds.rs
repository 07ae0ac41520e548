//! The texture families: one line per kind in `texture_family!`'s two lists below (float
//! textures, spectrum textures), and each kind in its own file of `kinds/`, which owns its
//! description (plain data, what the readers make), its build into what the renderer reads
//! ([`TextureDescKind`]: a copy, [`PlainKind`], for every kind but the image, whose build makes
//! its MIP pyramid) and its lookups: float, RGB and, for spectrum textures, at the path's
//! wavelengths.
//!
//! A kind that only combines other parameters (checkerboard, scale, mix, dots, directionmix)
//! writes its formula once, for any value type, as [`Combining::combine`] over its
//! [`Inputs`]; the float, RGB and sampled lookups are that formula read through [`At`] or
//! [`SampledAt`]. A kind that makes its value (image, bilerp, the noise patterns) implements
//! [`TextureKind`] for the values it gives.
//!
//! The lists make the description enums [`FloatTextureDesc`] and [`SpectrumTextureDesc`] (of
//! [`crate::SceneDesc`]), the runtime enums [`FloatTexture`] and [`SpectrumTexture`] (of
//! [`crate::Scene`]), and write their `match`es once, each arm a direct call to the kind's
//! method (static dispatch, inlined into one function as a hand-written `match` would be; no
//! allocation).

pub mod bilerp;
pub mod checkerboard;
pub mod constant;
pub mod direction_mix;
pub mod dots;
pub mod fbm;
pub mod image;
pub mod marble;
pub mod mix;
pub mod scale;
pub mod windy;
pub mod wrinkled;

use super::mipmap::Pyramids;
use super::{FloatTex, SpectrumTex, TexCoord};
use crate::math::{Rgb, SampledSpectrum};
use crate::spectrum::sampled::{ColourKind, SampledWavelengths};
use std::ops::{Add, Mul};

/// Evaluates texture parameters against the scene's texture lists (the lookups are in
/// `eval.rs` and `spectral.rs`; the kinds call back into them for their parameters).
#[derive(Clone, Copy)]
pub struct TextureEval<'a> {
    /// The scene's float textures.
    pub floats: &'a [FloatTexture],
    /// The scene's spectrum textures.
    pub spectra: &'a [SpectrumTexture],
}

/// Where a texture is looked up: the scene's textures and the hit's texture coordinates.
#[derive(Clone, Copy)]
pub struct At<'a> {
    /// The scene's textures, for the parameters that are textures themselves.
    pub ev: &'a TextureEval<'a>,
    /// The hit.
    pub tc: &'a TexCoord,
}

/// Where a spectrum texture is looked up at the path's wavelengths: as [`At`], with the
/// wavelengths and how RGB values are uplifted to spectra.
#[derive(Clone, Copy)]
pub struct SampledAt<'a> {
    /// The scene's textures.
    pub ev: &'a TextureEval<'a>,
    /// The hit.
    pub tc: &'a TexCoord,
    /// The path's wavelengths.
    pub lambda: &'a SampledWavelengths,
    /// How an RGB value becomes a spectrum (albedo or unbounded).
    pub kind: ColourKind,
}

/// A texture kind's lookups, giving values of type `V` (`f32` for a float texture, [`Rgb`]
/// for a spectrum texture).
pub trait TextureKind<V> {
    /// Its value at the hit.
    fn evaluate(&self, at: &At) -> V;

    /// Its value at the path's wavelengths, or `None` where that is the uplift of its RGB
    /// value ([`TextureKind::evaluate`]): every kind but those that combine spectrum
    /// parameters, which may hold a spectrum given as a spectrum.
    #[inline(always)]
    fn sampled(&self, at: &SampledAt) -> Option<SampledSpectrum> {
        let _ = at;
        None
    }

    /// Whether one of its parameters holds a [`SpectrumTex::Measured`] leaf; none by default.
    #[inline(always)]
    fn has_measured(&self, ev: &TextureEval) -> bool {
        let _ = ev;
        false
    }
}

/// What every combining kind reads, whatever the type of its parameters: the hit and its
/// float parameters (a blend factor, a scale).
pub trait Lookup {
    /// The hit.
    fn tc(&self) -> &TexCoord;
    /// A float parameter's value.
    fn float(&self, t: FloatTex) -> f32;
}

impl Lookup for At<'_> {
    #[inline(always)]
    fn tc(&self) -> &TexCoord {
        self.tc
    }
    #[inline(always)]
    fn float(&self, t: FloatTex) -> f32 {
        self.ev.float(t, self.tc)
    }
}

impl Lookup for SampledAt<'_> {
    #[inline(always)]
    fn tc(&self) -> &TexCoord {
        self.tc
    }
    #[inline(always)]
    fn float(&self, t: FloatTex) -> f32 {
        self.ev.float(t, self.tc)
    }
}

/// How a combining kind reads its parameters of type `T` ([`FloatTex`] or [`SpectrumTex`]):
/// as floats, RGB or sampled spectra.
pub trait Inputs<T>: Lookup {
    /// The values combined.
    type Value: Copy + Mul<f32, Output = Self::Value> + Add<Output = Self::Value>;
    /// Zero of [`Inputs::Value`].
    const ZERO: Self::Value;
    /// A parameter's value.
    fn input(&self, t: T) -> Self::Value;
}

impl Inputs<FloatTex> for At<'_> {
    type Value = f32;
    const ZERO: f32 = 0.0;
    #[inline(always)]
    fn input(&self, t: FloatTex) -> f32 {
        self.ev.float(t, self.tc)
    }
}

impl Inputs<SpectrumTex> for At<'_> {
    type Value = Rgb;
    const ZERO: Rgb = Rgb::ZERO;
    #[inline(always)]
    fn input(&self, t: SpectrumTex) -> Rgb {
        self.ev.spectrum(t, self.tc)
    }
}

impl Inputs<SpectrumTex> for SampledAt<'_> {
    type Value = SampledSpectrum;
    const ZERO: SampledSpectrum = SampledSpectrum::ZERO;
    #[inline(always)]
    fn input(&self, t: SpectrumTex) -> SampledSpectrum {
        self.ev.sampled(t, self.tc, self.lambda, self.kind)
    }
}

/// A kind whose value combines its parameters of type `T`, written once for every value type.
pub trait Combining<T> {
    /// Its value from its parameters' values, read through `at`.
    fn combine<I: Inputs<T>>(&self, at: &I) -> I::Value;
    /// Whether `f` holds for one of its parameters of type `T`.
    fn any_input(&self, f: impl Fn(T) -> bool) -> bool;
}

impl<K: Combining<FloatTex>> TextureKind<f32> for K {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> f32 {
        self.combine(at)
    }
}

impl<K: Combining<SpectrumTex>> TextureKind<Rgb> for K {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> Rgb {
        self.combine(at)
    }

    #[inline(always)]
    fn sampled(&self, at: &SampledAt) -> Option<SampledSpectrum> {
        Some(self.combine(at))
    }

    #[inline(always)]
    fn has_measured(&self, ev: &TextureEval) -> bool {
        self.any_input(|t| ev.has_measured(t))
    }
}

/// A texture kind's description: plain data (what the readers make), built once per scene
/// into what the renderer reads.
pub trait TextureDescKind {
    /// The kind's runtime form.
    type Built;
    /// The runtime form of this description; `pyramids` holds the image pyramids the build
    /// has made so far.
    fn build(&self, pyramids: &mut Pyramids) -> Self::Built;
}

/// A kind whose description is what the renderer reads (every kind but the image): its build
/// is a copy.
pub trait PlainKind: Clone {}

impl<K: PlainKind> TextureDescKind for K {
    type Built = K;
    #[inline]
    fn build(&self, _: &mut Pyramids) -> K {
        self.clone()
    }
}

/// Writes a family's two enums (description and runtime) and their `match`es from its list of
/// kinds: per kind, its variant name and its description type (its runtime type is the
/// description's [`TextureDescKind::Built`]). `spectrum` families also dispatch the lookups at
/// the path's wavelengths.
macro_rules! texture_family {
    (@enum $(#[$fdoc:meta])* $family:ident, $desc_family:ident => $value:ty {
        $($(#[$doc:meta])* $kind:ident($ty:ty),)*
    }) => {
        $(#[$fdoc])*
        /// As the scene gives it: plain data, what the readers make; the scene build turns it
        #[doc = concat!("into a [`", stringify!($family), "`].")]
        #[derive(Clone, Debug)]
        pub enum $desc_family {
            $($(#[$doc])* $kind($ty),)*
        }

        $(#[$fdoc])*
        #[doc = concat!(
            "As the renderer reads it, built from a [`", stringify!($desc_family), "`]."
        )]
        #[derive(Clone, Debug)]
        pub enum $family {
            $($(#[$doc])* $kind(<$ty as TextureDescKind>::Built),)*
        }

        impl $desc_family {
            /// The runtime texture of this description, its image pyramid (if any) taken from
            /// `pyramids` ([`TextureDescKind::build`]).
            pub fn build(&self, pyramids: &mut Pyramids) -> $family {
                match self {
                    $($desc_family::$kind(k) => $family::$kind(k.build(pyramids)),)*
                }
            }
        }

        impl $family {
            /// The texture's value at `at` ([`TextureKind::evaluate`]).
            #[inline(always)]
            pub fn evaluate(&self, at: &At) -> $value {
                match self {
                    $($family::$kind(k) => {
                        <<$ty as TextureDescKind>::Built as TextureKind<$value>>::evaluate(k, at)
                    })*
                }
            }
        }
    };
    (float $($rest:tt)*) => {
        texture_family!(@enum $($rest)*);
    };
    (spectrum $(#[$fdoc:meta])* $family:ident, $desc_family:ident => $value:ty {
        $($(#[$doc:meta])* $kind:ident($ty:ty),)*
    }) => {
        texture_family!(@enum $(#[$fdoc])* $family, $desc_family => $value {
            $($(#[$doc])* $kind($ty),)*
        });

        impl $family {
            /// The texture's value at the path's wavelengths, `None` where that is the uplift
            /// of its RGB value ([`TextureKind::sampled`]).
            #[inline(always)]
            pub fn sampled(&self, at: &SampledAt) -> Option<SampledSpectrum> {
                match self {
                    $($family::$kind(k) => {
                        <<$ty as TextureDescKind>::Built as TextureKind<$value>>::sampled(k, at)
                    })*
                }
            }

            /// Whether the texture holds a spectrum given as a spectrum
            /// ([`TextureKind::has_measured`]).
            #[inline(always)]
            pub fn has_measured(&self, ev: &TextureEval) -> bool {
                match self {
                    $($family::$kind(k) => {
                        type Built = <$ty as TextureDescKind>::Built;
                        <Built as TextureKind<$value>>::has_measured(k, ev)
                    })*
                }
            }
        }
    };
}

texture_family! {
    float
    /// A float texture (pbrt's float textures).
    FloatTexture, FloatTextureDesc => f32 {
        /// A constant.
        Constant(f32),
        /// An image holding the float value in all three channels (the scene reader chooses
        /// it as pbrt-v4 does: alpha, the average of R, G, B, or the first channel); `.x` is
        /// read.
        Image(image::ImageTextureDesc),
        /// Alternates `tex1` and `tex2` on a grid of the mapped (s, t).
        Checkerboard(checkerboard::CheckerboardTexture<FloatTex>),
        /// `tex · scale`.
        Scale(scale::ScaleTexture<FloatTex>),
        /// `(1 − amount)·tex1 + amount·tex2`.
        Mix(mix::MixTexture<FloatTex>),
        /// Alternates `tex1` and `tex2` on unit cubes of texture space (`dimension` 3).
        Checkerboard3D(checkerboard::Checkerboard3DTexture<FloatTex>),
        /// Bilinear interpolation of four corner values over (s, t).
        Bilerp(bilerp::BilerpTexture<f32>),
        /// Polka dots.
        Dots(dots::DotsTexture<FloatTex>),
        /// Fractional Brownian motion in texture space.
        Fbm(fbm::FbmTexture),
        /// Turbulence in texture space.
        Wrinkled(wrinkled::WrinkledTexture),
        /// Wind-swept waves in texture space.
        Windy(windy::WindyTexture),
        /// `a·tex1 + (1 − a)·tex2` with `a = |n·dir|` (n the geometric normal).
        DirectionMix(direction_mix::DirectionMixTexture<FloatTex>),
    }
}

texture_family! {
    spectrum
    /// A colour texture (pbrt's spectrum textures).
    SpectrumTexture, SpectrumTextureDesc => Rgb {
        /// A constant.
        Constant(Rgb),
        /// An image.
        Image(image::ImageTextureDesc),
        /// Alternates `tex1` and `tex2` on a grid of the mapped (s, t).
        Checkerboard(checkerboard::CheckerboardTexture<SpectrumTex>),
        /// `tex · scale`.
        Scale(scale::ScaleTexture<SpectrumTex>),
        /// `(1 − amount)·tex1 + amount·tex2`.
        Mix(mix::MixTexture<SpectrumTex>),
        /// Alternates `tex1` and `tex2` on unit cubes of texture space (`dimension` 3).
        Checkerboard3D(checkerboard::Checkerboard3DTexture<SpectrumTex>),
        /// Bilinear interpolation of four corner colours over (s, t).
        Bilerp(bilerp::BilerpTexture<Rgb>),
        /// Polka dots.
        Dots(dots::DotsTexture<SpectrumTex>),
        /// Marble in texture space.
        Marble(marble::MarbleTexture),
        /// `a·tex1 + (1 − a)·tex2` with `a = |n·dir|` (n the geometric normal).
        DirectionMix(direction_mix::DirectionMixTexture<SpectrumTex>),
    }
}
