//! The `wrinkled` texture: turbulence in texture space.

use super::{At, PlainKind, TextureKind};
use crate::math::noise::turbulence;
use crate::texture::Mapping3D;

/// Turbulence ([`crate::math::noise::turbulence`]) in texture space, plain data.
#[derive(Clone, Debug)]
pub struct WrinkledTexture {
    /// Texture space.
    pub mapping: Mapping3D,
    /// Maximum number of octaves.
    pub octaves: u32,
    /// Amplitude ratio between octaves (`roughness`).
    pub omega: f32,
}

impl TextureKind<f32> for WrinkledTexture {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> f32 {
        // pbrt-v4 fades out the octaves finer than the footprint.
        let (p, dpdx, dpdy) = self.mapping.map_footprint(at.tc);
        turbulence(p, dpdx, dpdy, self.omega, self.octaves)
    }
}

/// Its description is what the renderer reads.
impl PlainKind for WrinkledTexture {}
