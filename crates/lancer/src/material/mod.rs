//! Materials: how a surface scatters light, as plain data ([`Material`]), turned at each hit
//! into a [`Bsdf`] in the local shading frame.

mod bssrdf;
mod bump;
mod bxdf;
mod conductor;
mod dielectric;
mod diffuse;
mod fresnel;
mod hair;
mod layered;
pub mod measured;
mod microfacet;
pub mod mix;
mod scatter;
mod subsurface;

pub use bssrdf::{
    BssrdfTable, NormalizedFresnelBxdf, ProbeSegment, SubsurfaceCoefficients, SubsurfaceMaterial,
    TabulatedBssrdf, subsurface_from_diffuse,
};
pub use bump::{bump_shading, normal_map_shading};
pub use bxdf::{Bsdf, BxDF};
pub use conductor::ConductorBxdf;
pub use dielectric::{DielectricBxdf, ThinDielectricBxdf};
pub use diffuse::{DiffuseBxdf, DiffuseTransmissionBxdf};
pub use fresnel::{fresnel_complex, fresnel_dielectric, reflect, refract};
pub use hair::{
    HairAbsorption, HairBxdf, HairMaterial, hair_sigma_a_from_concentration,
    hair_sigma_a_from_reflectance,
};
pub use layered::{CoatedConductorBxdf, CoatedDiffuseBxdf, LayeredBxdf};
pub use measured::{MeasuredBxdf, MeasuredData};
pub use microfacet::TrowbridgeReitz;
pub use scatter::{BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode};

use crate::math::{Rgb, SampledSpectrum, rgb_lanes};
use crate::spectrum::Ior;
use crate::spectrum::dense::PreparedSpectrum;
use crate::spectrum::sampled::{ColourKind, SampledWavelengths};
use crate::texture::{FloatTex, SpectrumTex, TexCoord, TextureEval};

