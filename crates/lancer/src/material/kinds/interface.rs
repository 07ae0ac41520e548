//! The `interface` material: no surface at all, the boundary of a participating medium that
//! rays pass through; no BxDF.

use super::{MaterialDescKind, MaterialKind};

/// pbrt-v4's `interface` material (it has no parameters); its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceMaterial;

impl MaterialDescKind for InterfaceMaterial {
    type Built = InterfaceMaterial;
    const PBRT_NAME: &'static str = "interface";
    fn build(&self) -> InterfaceMaterial {
        *self
    }
}

impl MaterialKind for InterfaceMaterial {
    /// No surface of its own: rays pass through.
    #[inline(always)]
    fn may_be_specular(&self) -> bool {
        false
    }
}
