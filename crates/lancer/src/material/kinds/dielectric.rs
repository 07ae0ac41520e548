//! The `dielectric` material: glass, Fresnel reflection and refraction, smooth or rough.

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{HitLookup, nonzero_eta};
use crate::material::{BxDF, DielectricBxdf};
use crate::spectrum::Ior;
use crate::texture::FloatTex;

/// pbrt-v4's `dielectric` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DielectricMaterial {
    /// Relative index of refraction (inside / outside); a named glass's varies with
    /// wavelength.
    pub eta: Ior,
    /// Roughness along u.
    pub uroughness: FloatTex,
    /// Roughness along v.
    pub vroughness: FloatTex,
    /// Map roughness to α as pbrt does.
    pub remap_roughness: bool,
}

impl MaterialDescKind for DielectricMaterial {
    type Built = DielectricMaterial;
    const PBRT_NAME: &'static str = "dielectric";
    fn build(&self) -> DielectricMaterial {
        *self
    }
}

impl MaterialKind for DielectricMaterial {
    /// Specular when smooth.
    fn may_be_specular(&self) -> bool {
        super::may_be_smooth(self.uroughness, self.vroughness, self.remap_roughness)
    }

    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        Some(BxDF::Dielectric(DielectricBxdf {
            eta: nonzero_eta(at.ior(self.eta)),
            distrib: at.distrib(self.uroughness, self.vroughness, self.remap_roughness),
        }))
    }

    #[inline(always)]
    fn disperses(&self) -> bool {
        self.eta.is_dispersive()
    }
}
