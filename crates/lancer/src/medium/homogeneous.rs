//! pbrt-v4's `homogeneous` medium: σ_a, σ_s and Le the same everywhere, so the majorant is σ_t
//! itself and delta tracking never meets a null collision.

use super::phase::HgPhaseFunction;
use super::properties::MediumProperties;
use crate::math::{Rgb, SampledSpectrum, rgb_lanes};
use crate::spectrum::sampled::{ColourKind, RgbSpectrum, SampledWavelengths};

/// A coefficient as an RGB colour (RGB mode) and as its spectrum (spectral mode, pbrt-v4's
/// `RGBUnboundedSpectrum`), prepared once.
#[derive(Clone, Copy, Debug)]
struct Coefficient {
    rgb: Rgb,
    spectrum: RgbSpectrum,
}

impl Coefficient {
    fn new(rgb: Rgb) -> Coefficient {
        Coefficient {
            rgb,
            spectrum: RgbSpectrum::new(rgb.max(Rgb::ZERO), ColourKind::Unbounded),
        }
    }

    #[inline]
    fn at(&self, lambda: Option<&SampledWavelengths>) -> SampledSpectrum {
        lambda.map_or(rgb_lanes(self.rgb), |w| w.sample(&self.spectrum))
    }

    #[inline]
    fn illuminant_at(&self, lambda: Option<&SampledWavelengths>) -> SampledSpectrum {
        lambda.map_or(rgb_lanes(self.rgb), |w| w.sample_illuminant(&self.spectrum))
    }
}

/// pbrt-v4's `homogeneous` medium as a scene describes it, plain data.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomogeneousDesc {
    /// Absorption coefficient σ_a (per unit length, before `scale`).
    pub sigma_a: Rgb,
    /// Scattering coefficient σ_s (before `scale`).
    pub sigma_s: Rgb,
    /// Multiplies σ_a and σ_s.
    pub scale: f32,
    /// Emitted radiance (RGB illuminant, already normalised as pbrt-v4 does), before
    /// `le_scale`.
    pub le: Rgb,
    /// Multiplies `le`.
    pub le_scale: f32,
    /// Henyey–Greenstein asymmetry g ∈ (−1, 1).
    pub g: f32,
}

impl HomogeneousDesc {
    /// The medium ready to render: σ_a·scale, σ_s·scale, Le·le_scale, g.
    pub fn build(&self) -> HomogeneousMedium {
        HomogeneousMedium::new(
            self.sigma_a * self.scale,
            self.sigma_s * self.scale,
            self.le * self.le_scale,
            self.g,
        )
    }
}

/// The same coefficients everywhere.
#[derive(Clone, Copy, Debug)]
pub struct HomogeneousMedium {
    sigma_a: Coefficient,
    sigma_s: Coefficient,
    le: Coefficient,
    phase: HgPhaseFunction,
}

impl HomogeneousMedium {
    /// A medium of absorption `sigma_a`, scattering `sigma_s` (scale applied), emission `le`
    /// (an RGB illuminant, scale applied) and Henyey–Greenstein asymmetry `g`.
    pub fn new(sigma_a: Rgb, sigma_s: Rgb, le: Rgb, g: f32) -> HomogeneousMedium {
        HomogeneousMedium {
            sigma_a: Coefficient::new(sigma_a),
            sigma_s: Coefficient::new(sigma_s),
            le: Coefficient::new(le),
            phase: HgPhaseFunction { g },
        }
    }

    /// True when Le is not black.
    pub fn is_emissive(&self) -> bool {
        self.le.rgb.max_element() > 0.0
    }

    /// σ_t = σ_a + σ_s at the wavelengths.
    #[inline]
    pub fn sigma_t(&self, lambda: Option<&SampledWavelengths>) -> SampledSpectrum {
        self.sigma_a.at(lambda) + self.sigma_s.at(lambda)
    }

    /// The properties (the same at every point).
    #[inline]
    pub fn properties(&self, lambda: Option<&SampledWavelengths>) -> MediumProperties {
        MediumProperties {
            sigma_a: self.sigma_a.at(lambda),
            sigma_s: self.sigma_s.at(lambda),
            le: if self.is_emissive() {
                self.le.illuminant_at(lambda)
            } else {
                SampledSpectrum::ZERO
            },
            phase: self.phase,
        }
    }
}
