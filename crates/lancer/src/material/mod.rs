//! Materials: how a surface scatters light. A scene gives each as plain data
//! ([`MaterialDesc`]), the scene build turns it into a [`Material`], and at each hit the
//! material becomes a [`Bsdf`] in the local shading frame. Each kind lives in its own file of
//! `kinds/` (its description, build, colours and BxDF at a hit); [`kinds`] lists them.
//!
//! Adding a kind: a file in `kinds/` with its description type (implementing
//! [`MaterialDescKind`]: its pbrt name and its build) and its runtime type (implementing
//! [`MaterialKind`]: its colours and its BxDF at a hit, read through [`HitLookup`]), one line
//! in `material_kinds!`'s list in `kinds.rs`, and its reader in `lancer-scene`'s
//! `pbrt/materials.rs`.

mod at_hit;
mod bssrdf;
mod bump;
mod bxdf;
mod conductor;
mod dielectric;
mod diffuse;
mod fresnel;
mod hair;
pub mod kinds;
mod layered;
pub mod measured;
mod microfacet;
pub mod mix;
mod scatter;

pub(crate) use at_hit::rgb_colour;
pub use at_hit::{COLOUR_SLOTS, Colours, HitLookup, NO_COLOURS, SpectralColours};
pub use bssrdf::{
    BssrdfTable, NormalizedFresnelBxdf, ProbeSegment, TabulatedBssrdf, subsurface_from_diffuse,
};
pub use bump::{bump_shading, normal_map_shading};
pub use bxdf::{Bsdf, BxDF};
pub use conductor::ConductorBxdf;
pub use dielectric::{DielectricBxdf, ThinDielectricBxdf};
pub use diffuse::{DiffuseBxdf, DiffuseTransmissionBxdf};
pub use fresnel::{fresnel_complex, fresnel_dielectric, reflect, refract};
pub use hair::{HairBxdf, hair_sigma_a_from_concentration, hair_sigma_a_from_reflectance};
pub use kinds::bumped::BumpedMaterial;
pub use kinds::coated_conductor::CoatedConductorMaterial;
pub use kinds::coated_diffuse::CoatedDiffuseMaterial;
pub use kinds::conductor::ConductorMaterial;
pub use kinds::dielectric::DielectricMaterial;
pub use kinds::diffuse::DiffuseMaterial;
pub use kinds::diffuse_transmission::DiffuseTransmissionMaterial;
pub use kinds::hair::{HairAbsorption, HairMaterial};
pub use kinds::interface::InterfaceMaterial;
pub use kinds::mix::MixMaterial;
pub use kinds::subsurface::{BuiltSubsurface, SubsurfaceCoefficients, SubsurfaceMaterial};
pub use kinds::thin_dielectric::ThinDielectricMaterial;
pub use kinds::{Material, MaterialDesc, MaterialDescKind, MaterialKind};
pub use layered::{CoatedConductorBxdf, CoatedDiffuseBxdf, LayeredBxdf};
pub use measured::{MeasuredBxdf, MeasuredData, MeasuredFile};
pub use microfacet::TrowbridgeReitz;
pub use scatter::{BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode};

#[cfg(test)]
mod tests;
