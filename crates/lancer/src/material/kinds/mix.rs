//! The `mix` material: chooses between two materials per hit (resolved by the caller through
//! [`crate::material::mix::mix_pick`], which needs a random choice); no BxDF of its own.

use super::{MaterialDescKind, MaterialKind};
use crate::texture::FloatTex;

/// pbrt-v4's `mix` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MixMaterial {
    /// Indices of the two materials in the scene's list.
    pub materials: [u32; 2],
    /// Probability of choosing the second.
    pub amount: FloatTex,
}

impl MaterialDescKind for MixMaterial {
    type Built = MixMaterial;
    const PBRT_NAME: &'static str = "mix";
    fn build(&self) -> MixMaterial {
        *self
    }
}

impl MaterialKind for MixMaterial {}
