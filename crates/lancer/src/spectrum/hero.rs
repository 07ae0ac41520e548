//! Dispersion's bookkeeping: a path that refracts through a material whose index varies with
//! wavelength follows one direction, right for its hero wavelength λ₀ only, so it keeps λ₀ and
//! drops the other three (pbrt-v4's `SampledWavelengths::TerminateSecondary`).
//!
//! pbrt-v4 sets the densities of lanes 1–3 to 0 and divides lane 0's by 4, so that the film's
//! estimate (1/4) Σᵢ L(λᵢ)/p(λᵢ) over the lanes of nonzero density becomes L(λ₀)/p(λ₀).
//! lancer's film converts with the wavelengths drawn for the camera sample, so the integrators
//! instead weight the path's radiance by [`HERO_ONLY`] = (4, 0, 0, 0): (1/4)·4·L(λ₀)/p(λ₀) is
//! the same estimate. They still terminate their own copy of the wavelengths, which marks the
//! path so that the weight is applied once.

use super::sampled::{N_SPECTRUM_SAMPLES, SampledWavelengths};
use crate::math::SampledSpectrum;

/// The weight that turns a four-wavelength radiance into the hero wavelength's alone, for the
/// film's unchanged densities: N = 4 in lane 0, 0 elsewhere.
pub const HERO_ONLY: SampledSpectrum =
    SampledSpectrum::new(N_SPECTRUM_SAMPLES as f32, 0.0, 0.0, 0.0);

impl SampledWavelengths {
    /// Keeps only the hero wavelength λ₀, as pbrt-v4: the densities of λ₁…λ₃ become 0 and
    /// λ₀'s is divided by N = 4. Does nothing if already done.
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        self.pdf = SampledSpectrum::new(self.pdf[0] / N_SPECTRUM_SAMPLES as f32, 0.0, 0.0, 0.0);
    }

    /// Whether [`SampledWavelengths::terminate_secondary`] has been called.
    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1] == 0.0 && self.pdf[2] == 0.0 && self.pdf[3] == 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terminate_secondary_keeps_the_hero_density_over_four() {
        let mut lambda = SampledWavelengths::sample_visible(0.3);
        let hero = (lambda.lambda[0], lambda.pdf[0]);
        assert!(!lambda.secondary_terminated());
        lambda.terminate_secondary();
        assert_eq!(lambda.lambda[0], hero.0);
        assert_eq!(lambda.pdf.to_array(), [hero.1 / 4.0, 0.0, 0.0, 0.0]);
        assert!(lambda.secondary_terminated());
        // Idempotent, as pbrt-v4's.
        lambda.terminate_secondary();
        assert_eq!(lambda.pdf[0], hero.1 / 4.0);
    }

    /// The film colour of radiance L with terminated wavelengths equals that of L·HERO_ONLY
    /// with the wavelengths as drawn, and depends on λ₀'s radiance only.
    #[test]
    fn hero_weight_matches_terminated_densities() {
        let drawn = SampledWavelengths::sample_visible(0.61);
        let mut terminated = drawn;
        terminated.terminate_secondary();
        let l = SampledSpectrum::new(0.7, 0.2, 1.3, 0.4);
        let a = terminated.to_film_rgb(l);
        let b = drawn.to_film_rgb(l * HERO_ONLY);
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-6 * a[c].abs().max(1.0),
                "{a:?} vs {b:?}"
            );
        }
        let other = terminated.to_film_rgb(SampledSpectrum::new(0.7, 9.0, 0.0, 5.0));
        assert_eq!(a, other);
        assert_ne!(a, drawn.to_film_rgb(l));
    }
}
