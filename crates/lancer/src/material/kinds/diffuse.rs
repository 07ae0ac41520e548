//! The `diffuse` material: Lambertian reflection, f = ρ/π.

use super::{MaterialDescKind, MaterialKind};
use crate::material::BxDF;
use crate::material::at_hit::{Colours, HitLookup, NO_COLOURS, SpectralColours};
use crate::math::{Rgb, SampledSpectrum};
use crate::spectrum::sampled::ColourKind;
use crate::texture::SpectrumTex;

/// Position of the reflectance in the material's [`Colours`].
const REFLECTANCE: usize = 0;

/// pbrt-v4's `diffuse` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseMaterial {
    /// Albedo ρ.
    pub reflectance: SpectrumTex,
}

impl Default for DiffuseMaterial {
    /// pbrt's default: reflectance 0.5.
    fn default() -> Self {
        DiffuseMaterial {
            reflectance: SpectrumTex::Const(Rgb::splat(0.5)),
        }
    }
}

impl DiffuseMaterial {
    /// The reflectance at the path's wavelengths when it is a constant (the integrator's
    /// shortcut past the texture lookup for constant diffuse surfaces).
    #[inline(always)]
    pub(crate) fn prepared_reflectance(sc: SpectralColours) -> SampledSpectrum {
        sc.constant(REFLECTANCE)
    }
}

impl MaterialDescKind for DiffuseMaterial {
    type Built = DiffuseMaterial;
    const PBRT_NAME: &'static str = "diffuse";
    fn build(&self) -> DiffuseMaterial {
        *self
    }
}

impl MaterialKind for DiffuseMaterial {
    /// Never specular.
    #[inline(always)]
    fn may_be_specular(&self) -> bool {
        false
    }

    #[inline(always)]
    fn colours(&self) -> Colours {
        let mut c = NO_COLOURS;
        c[REFLECTANCE] = Some((self.reflectance, ColourKind::Albedo));
        c
    }

    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        Some(BxDF::diffuse(at.albedo(REFLECTANCE, self.reflectance)))
    }
}
