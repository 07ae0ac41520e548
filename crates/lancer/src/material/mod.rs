//! Materials: how a surface scatters light, as plain data ([`Material`]), turned at each hit
//! into a [`Bsdf`] in the local shading frame.

mod bxdf;
mod fresnel;

pub use bxdf::{Bsdf, BsdfSample, BxDF, BxdfFlags, TransportMode};
pub use fresnel::{fresnel_complex, fresnel_dielectric, reflect, refract};

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
        /// Relative index of refraction (inside / outside).
        eta: f32,
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
        eta: f32,
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
        /// Index of refraction of the coating.
        eta: f32,
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
        /// Coating index of refraction.
        interface_eta: f32,
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
    /// No surface at all: marks the boundary of a participating medium; rays pass through.
    Interface,
}

impl Default for Material {
    /// pbrt's default: diffuse with reflectance 0.5.
    fn default() -> Self {
        Material::Diffuse {
            reflectance: SpectrumTex::Const(crate::math::Rgb::splat(0.5)),
        }
    }
}

impl Material {
    /// The BxDF this material has at a surface point, with textures evaluated there. `Mix` must
    /// be resolved by the caller first (it needs a random choice); `Interface` has none.
    pub fn bxdf(&self, tex: &TextureEval, tc: &TexCoord) -> Option<BxDF> {
        match self {
            Material::Diffuse { reflectance } => Some(BxDF::Diffuse {
                r: tex
                    .spectrum(*reflectance, tc)
                    .clamp(crate::math::Rgb::ZERO, crate::math::Rgb::ONE),
            }),
            Material::Conductor {
                eta,
                k,
                reflectance,
                ..
            } => {
                let (eta, k) = match reflectance {
                    Some(r) => {
                        // pbrt: k = 2√r / √(1 − r), eta = 1, so that F(0) = r.
                        let r = tex
                            .spectrum(*r, tc)
                            .clamp(crate::math::Rgb::ZERO, crate::math::Rgb::splat(0.9999));
                        let k = 2.0 * r.map(f32::sqrt) / (crate::math::Rgb::ONE - r).map(f32::sqrt);
                        (crate::math::Rgb::ONE, k)
                    }
                    None => (tex.spectrum(*eta, tc), tex.spectrum(*k, tc)),
                };
                Some(BxDF::Conductor { eta, k })
            }
            Material::Dielectric { eta, .. } | Material::ThinDielectric { eta } => {
                Some(BxDF::Dielectric { eta: *eta })
            }
            Material::DiffuseTransmission {
                reflectance, scale, ..
            } => Some(BxDF::Diffuse {
                r: (tex.spectrum(*reflectance, tc) * *scale)
                    .clamp(crate::math::Rgb::ZERO, crate::math::Rgb::ONE),
            }),
            Material::CoatedDiffuse { reflectance, .. } => Some(BxDF::Diffuse {
                r: tex
                    .spectrum(*reflectance, tc)
                    .clamp(crate::math::Rgb::ZERO, crate::math::Rgb::ONE),
            }),
            Material::CoatedConductor {
                conductor_eta, k, ..
            } => Some(BxDF::Conductor {
                eta: tex.spectrum(*conductor_eta, tc),
                k: tex.spectrum(*k, tc),
            }),
            Material::Mix { .. } | Material::Interface => None,
        }
    }
}
