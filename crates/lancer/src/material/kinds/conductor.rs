//! The `conductor` material: a metal, Fresnel reflection with complex index `eta + i·k` or an
//! artist's `reflectance`, smooth or rough (GGX).

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{Colours, HitLookup, NO_COLOURS};
use crate::material::{BxDF, ConductorBxdf};
use crate::math::SampledSpectrum;
use crate::spectrum::sampled::ColourKind;
use crate::texture::{FloatTex, SpectrumTex};

/// Positions of `eta`, `k` and `reflectance` in the material's [`Colours`].
const SLOTS: ConductorSlots = ConductorSlots {
    eta: 0,
    k: 1,
    reflectance: 2,
};

/// pbrt-v4's `conductor` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConductorMaterial {
    /// Real part of the index of refraction, per channel.
    pub eta: SpectrumTex,
    /// Imaginary part (absorption), per channel.
    pub k: SpectrumTex,
    /// When set, replaces `eta`/`k` by the index that gives this reflectance at normal
    /// incidence.
    pub reflectance: Option<SpectrumTex>,
    /// Roughness along u.
    pub uroughness: FloatTex,
    /// Roughness along v.
    pub vroughness: FloatTex,
    /// Map roughness to the microfacet α as pbrt does (`remaproughness`).
    pub remap_roughness: bool,
}

/// Where a material that holds a conductor keeps the conductor's colours in its [`Colours`]
/// (each such kind chooses its own).
#[derive(Clone, Copy, Debug)]
pub(crate) struct ConductorSlots {
    /// Position of `eta` (unbounded).
    pub eta: usize,
    /// Position of `k` (unbounded).
    pub k: usize,
    /// Position of the artist's reflectance (an albedo).
    pub reflectance: usize,
}

impl ConductorSlots {
    /// Writes the conductor's colours into `c` at these positions.
    #[inline(always)]
    pub(crate) fn fill(
        &self,
        c: &mut Colours,
        eta: SpectrumTex,
        k: SpectrumTex,
        reflectance: Option<SpectrumTex>,
    ) {
        c[self.eta] = Some((eta, ColourKind::Unbounded));
        c[self.k] = Some((k, ColourKind::Unbounded));
        c[self.reflectance] = reflectance.map(|r| (r, ColourKind::Albedo));
    }

    /// The conductor index pbrt-v4 uses: `eta`/`k` as given, or, when an artist's
    /// `reflectance` r is given instead, η = 1 and k = 2√r / √(1 − r) (r clamped to
    /// [0, 0.9999]), which makes the normal-incidence Fresnel reflectance
    /// ((η − 1)² + k²)/((η + 1)² + k²) equal r. In spectral mode `eta` and `k` are unbounded
    /// spectra and r a reflectance spectrum; in RGB mode their lanes.
    #[inline(always)]
    pub(crate) fn index(
        &self,
        at: &HitLookup,
        eta: SpectrumTex,
        k: SpectrumTex,
        reflectance: Option<SpectrumTex>,
    ) -> (SampledSpectrum, SampledSpectrum) {
        match reflectance {
            Some(r) => {
                let r = at
                    .colour(self.reflectance, r, ColourKind::Albedo)
                    .clamp(SampledSpectrum::ZERO, SampledSpectrum::splat(0.9999));
                let k = 2.0 * r.map(f32::sqrt)
                    / (SampledSpectrum::ONE - r)
                        .max(SampledSpectrum::ZERO)
                        .map(f32::sqrt);
                (SampledSpectrum::ONE, k)
            }
            None => (
                at.colour(self.eta, eta, ColourKind::Unbounded),
                at.colour(self.k, k, ColourKind::Unbounded),
            ),
        }
    }
}

impl MaterialDescKind for ConductorMaterial {
    type Built = ConductorMaterial;
    const PBRT_NAME: &'static str = "conductor";
    fn build(&self) -> ConductorMaterial {
        *self
    }
}

impl MaterialKind for ConductorMaterial {
    /// Specular when smooth.
    fn may_be_specular(&self) -> bool {
        super::may_be_smooth(self.uroughness, self.vroughness, self.remap_roughness)
    }

    #[inline(always)]
    fn colours(&self) -> Colours {
        let mut c = NO_COLOURS;
        SLOTS.fill(&mut c, self.eta, self.k, self.reflectance);
        c
    }

    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        let (eta, k) = SLOTS.index(at, self.eta, self.k, self.reflectance);
        Some(BxDF::Conductor(ConductorBxdf {
            distrib: at.distrib(self.uroughness, self.vroughness, self.remap_roughness),
            eta,
            k,
        }))
    }
}
