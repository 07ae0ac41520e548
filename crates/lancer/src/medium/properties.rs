//! What a medium is at one point (a leaf module: the media make it, the integrator reads it).

use super::phase::HgPhaseFunction;
use crate::math::SampledSpectrum;

/// A medium's local properties at a point, at the path's wavelengths.
#[derive(Clone, Copy, Debug)]
pub struct MediumProperties {
    /// Absorption coefficient.
    pub sigma_a: SampledSpectrum,
    /// Scattering coefficient.
    pub sigma_s: SampledSpectrum,
    /// Emitted radiance.
    pub le: SampledSpectrum,
    /// The phase function.
    pub phase: HgPhaseFunction,
}
