//! The `coatedconductor` material: a conductor under a dielectric coating, the layer between
//! them walked at random ([`crate::material::LayeredBxdf`]).

use super::conductor::ConductorSlots;
use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{Colours, HitLookup, NO_COLOURS, nonzero_eta};
use crate::material::{BxDF, CoatedConductorBxdf, ConductorBxdf, DielectricBxdf};
use crate::spectrum::Ior;
use crate::spectrum::sampled::ColourKind;
use crate::texture::{FloatTex, SpectrumTex};

/// Positions of the conductor's `eta`, `k` and `reflectance` in the material's [`Colours`].
const CONDUCTOR: ConductorSlots = ConductorSlots {
    eta: 0,
    k: 1,
    reflectance: 2,
};
/// Position of the coating medium's albedo.
const ALBEDO: usize = 3;

/// pbrt-v4's `coatedconductor` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatedConductorMaterial {
    /// Coating roughness along u.
    pub interface_uroughness: FloatTex,
    /// Coating roughness along v.
    pub interface_vroughness: FloatTex,
    /// Coating index of refraction (taken at the hero wavelength when it varies).
    pub interface_eta: Ior,
    /// Conductor's `eta`.
    pub conductor_eta: SpectrumTex,
    /// Conductor's `k`.
    pub k: SpectrumTex,
    /// Conductor's reflectance, replacing `eta`/`k` when given.
    pub reflectance: Option<SpectrumTex>,
    /// Conductor roughness along u.
    pub conductor_uroughness: FloatTex,
    /// Conductor roughness along v.
    pub conductor_vroughness: FloatTex,
    /// Thickness of the coating medium.
    pub thickness: FloatTex,
    /// Albedo of the coating medium.
    pub albedo: SpectrumTex,
    /// Henyey–Greenstein asymmetry.
    pub g: FloatTex,
    /// Random-walk depth.
    pub max_depth: u32,
    /// Random-walk samples.
    pub n_samples: u32,
    /// Map roughness to α as pbrt does.
    pub remap_roughness: bool,
}

impl MaterialDescKind for CoatedConductorMaterial {
    type Built = CoatedConductorMaterial;
    const PBRT_NAME: &'static str = "coatedconductor";
    fn build(&self) -> CoatedConductorMaterial {
        *self
    }
}

impl MaterialKind for CoatedConductorMaterial {
    /// Specular when its coating or its conductor is smooth.
    fn may_be_specular(&self) -> bool {
        super::may_be_smooth(
            self.interface_uroughness,
            self.interface_vroughness,
            self.remap_roughness,
        ) || super::may_be_smooth(
            self.conductor_uroughness,
            self.conductor_vroughness,
            self.remap_roughness,
        )
    }

    #[inline(always)]
    fn colours(&self) -> Colours {
        let mut c = NO_COLOURS;
        CONDUCTOR.fill(&mut c, self.conductor_eta, self.k, self.reflectance);
        c[ALBEDO] = Some((self.albedo, ColourKind::Albedo));
        c
    }

    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        let ieta = nonzero_eta(at.ior(self.interface_eta));
        let (ce, ck) = CONDUCTOR.index(at, self.conductor_eta, self.k, self.reflectance);
        Some(BxDF::CoatedConductor(CoatedConductorBxdf::new(
            DielectricBxdf {
                eta: ieta,
                distrib: at.distrib(
                    self.interface_uroughness,
                    self.interface_vroughness,
                    self.remap_roughness,
                ),
            },
            // Under the coating the conductor borders the coating's medium, not air: its index
            // relative to that medium is (η + ik)/η_coating.
            ConductorBxdf {
                distrib: at.distrib(
                    self.conductor_uroughness,
                    self.conductor_vroughness,
                    self.remap_roughness,
                ),
                eta: ce / ieta,
                k: ck / ieta,
            },
            at.float(self.thickness),
            at.albedo(ALBEDO, self.albedo),
            at.float(self.g).clamp(-1.0, 1.0),
            self.max_depth,
            self.n_samples,
        )))
    }

    #[inline(always)]
    fn disperses(&self) -> bool {
        self.interface_eta.is_dispersive()
    }
}