/// A material as given in a scene (pbrt-v4's names and parameters), plain data.
#[derive(Clone, Debug, PartialEq)]
pub enum Material {
    /// Lambertian reflection: f = ρ/π.
    Diffuse {
        /// Albedo ρ.
        reflectance: SpectrumTex,
    },
    /// A metal: Fresnel reflection with complex index `eta + i·k`, or an artist's
    /// `reflectance` (normal-incidence colour) when given; smooth or rough (GGX).
    Conductor {
        /// Real part of the index of refraction, per channel.
        eta: SpectrumTex,
        /// Imaginary part (absorption), per channel.
        k: SpectrumTex,
        /// When set, replaces `eta`/`k` by the index that gives this reflectance at normal
        /// incidence.
        reflectance: Option<SpectrumTex>,
        /// Roughness along u.
        uroughness: FloatTex,
        /// Roughness along v.
        vroughness: FloatTex,
        /// Map roughness to the microfacet α as pbrt does (`remaproughness`).
        remap_roughness: bool,
    },
    /// Glass: Fresnel reflection and refraction, smooth or rough.
    Dielectric {
        /// Relative index of refraction (inside / outside); a named glass's varies with
        /// wavelength.
        eta: Ior,
        /// Roughness along u.
        uroughness: FloatTex,
        /// Roughness along v.
        vroughness: FloatTex,
        /// Map roughness to α as pbrt does.
        remap_roughness: bool,
    },
    /// An infinitely thin dielectric slab (a window pane): no refraction offset.
    ThinDielectric {
        /// Index of refraction.
        eta: Ior,
    },
    /// Diffuse reflection and diffuse transmission.
    DiffuseTransmission {
        /// Albedo of reflection.
        reflectance: SpectrumTex,
        /// Albedo of transmission.
        transmittance: SpectrumTex,
        /// Multiplies both.
        scale: f32,
    },
    /// A diffuse base under a dielectric coating (varnish, plastic).
    CoatedDiffuse {
        /// Albedo of the base.
        reflectance: SpectrumTex,
        /// Coating roughness along u.
        uroughness: FloatTex,
        /// Coating roughness along v.
        vroughness: FloatTex,
        /// Thickness of the medium between coating and base.
        thickness: FloatTex,
        /// Index of refraction of the coating; one that varies with wavelength is taken at
        /// the hero wavelength, as a dielectric's (see [`Material::disperses`]).
        eta: Ior,
        /// Albedo of the medium in the coating.
        albedo: SpectrumTex,
        /// Henyey–Greenstein asymmetry of that medium.
        g: FloatTex,
        /// Maximum number of bounces in the layer's random walk.
        max_depth: u32,
        /// Number of random-walk samples per evaluation.
        n_samples: u32,
        /// Map roughness to α as pbrt does.
        remap_roughness: bool,
    },
    /// A conductor under a dielectric coating.
    CoatedConductor {
        /// Coating roughness along u.
        interface_uroughness: FloatTex,
        /// Coating roughness along v.
        interface_vroughness: FloatTex,
        /// Coating index of refraction (taken at the hero wavelength when it varies).
        interface_eta: Ior,
        /// Conductor's `eta`.
        conductor_eta: SpectrumTex,
        /// Conductor's `k`.
        k: SpectrumTex,
        /// Conductor's reflectance, replacing `eta`/`k` when given.
        reflectance: Option<SpectrumTex>,
        /// Conductor roughness along u.
        conductor_uroughness: FloatTex,
        /// Conductor roughness along v.
        conductor_vroughness: FloatTex,
        /// Thickness of the coating medium.
        thickness: FloatTex,
        /// Albedo of the coating medium.
        albedo: SpectrumTex,
        /// Henyey–Greenstein asymmetry.
        g: FloatTex,
        /// Random-walk depth.
        max_depth: u32,
        /// Random-walk samples.
        n_samples: u32,
        /// Map roughness to α as pbrt does.
        remap_roughness: bool,
    },
    /// Chooses between two materials per hit with probability `amount` for the second.
    Mix {
        /// Indices of the two materials in the scene's list.
        materials: [u32; 2],
        /// Probability of choosing the second.
        amount: FloatTex,
    },
    /// Hair fibres (pbrt-v4's `hair`, [`HairBxdf`]), meant for `curve` shapes.
    Hair(HairMaterial),
    /// A tabulated BRDF read from an RGL `.bsdf` file (pbrt-v4's `measured`, [`MeasuredBxdf`]).
    Measured(&'static MeasuredData),
    /// A dielectric boundary over a scattering medium, rendered with a BSSRDF (pbrt-v4's
    /// `subsurface`, [`TabulatedBssrdf`]).
    Subsurface(SubsurfaceMaterial),
    /// No surface at all: marks the boundary of a participating medium; rays pass through.
    Interface,
    /// Material `base` with its shading frame changed by a bump map (`displacement`) or a
    /// normal map (pbrt-v4's `normalmap`, which wins when both are given); see [`bump`].
    Bumped {
        /// Index of the material underneath in the scene's list.
        base: u32,
        /// Height texture.
        displacement: Option<FloatTex>,
        /// Spectrum texture holding the tangent-space normal image.
        normal_map: Option<u32>,
    },
}

impl Default for Material {
    /// pbrt's default: diffuse with reflectance 0.5.
    fn default() -> Self {
        Material::Diffuse {
            reflectance: SpectrumTex::Const(crate::math::Rgb::splat(0.5)),
        }
    }
}

/// pbrt's treatment of an index of refraction of 0 (unset or meaningless): 1.
#[inline]
fn nonzero_eta(eta: f32) -> f32 {
    if eta == 0.0 { 1.0 } else { eta }
}

/// How many constant colours a material can have ([`Material::colour_slots`]).
pub const COLOUR_SLOTS: usize = 4;

/// Spectral mode's view of a material at a hit: the path's wavelengths and the material's
/// constant colours, prepared once per scene ([`PreparedSpectrum`], by
/// [`Material::colour_slots`]).
#[derive(Clone, Copy, Debug)]
pub struct SpectralColours<'a> {
    /// The path's wavelengths.
    pub lambda: &'a SampledWavelengths,
    /// The material's constant colours as spectra, by slot (unused slots are anything).
    pub consts: &'a [PreparedSpectrum; COLOUR_SLOTS],
}

impl SpectralColours<'_> {
    /// The constant colour of slot `slot` at the path's wavelengths.
    #[inline(always)]
    pub fn constant(&self, slot: usize) -> SampledSpectrum {
        self.lambda.sample_prepared(&self.consts[slot])
    }
}

