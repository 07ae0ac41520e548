//! The `coateddiffuse` material: a diffuse base under a dielectric coating (varnish, plastic),
//! the layer between them walked at random ([`crate::material::LayeredBxdf`]).

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{Colours, HitLookup, NO_COLOURS, nonzero_eta};
use crate::material::{BxDF, CoatedDiffuseBxdf, DielectricBxdf, DiffuseBxdf};
use crate::spectrum::Ior;
use crate::spectrum::sampled::ColourKind;
use crate::texture::{FloatTex, SpectrumTex};

/// Position of the base's reflectance in the material's [`Colours`].
const REFLECTANCE: usize = 0;
/// Position of the coating medium's albedo.
const ALBEDO: usize = 1;

/// pbrt-v4's `coateddiffuse` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoatedDiffuseMaterial {
    /// Albedo of the base.
    pub reflectance: SpectrumTex,
    /// Coating roughness along u.
    pub uroughness: FloatTex,
    /// Coating roughness along v.
    pub vroughness: FloatTex,
    /// Thickness of the medium between coating and base.
    pub thickness: FloatTex,
    /// Index of refraction of the coating; one that varies with wavelength is taken at the
    /// hero wavelength, as a dielectric's (see [`MaterialKind::disperses`]).
    pub eta: Ior,
    /// Albedo of the medium in the coating.
    pub albedo: SpectrumTex,
    /// Henyey–Greenstein asymmetry of that medium.
    pub g: FloatTex,
    /// Maximum number of bounces in the layer's random walk.
    pub max_depth: u32,
    /// Number of random-walk samples per evaluation.
    pub n_samples: u32,
    /// Map roughness to α as pbrt does.
    pub remap_roughness: bool,
}

impl MaterialDescKind for CoatedDiffuseMaterial {
    type Built = CoatedDiffuseMaterial;
    const PBRT_NAME: &'static str = "coateddiffuse";
    fn build(&self) -> CoatedDiffuseMaterial {
        *self
    }
}

impl MaterialKind for CoatedDiffuseMaterial {
    /// Specular when its coating is smooth.
    fn may_be_specular(&self) -> bool {
        super::may_be_smooth(self.uroughness, self.vroughness, self.remap_roughness)
    }

    #[inline(always)]
    fn colours(&self) -> Colours {
        let mut c = NO_COLOURS;
        c[REFLECTANCE] = Some((self.reflectance, ColourKind::Albedo));
        c[ALBEDO] = Some((self.albedo, ColourKind::Albedo));
        c
    }

    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        Some(BxDF::CoatedDiffuse(CoatedDiffuseBxdf::new(
            DielectricBxdf {
                eta: nonzero_eta(at.ior(self.eta)),
                distrib: at.distrib(self.uroughness, self.vroughness, self.remap_roughness),
            },
            DiffuseBxdf {
                r: at.albedo(REFLECTANCE, self.reflectance),
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
        self.eta.is_dispersive()
    }
}
