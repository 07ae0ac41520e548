//! The material family: one line per kind in [`material_kinds!`]'s list below, and each kind in
//! its own file of `kinds/`, which owns its description (plain data, what the readers make), its
//! build into the form the renderer uses, its colour list and its BxDF at a hit with its own
//! texture and colour lookups ([`HitLookup`]).
//!
//! The list makes [`MaterialDesc`] (the description enum of [`crate::SceneDesc`]) and
//! [`Material`] (the runtime enum of [`crate::Scene`]) and writes their `match`es once, each
//! arm a direct call to the kind's method (static dispatch, inlined into one function as a
//! hand-written `match` would be).

pub mod bumped;
pub mod coated_conductor;
pub mod coated_diffuse;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod diffuse_transmission;
pub mod hair;
pub mod interface;
pub mod measured;
pub mod mix;
pub mod subsurface;
pub mod thin_dielectric;

use super::at_hit::{Colours, HitLookup, NO_COLOURS, SpectralColours};
use super::{BxDF, MeasuredFile};
use crate::texture::{TexCoord, TextureEval};

/// A material kind's description: plain data, built once per scene into what the renderer
/// uses.
pub trait MaterialDescKind {
    /// The kind's runtime form.
    type Built: MaterialKind;
    /// The pbrt-v4 name of the kind (`Material "…"`).
    const PBRT_NAME: &'static str;
    /// The runtime form of this description.
    fn build(&self) -> Self::Built;
}

/// A material kind at render time: what the path tracer asks of it at a hit.
pub trait MaterialKind {
    /// Its colour parameters, in the order its [`MaterialKind::bxdf`] reads them back
    /// ([`Colours`]); none by default.
    #[inline(always)]
    fn colours(&self) -> Colours {
        NO_COLOURS
    }

    /// Its BxDF at a hit, textures and colours read through `at`, as pbrt-v4's materials
    /// build theirs (albedos clamped to [0, 1], roughness remapped to α when asked, an index of
    /// 0 taken as 1); `None` for the kinds that have none of their own (`mix`, `interface`,
    /// `bumped`, which the caller resolves).
    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        let _ = at;
        None
    }

    /// Whether a hit on it may scatter by a specular (delta) lobe; true unless the kind
    /// knows better (a diffuse surface, a rough surface of constant roughness): `path` with
    /// `caustics` aims its light paths at the surfaces that may
    /// ([`crate::integrator::caustics`]).
    #[inline(always)]
    fn may_be_specular(&self) -> bool {
        true
    }

    /// Whether its index varies with wavelength (a dielectric, or a coating, of a named
    /// glass): in spectral mode a path that meets it keeps only its hero wavelength, as
    /// pbrt-v4's dielectric and coated materials call `TerminateSecondary` whenever their
    /// `eta` is not constant.
    #[inline(always)]
    fn disperses(&self) -> bool {
        false
    }
}