/// RGB mode's value of a colour `c` as transport uses it, as lanes (r, g, b, b): an albedo
/// clamped to [0, 1], an unbounded colour as it is.
#[inline(always)]
pub(crate) fn rgb_colour(c: Rgb, kind: ColourKind) -> SampledSpectrum {
    rgb_lanes(match kind {
        ColourKind::Albedo => c.clamp(Rgb::ZERO, Rgb::ONE),
        ColourKind::Unbounded => c,
    })
}

/// A material's colour `t` (slot `slot` of its constant colours) at a hit, as every material
/// reads its colours. RGB mode: [`rgb_colour`] of the texture's value. Spectral mode: the
/// prepared spectrum of a constant ([`SpectralColours::constant`]), or a texture's value at the
/// wavelengths (the uplift of its RGB value, which clamps an albedo the same way first, or for
/// a tree holding spectra its sampled values, as pbrt-v4 evaluates spectrum textures).
#[inline(always)]
pub(crate) fn slot_colour(
    tex: &TextureEval,
    tc: &TexCoord,
    spectral: Option<SpectralColours>,
    slot: usize,
    t: SpectrumTex,
    kind: ColourKind,
) -> SampledSpectrum {
    match (spectral, t) {
        (None, _) => rgb_colour(tex.spectrum(t, tc), kind),
        (Some(sc), SpectrumTex::Const(_) | SpectrumTex::Measured(_)) => sc.constant(slot),
        (Some(sc), SpectrumTex::Tex(_)) => tex.spectrum_at(t, tc, sc.lambda, kind),
    }
}

/// The conductor index pbrt-v4 uses: `eta`/`k` as given (slots 0 and 1), or, when an artist's
/// `reflectance` r is given instead (slot 2), η = 1 and k = 2√r / √(1 − r) (r clamped to
/// [0, 0.9999]), which makes the normal-incidence Fresnel reflectance
/// ((η − 1)² + k²)/((η + 1)² + k²) equal r. `colour` gives a slot's value at the path's
/// wavelengths (spectral mode: `eta` and `k` unbounded spectra, r a reflectance spectrum) or
/// its RGB lanes.
fn conductor_index(
    colour: &impl Fn(usize, SpectrumTex, ColourKind) -> SampledSpectrum,
    eta: SpectrumTex,
    k: SpectrumTex,
    reflectance: Option<SpectrumTex>,
) -> (SampledSpectrum, SampledSpectrum) {
    match reflectance {
        Some(r) => {
            let r = colour(2, r, ColourKind::Albedo)
                .clamp(SampledSpectrum::ZERO, SampledSpectrum::splat(0.9999));
            let k = 2.0 * r.map(f32::sqrt)
                / (SampledSpectrum::ONE - r)
                    .max(SampledSpectrum::ZERO)
                    .map(f32::sqrt);
            (SampledSpectrum::ONE, k)
        }
        None => (
            colour(0, eta, ColourKind::Unbounded),
            colour(1, k, ColourKind::Unbounded),
        ),
    }
}

