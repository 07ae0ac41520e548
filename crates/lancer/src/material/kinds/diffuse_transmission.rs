//! The `diffusetransmission` material: diffuse reflection and diffuse transmission.

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{Colours, HitLookup, NO_COLOURS};
use crate::material::{BxDF, DiffuseTransmissionBxdf};
use crate::math::{SampledSpectrum, rgb_lanes};
use crate::spectrum::sampled::ColourKind;
use crate::texture::SpectrumTex;

/// Position of the reflectance in the material's [`Colours`].
const REFLECTANCE: usize = 0;
/// Position of the transmittance.
const TRANSMITTANCE: usize = 1;

/// pbrt-v4's `diffusetransmission` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiffuseTransmissionMaterial {
    /// Albedo of reflection.
    pub reflectance: SpectrumTex,
    /// Albedo of transmission.
    pub transmittance: SpectrumTex,
    /// Multiplies both.
    pub scale: f32,
}

impl MaterialDescKind for DiffuseTransmissionMaterial {
    type Built = DiffuseTransmissionMaterial;
    const PBRT_NAME: &'static str = "diffusetransmission";
    fn build(&self) -> DiffuseTransmissionMaterial {
        *self
    }
}

impl MaterialKind for DiffuseTransmissionMaterial {
    /// Never specular.
    #[inline(always)]
    fn may_be_specular(&self) -> bool {
        false
    }

    #[inline(always)]
    fn colours(&self) -> Colours {
        let mut c = NO_COLOURS;
        c[REFLECTANCE] = Some((self.reflectance, ColourKind::Albedo));
        c[TRANSMITTANCE] = Some((self.transmittance, ColourKind::Albedo));
        c
    }

    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        // pbrt-v4: clamp(scale · ρ(λ), 0, 1), ρ a reflectance spectrum (in RGB mode the colour
        // is scaled before it is clamped, so scale < 1 can tame a colour > 1).
        let scaled = |slot: usize, t: SpectrumTex| {
            let rho = match at.spectral {
                None => rgb_lanes(at.tex.spectrum(t, at.tc)),
                Some(_) => at.albedo(slot, t),
            };
            (rho * self.scale).clamp(SampledSpectrum::ZERO, SampledSpectrum::ONE)
        };
        Some(BxDF::DiffuseTransmission(DiffuseTransmissionBxdf {
            r: scaled(REFLECTANCE, self.reflectance),
            t: scaled(TRANSMITTANCE, self.transmittance),
        }))
    }
}