/// Writes the family's two enums and their `match`es from the list of kinds: per kind, its
/// variant name and its description type (its runtime type is the description's
/// [`MaterialDescKind::Built`]).
macro_rules! material_kinds {
    ($($(#[$doc:meta])* $kind:ident($desc:ty),)*) => {
        /// A material as given in a scene (pbrt-v4's names and parameters), plain data; the
        /// scene build turns it into a [`Material`] ([`MaterialDesc::build`]).
        #[derive(Clone, Debug, PartialEq)]
        pub enum MaterialDesc {
            $($(#[$doc])* $kind($desc),)*
        }

        /// A material as the renderer uses it, built from a [`MaterialDesc`]: turned at each
        /// hit into a BxDF ([`Material::bxdf`]).
        #[derive(Clone, Debug, PartialEq)]
        pub enum Material {
            $($(#[$doc])* $kind(<$desc as MaterialDescKind>::Built),)*
        }

        impl MaterialDesc {
            /// The pbrt-v4 name of this material (`Material "…"`): `diffuse`, `conductor`, …
            pub fn pbrt_name(&self) -> &'static str {
                match self {
                    $(MaterialDesc::$kind(_) => <$desc as MaterialDescKind>::PBRT_NAME,)*
                }
            }

            /// The runtime material of this description.
            pub fn build(&self) -> Material {
                match self {
                    $(MaterialDesc::$kind(m) => Material::$kind(m.build()),)*
                }
            }
        }

        impl Material {
            /// The material's colour parameters, with what each describes, in the order its
            /// kind reads them ([`MaterialKind::colours`]): spectral mode turns the constant
            /// ones into spectra once per scene ([`SpectralColours`]).
            pub fn colour_slots(&self) -> Colours {
                match self {
                    $(Material::$kind(m) => m.colours(),)*
                }
            }

            /// Whether a hit on it may scatter specularly ([`MaterialKind::may_be_specular`]).
            pub fn may_be_specular(&self) -> bool {
                match self {
                    $(Material::$kind(m) => m.may_be_specular(),)*
                }
            }

            /// Whether this material's index varies with wavelength
            /// ([`MaterialKind::disperses`]).
            pub fn disperses(&self) -> bool {
                match self {
                    $(Material::$kind(m) => m.disperses(),)*
                }
            }

            /// The BxDF this material has at a surface point, with textures evaluated there
            /// ([`MaterialKind::bxdf`]). `Mix` must be resolved by the caller first (it needs
            /// a random choice); `Interface` and `Bumped` have none.
            ///
            /// With `spectral` (spectral mode) every colour becomes its values at the path's
            /// four wavelengths: albedos as reflectance spectra, conductor indices as unbounded
            /// spectra; constant colours come prepared ([`SpectralColours`]), texture lookups
            /// are uplifted at the hit. Without it (RGB mode) colours are used as they are, as
            /// lanes (r, g, b, b) ([`crate::math::rgb_lanes`]).
            pub fn bxdf(
                &self,
                tex: &TextureEval,
                tc: &TexCoord,
                spectral: Option<SpectralColours>,
            ) -> Option<BxDF> {
                let at = HitLookup { tex, tc, spectral };
                match self {
                    $(Material::$kind(m) => m.bxdf(&at),)*
                }
            }
        }
    };
}

material_kinds! {
    /// Lambertian reflection: f = ρ/π.
    Diffuse(diffuse::DiffuseMaterial),
    /// A metal: Fresnel reflection with complex index `eta + i·k`, or an artist's
    /// `reflectance`; smooth or rough (GGX).
    Conductor(conductor::ConductorMaterial),
    /// Glass: Fresnel reflection and refraction, smooth or rough.
    Dielectric(dielectric::DielectricMaterial),
    /// An infinitely thin dielectric slab (a window pane): no refraction offset.
    ThinDielectric(thin_dielectric::ThinDielectricMaterial),
    /// Diffuse reflection and diffuse transmission.
    DiffuseTransmission(diffuse_transmission::DiffuseTransmissionMaterial),
    /// A diffuse base under a dielectric coating (varnish, plastic).
    CoatedDiffuse(coated_diffuse::CoatedDiffuseMaterial),
    /// A conductor under a dielectric coating.
    CoatedConductor(coated_conductor::CoatedConductorMaterial),
    /// Chooses between two materials per hit with probability `amount` for the second.
    Mix(mix::MixMaterial),
    /// Hair fibres (pbrt-v4's `hair`, [`super::HairBxdf`]), meant for `curve` shapes.
    Hair(hair::HairMaterial),
    /// A tabulated BRDF read from an RGL `.bsdf` file (pbrt-v4's `measured`,
    /// [`super::MeasuredBxdf`]): the file's tables, shared by the materials naming it; built
    /// into its sampling tables ([`super::MeasuredData`]).
    Measured(std::sync::Arc<MeasuredFile>),
    /// A dielectric boundary over a scattering medium, rendered with a BSSRDF (pbrt-v4's
    /// `subsurface`, [`super::TabulatedBssrdf`]); built into a
    /// [`subsurface::BuiltSubsurface`], which adds the profile table.
    Subsurface(subsurface::SubsurfaceMaterial),
    /// No surface at all: marks the boundary of a participating medium; rays pass through.
    Interface(interface::InterfaceMaterial),
    /// Material `base` with its shading frame changed by a bump map (`displacement`) or a
    /// normal map (pbrt-v4's `normalmap`, which wins when both are given); see
    /// [`super::bump`].
    Bumped(bumped::BumpedMaterial),
}

impl Default for MaterialDesc {
    /// pbrt's default: diffuse with reflectance 0.5.
    fn default() -> Self {
        MaterialDesc::Diffuse(diffuse::DiffuseMaterial::default())
    }
}

/// Whether a microfacet lobe of roughness (`u`, `v`) may be specular: false only when both are
/// constants whose α (remapped as pbrt-v4 does with `remap`) is not effectively smooth.
pub(crate) fn may_be_smooth(
    u: crate::texture::FloatTex,
    v: crate::texture::FloatTex,
    remap: bool,
) -> bool {
    use super::microfacet::TrowbridgeReitz;
    use crate::texture::FloatTex;
    match (u, v) {
        (FloatTex::Const(a), FloatTex::Const(b)) => {
            let alpha = |r: f32| {
                if remap {
                    TrowbridgeReitz::roughness_to_alpha(r)
                } else {
                    r
                }
            };
            TrowbridgeReitz::new(alpha(a), alpha(b)).effectively_smooth()
        }
        _ => true,
    }
}
