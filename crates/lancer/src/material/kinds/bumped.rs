//! A material with a bump or normal map: another material (`base`) whose shading frame the
//! map changes at the hit ([`crate::material::mix::apply_bump`]); the BxDF is the base's.

use super::{MaterialDescKind, MaterialKind};
use crate::texture::FloatTex;

/// A bump- or normal-mapped material (pbrt-v4's `displacement` and `normalmap` parameters,
/// the normal map winning when both are given), plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BumpedMaterial {
    /// Index of the material underneath in the scene's list.
    pub base: u32,
    /// Height texture.
    pub displacement: Option<FloatTex>,
    /// Spectrum texture holding the tangent-space normal image.
    pub normal_map: Option<u32>,
}

impl MaterialDescKind for BumpedMaterial {
    type Built = BumpedMaterial;
    const PBRT_NAME: &'static str = "bumped";
    fn build(&self) -> BumpedMaterial {
        *self
    }
}

impl MaterialKind for BumpedMaterial {}
