//! Textures: values that vary over a surface, looked up by (u, v) or position.
//!
//! A material parameter is either a constant or a reference to a texture of the scene
//! ([`FloatTex`], [`SpectrumTex`]). A scene description's textures are plain data
//! ([`FloatTextureDesc`], [`SpectrumTextureDesc`]); the scene build turns them into the
//! textures the renderer reads ([`FloatTexture`], [`SpectrumTexture`]: the same but for image
//! textures, which get their MIP pyramids, one per distinct image and settings, [`Pyramids`]),
//! stored in the scene's lists and evaluated by [`TextureEval`].
//!
//! Each texture kind is a file of `kinds/` (its description, its build and its float, RGB and
//! spectral lookups); [`kinds`] lists them. Adding a kind: a file in `kinds/` with its
//! description type (implementing [`kinds::TextureKind`], or [`kinds::Combining`] for a kind
//! that only combines its parameters, and [`PlainKind`] when the renderer reads the
//! description as it is, else [`TextureDescKind`]), a line in `texture_family!`'s list(s) in
//! `kinds.rs`, and its reader in `lancer-scene`'s `pbrt/textures.rs`.

mod eval;
pub mod kinds;
mod mapping;
pub mod mipmap;
mod param;
mod spectral;
#[cfg(test)]
mod tests;

pub use crate::image::WrapMode;
pub use kinds::bilerp::BilerpTexture;
pub use kinds::checkerboard::{Checkerboard3DTexture, CheckerboardTexture};
pub use kinds::direction_mix::DirectionMixTexture;
pub use kinds::dots::DotsTexture;
pub use kinds::fbm::FbmTexture;
pub use kinds::image::{ImageTexture, ImageTextureDesc};
pub use kinds::marble::MarbleTexture;
pub use kinds::mix::MixTexture;
pub use kinds::scale::ScaleTexture;
pub use kinds::windy::WindyTexture;
pub use kinds::wrinkled::WrinkledTexture;
pub use kinds::{
    FloatTexture, FloatTextureDesc, PlainKind, SpectrumTexture, SpectrumTextureDesc,
    TextureDescKind, TextureEval,
};
pub use mapping::{Mapping2D, Mapping3D, TexCoord, UvMapping};
pub use mipmap::{ImageFilter, MipMap, Pyramids, StFootprint};
pub use param::{FloatTex, SpectrumTex};
