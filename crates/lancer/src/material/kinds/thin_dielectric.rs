//! The `thindielectric` material: an infinitely thin dielectric slab (a window pane), no
//! refraction offset.

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{HitLookup, nonzero_eta};
use crate::material::{BxDF, ThinDielectricBxdf};
use crate::spectrum::Ior;

/// pbrt-v4's `thindielectric` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectricMaterial {
    /// Index of refraction.
    pub eta: Ior,
}

impl MaterialDescKind for ThinDielectricMaterial {
    type Built = ThinDielectricMaterial;
    const PBRT_NAME: &'static str = "thindielectric";
    fn build(&self) -> ThinDielectricMaterial {
        *self
    }
}

impl MaterialKind for ThinDielectricMaterial {
    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        Some(BxDF::ThinDielectric(ThinDielectricBxdf {
            eta: nonzero_eta(at.ior(self.eta)),
        }))
    }

    #[inline(always)]
    fn disperses(&self) -> bool {
        self.eta.is_dispersive()
    }
}
