//! The `fbm` texture: fractional Brownian motion in texture space.

use super::{At, PlainKind, TextureKind};
use crate::math::noise::fbm;
use crate::texture::Mapping3D;

/// Fractional Brownian motion ([`crate::math::noise::fbm`]) in texture space, plain data.
#[derive(Clone, Debug)]
pub struct FbmTexture {
    /// Texture space.
    pub mapping: Mapping3D,
    /// Maximum number of octaves.
    pub octaves: u32,
    /// Amplitude ratio between octaves (`roughness`).
    pub omega: f32,
}

impl TextureKind<f32> for FbmTexture {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> f32 {
        // pbrt-v4 fades out the octaves finer than the footprint.
        let (p, dpdx, dpdy) = self.mapping.map_footprint(at.tc);
        fbm(p, dpdx, dpdy, self.omega, self.octaves)
    }
}

/// Its description is what the renderer reads.
impl PlainKind for FbmTexture {}
