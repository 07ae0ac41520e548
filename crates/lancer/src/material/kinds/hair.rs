//! The `hair` material: fibres ([`HairBxdf`], pbrt-v4's `HairMaterial`), meant for `curve`
//! shapes; σₐ given, from a colour, or from melanin concentrations.

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::{Colours, HitLookup, NO_COLOURS};
use crate::material::{
    BxDF, HairBxdf, hair_sigma_a_from_concentration, hair_sigma_a_from_reflectance,
};
use crate::math::rgb_lanes;
use crate::spectrum::sampled::{ColourKind, RgbSpectrum};
use crate::texture::{FloatTex, SpectrumTex};

/// Position of the absorption's colour (σₐ, or the colour it gives) in the material's
/// [`Colours`].
const ABSORPTION: usize = 0;

/// pbrt-v4's `hair` material, plain data; its own runtime form.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HairMaterial {
    /// σₐ, the colour it gives, or melanin concentrations.
    pub absorption: HairAbsorption,
    /// Index of refraction of the fibre.
    pub eta: FloatTex,
    /// Longitudinal roughness, clamped to [0.01, 1].
    pub beta_m: FloatTex,
    /// Azimuthal roughness, clamped to [0.01, 1].
    pub beta_n: FloatTex,
    /// Tilt of the cuticle scales, degrees.
    pub alpha: FloatTex,
}

/// Where a `hair` material's absorption comes from (pbrt-v4 takes the first given of
/// `sigma_a`, `reflectance`/`color`, `eumelanin`/`pheomelanin`; with none, eumelanin 1.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HairAbsorption {
    /// σₐ itself (an unbounded colour).
    SigmaA(SpectrumTex),
    /// The colour the hair should have; σₐ follows from it and βn
    /// ([`hair_sigma_a_from_reflectance`]).
    Reflectance(SpectrumTex),
    /// Melanin concentrations ([`hair_sigma_a_from_concentration`]).
    Melanin {
        /// Eumelanin (brown-black).
        eumelanin: FloatTex,
        /// Pheomelanin (red-yellow).
        pheomelanin: FloatTex,
    },
}

impl HairAbsorption {
    /// The colour this absorption prepares in spectral mode (the material's [`ABSORPTION`]),
    /// when it has one: σₐ or the reflectance as given, or the σₐ of constant melanin concentrations.
    fn colour(&self) -> Option<(SpectrumTex, ColourKind)> {
        match *self {
            HairAbsorption::SigmaA(s) => Some((s, ColourKind::Unbounded)),
            HairAbsorption::Reflectance(c) => Some((c, ColourKind::Albedo)),
            HairAbsorption::Melanin {
                eumelanin: FloatTex::Const(ce),
                pheomelanin: FloatTex::Const(cp),
            } => Some((
                SpectrumTex::Const(hair_sigma_a_from_concentration(ce.max(0.0), cp.max(0.0))),
                ColourKind::Unbounded,
            )),
            HairAbsorption::Melanin { .. } => None,
        }
    }
}

impl MaterialDescKind for HairMaterial {
    type Built = HairMaterial;
    const PBRT_NAME: &'static str = "hair";
    fn build(&self) -> HairMaterial {
        *self
    }
}

impl MaterialKind for HairMaterial {
    /// Never specular.
    #[inline(always)]
    fn may_be_specular(&self) -> bool {
        false
    }

    #[inline(always)]
    fn colours(&self) -> Colours {
        let mut c = NO_COLOURS;
        c[ABSORPTION] = self.absorption.colour();
        c
    }

    /// The fibre's BxDF at a hit, as pbrt-v4's `HairMaterial::GetBxDF` makes it: βm, βn
    /// clamped to [0.01, 1], σₐ from the absorption (textured melanin uplifted here), and the
    /// offset h = −1 + 2v.
    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        let [eta, beta_m, beta_n, alpha] =
            [self.eta, self.beta_m, self.beta_n, self.alpha].map(|p| at.float(p));
        let (bm, bn) = (beta_m.clamp(0.01, 1.0), beta_n.clamp(0.01, 1.0));
        let sigma_a = match self.absorption {
            HairAbsorption::SigmaA(s) => at.colour(ABSORPTION, s, ColourKind::Unbounded),
            HairAbsorption::Reflectance(c) => {
                hair_sigma_a_from_reflectance(at.albedo(ABSORPTION, c), bn)
            }
            HairAbsorption::Melanin {
                eumelanin,
                pheomelanin,
            } => match self.absorption.colour() {
                // Constant concentrations: σa is a constant colour, listed by `colours`.
                Some((s, kind)) => at.colour(ABSORPTION, s, kind),
                None => {
                    let rgb = hair_sigma_a_from_concentration(
                        at.float(eumelanin).max(0.0),
                        at.float(pheomelanin).max(0.0),
                    );
                    match at.lambda() {
                        None => rgb_lanes(rgb),
                        Some(l) => l.sample(&RgbSpectrum::new(rgb, ColourKind::Unbounded)),
                    }
                }
            },
        };
        Some(BxDF::Hair(HairBxdf::new(
            -1.0 + 2.0 * at.tc.uv.y,
            eta,
            sigma_a,
            bm,
            bn,
            alpha,
        )))
    }
}