impl Material {
    /// The pbrt-v4 name of this material (`Material "…"`): `diffuse`, `conductor`, …
    pub fn pbrt_name(&self) -> &'static str {
        match self {
            Material::Diffuse { .. } => "diffuse",
            Material::Conductor { .. } => "conductor",
            Material::Dielectric { .. } => "dielectric",
            Material::ThinDielectric { .. } => "thindielectric",
            Material::DiffuseTransmission { .. } => "diffusetransmission",
            Material::CoatedDiffuse { .. } => "coateddiffuse",
            Material::CoatedConductor { .. } => "coatedconductor",
            Material::Mix { .. } => "mix",
            Material::Hair { .. } => "hair",
            Material::Measured(_) => "measured",
            Material::Subsurface { .. } => "subsurface",
            Material::Interface => "interface",
            Material::Bumped { .. } => "bumped",
        }
    }

    /// The material's colour parameters by slot, with what each describes: the slots
    /// [`Material::bxdf`] reads them from in spectral mode, where the constant ones have been
    /// turned into spectra once ([`SpectralColours`]). Diffuse: reflectance. Conductor: eta,
    /// k, reflectance. Diffuse transmission: reflectance, transmittance. Coated diffuse:
    /// reflectance, medium albedo. Coated conductor: eta, k, reflectance, medium albedo.
    pub fn colour_slots(&self) -> [Option<(SpectrumTex, ColourKind)>; COLOUR_SLOTS] {
        use ColourKind::{Albedo, Unbounded};
        match *self {
            Material::Diffuse { reflectance } => [Some((reflectance, Albedo)), None, None, None],
            Material::Conductor {
                eta,
                k,
                reflectance,
                ..
            } => [
                Some((eta, Unbounded)),
                Some((k, Unbounded)),
                reflectance.map(|r| (r, Albedo)),
                None,
            ],
            Material::DiffuseTransmission {
                reflectance,
                transmittance,
                ..
            } => [
                Some((reflectance, Albedo)),
                Some((transmittance, Albedo)),
                None,
                None,
            ],
            Material::CoatedDiffuse {
                reflectance,
                albedo,
                ..
            } => [
                Some((reflectance, Albedo)),
                Some((albedo, Albedo)),
                None,
                None,
            ],
            Material::CoatedConductor {
                conductor_eta,
                k,
                reflectance,
                albedo,
                ..
            } => [
                Some((conductor_eta, Unbounded)),
                Some((k, Unbounded)),
                reflectance.map(|r| (r, Albedo)),
                Some((albedo, Albedo)),
            ],
            Material::Hair(h) => [h.absorption.colour_slot(), None, None, None],
            Material::Subsurface(ref m) => m.coefficients.colour_slots(),
            Material::Dielectric { .. }
            | Material::ThinDielectric { .. }
            | Material::Measured(_)
            | Material::Mix { .. }
            | Material::Interface
            | Material::Bumped { .. } => [None; COLOUR_SLOTS],
        }
    }

    /// Whether this material's index varies with wavelength (a dielectric, or a coating, of a
    /// named glass): in spectral mode a path that meets it keeps only its hero wavelength, as
    /// pbrt-v4's dielectric and coated materials call `TerminateSecondary` whenever their
    /// `eta` is not constant.
    pub fn disperses(&self) -> bool {
        match self {
            Material::Dielectric { eta, .. }
            | Material::ThinDielectric { eta }
            | Material::CoatedDiffuse { eta, .. }
            | Material::CoatedConductor {
                interface_eta: eta, ..
            } => eta.is_dispersive(),
            _ => false,
        }
    }

    /// The BxDF this material has at a surface point, with textures evaluated there, as
    /// pbrt-v4's materials build theirs: albedos clamped to [0, 1], roughness remapped to α
    /// when asked, an index of 0 taken as 1. `Mix` must be resolved by the caller first (it
    /// needs a random choice); `Interface` has none.
    ///
    /// With `spectral` (spectral mode) every colour becomes its values at the path's four
    /// wavelengths ([`SampledWavelengths`]): albedos as reflectance spectra, conductor indices as
    /// unbounded spectra; constant colours come prepared ([`SpectralColours`]), texture lookups
    /// are uplifted here. Without it (RGB mode) colours are used as they are, as lanes
    /// (r, g, b, b) ([`crate::math::rgb_lanes`]).
    pub fn bxdf(
        &self,
        tex: &TextureEval,
        tc: &TexCoord,
        spectral: Option<SpectralColours>,
    ) -> Option<BxDF> {
        // The colour in slot `slot` ([`slot_colour`]).
        let colour = |slot: usize, t: SpectrumTex, kind: ColourKind| -> SampledSpectrum {
            slot_colour(tex, tc, spectral, slot, t, kind)
        };
        let albedo = |slot: usize, t: SpectrumTex| colour(slot, t, ColourKind::Albedo);
        // A dielectric's index: RGB mode's single value, or the value at the hero wavelength
        // λ₀ (the only one a dispersive path keeps, see [`Material::disperses`]).
        let ior = |eta: Ior| match spectral {
            None => eta.constant_value(),
            Some(sc) => eta.at(sc.lambda.lambda[0]),
        };
        let distrib = |u: FloatTex, v: FloatTex, remap: bool| {
            TrowbridgeReitz::from_roughness(tex.float(u, tc), tex.float(v, tc), remap)
        };
        Some(match *self {
            Material::Diffuse { reflectance } => BxDF::diffuse(albedo(0, reflectance)),
            Material::Conductor {
                eta,
                k,
                reflectance,
                uroughness,
                vroughness,
                remap_roughness,
            } => {
                let (eta, k) = conductor_index(&colour, eta, k, reflectance);
                BxDF::Conductor(ConductorBxdf {
                    distrib: distrib(uroughness, vroughness, remap_roughness),
                    eta,
                    k,
                })
            }
            Material::Dielectric {
                eta,
                uroughness,
                vroughness,
                remap_roughness,
            } => BxDF::Dielectric(DielectricBxdf {
                eta: nonzero_eta(ior(eta)),
                distrib: distrib(uroughness, vroughness, remap_roughness),
            }),
            Material::ThinDielectric { eta } => BxDF::ThinDielectric(ThinDielectricBxdf {
                eta: nonzero_eta(ior(eta)),
            }),
            Material::DiffuseTransmission {
                reflectance,
                transmittance,
                scale,
            } => {
                // pbrt-v4: clamp(scale · ρ(λ), 0, 1), ρ a reflectance spectrum (in RGB mode the
                // colour is scaled before it is clamped, so scale < 1 can tame a colour > 1).
                let scaled = |slot: usize, t: SpectrumTex| {
                    let rho = match spectral {
                        None => rgb_lanes(tex.spectrum(t, tc)),
                        Some(_) => albedo(slot, t),
                    };
                    (rho * scale).clamp(SampledSpectrum::ZERO, SampledSpectrum::ONE)
                };
                BxDF::DiffuseTransmission(DiffuseTransmissionBxdf {
                    r: scaled(0, reflectance),
                    t: scaled(1, transmittance),
                })
            }
            Material::CoatedDiffuse {
                reflectance,
                uroughness,
                vroughness,
                thickness,
                eta,
                albedo: medium_albedo,
                g,
                max_depth,
                n_samples,
                remap_roughness,
            } => BxDF::CoatedDiffuse(CoatedDiffuseBxdf::new(
                DielectricBxdf {
                    eta: nonzero_eta(ior(eta)),
                    distrib: distrib(uroughness, vroughness, remap_roughness),
                },
                DiffuseBxdf {
                    r: albedo(0, reflectance),
                },
                tex.float(thickness, tc),
                albedo(1, medium_albedo),
                tex.float(g, tc).clamp(-1.0, 1.0),
                max_depth,
                n_samples,
            )),
            Material::CoatedConductor {
                interface_uroughness,
                interface_vroughness,
                interface_eta,
                conductor_eta,
                k,
                reflectance,
                conductor_uroughness,
                conductor_vroughness,
                thickness,
                albedo: medium_albedo,
                g,
                max_depth,
                n_samples,
                remap_roughness,
            } => {
                let ieta = nonzero_eta(ior(interface_eta));
                let (ce, ck) = conductor_index(&colour, conductor_eta, k, reflectance);
                BxDF::CoatedConductor(CoatedConductorBxdf::new(
                    DielectricBxdf {
                        eta: ieta,
                        distrib: distrib(
                            interface_uroughness,
                            interface_vroughness,
                            remap_roughness,
                        ),
                    },
                    // Under the coating the conductor borders the coating's medium, not air:
                    // its index relative to that medium is (η + ik)/η_coating.
                    ConductorBxdf {
                        distrib: distrib(
                            conductor_uroughness,
                            conductor_vroughness,
                            remap_roughness,
                        ),
                        eta: ce / ieta,
                        k: ck / ieta,
                    },
                    tex.float(thickness, tc),
                    albedo(3, medium_albedo),
                    tex.float(g, tc).clamp(-1.0, 1.0),
                    max_depth,
                    n_samples,
                ))
            }
            Material::Hair(h) => BxDF::Hair(hair::hair_at(
                &h,
                tex,
                tc,
                spectral.map(|sc| sc.lambda),
                &colour,
            )),
            Material::Measured(data) => {
                BxDF::Measured(MeasuredBxdf::new(data, spectral.map(|sc| sc.lambda)))
            }
            Material::Subsurface(ref m) => BxDF::Dielectric(DielectricBxdf {
                eta: nonzero_eta(m.eta),
                distrib: distrib(m.uroughness, m.vroughness, m.remap_roughness),
            }),
            Material::Mix { .. } | Material::Interface | Material::Bumped { .. } => return None,
        })
    }
}

#[cfg(test)]
mod tests;
