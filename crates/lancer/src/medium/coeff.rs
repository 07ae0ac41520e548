//! What every grid medium shares: a medium's properties at a point, constant coefficients
//! prepared for both rendering modes, and black-body emission from a temperature.
//!
//! A coefficient given as RGB becomes, in spectral mode, pbrt-v4's `RGBUnboundedSpectrum`
//! (σ_a, σ_s) or `RGBIlluminantSpectrum` (emission) at the path's wavelengths; in RGB mode
//! (`lambda` = `None`) it is its own lanes (r, g, b, b).

use crate::math::{Rgb, SampledSpectrum, rgb_lanes};
use crate::spectrum::sampled::{ColourKind, RgbSpectrum, SampledWavelengths};
use crate::spectrum::{Spectrum, spectrum_to_xyz_unnormalised, xyz_to_srgb};
use std::sync::OnceLock;

/// A medium's properties at a point (pbrt-v4's `MediumProperties` without the phase function,
/// which is the medium's Henyey–Greenstein `g`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointProperties {
    /// Absorption coefficient σ_a.
    pub sigma_a: SampledSpectrum,
    /// Scattering coefficient σ_s.
    pub sigma_s: SampledSpectrum,
    /// Emitted radiance L_e.
    pub le: SampledSpectrum,
}

/// An RGB coefficient prepared once for both modes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Coefficient {
    /// The colour (RGB mode).
    pub rgb: Rgb,
    /// Its spectrum, 2m·s(λ) (spectral mode).
    pub spectrum: RgbSpectrum,
}

impl Default for Coefficient {
    fn default() -> Self {
        Coefficient::new(Rgb::ZERO)
    }
}

impl Coefficient {
    /// `rgb` as an unbounded coefficient (negative components are clamped to 0, as pbrt-v4's
    /// `RGBUnboundedSpectrum` does).
    pub fn new(rgb: Rgb) -> Coefficient {
        let rgb = rgb.max(Rgb::ZERO);
        Coefficient {
            rgb,
            spectrum: RgbSpectrum::new(rgb, ColourKind::Unbounded),
        }
    }

    /// σ at the path's wavelengths (spectral) or its lanes (RGB).
    #[inline]
    pub fn at(&self, lambda: Option<&SampledWavelengths>) -> SampledSpectrum {
        match lambda {
            Some(w) => w.sample(&self.spectrum),
            None => rgb_lanes(self.rgb),
        }
    }

    /// The colour as emitted radiance: pbrt-v4's `RGBIlluminantSpectrum` (times D65) in
    /// spectral mode, the lanes in RGB mode.
    #[inline]
    pub fn emission_at(&self, lambda: Option<&SampledWavelengths>) -> SampledSpectrum {
        match lambda {
            Some(w) => w.sample_illuminant(&self.spectrum),
            None => rgb_lanes(self.rgb),
        }
    }

    /// The largest value over the visible wavelengths or the RGB components, whichever is
    /// larger: a bound for [`Coefficient::at`] in both modes. The sigmoid s(λ) of a quadratic
    /// peaks at an end of [360, 830] nm or at the quadratic's vertex.
    pub fn max_value(&self) -> f32 {
        use crate::spectrum::uplift::SigmoidSpectrum;
        let sp = &self.spectrum;
        let mut m = 0.0f32;
        for l in [360.0f32, 830.0] {
            m = m.max(sp.s.eval(l));
        }
        if let SigmoidSpectrum::Poly([c0, c1, _]) = sp.s
            && c0 != 0.0
        {
            let t = -c1 / (2.0 * c0);
            if (0.0..=1.0).contains(&t) {
                m = m.max(sp.s.eval(360.0 + t * 470.0));
            }
        }
        (m * sp.scale).max(self.rgb.max_element())
    }
}

/// Lowest temperature that emits, as pbrt-v4: colder points give no light.
pub const MIN_EMITTING_KELVIN: f32 = 100.0;

/// Radiance of a black body at `kelvin`, normalised to a peak of 1 (pbrt-v4's
/// `BlackbodySpectrum`): B(λ, T)/B(λ_max, T), λ_max = b/T (Wien, b = 2.8977721·10⁻³ m·K).
/// In RGB mode, the film colour of that spectrum (∫B̂·(x̄, ȳ, z̄)dλ/∫ȳdλ, then sRGB), from a
/// table in log T. Zero at or below [`MIN_EMITTING_KELVIN`].
pub fn blackbody_at(lambda: Option<&SampledWavelengths>, kelvin: f32) -> SampledSpectrum {
    if kelvin.is_nan() || kelvin <= MIN_EMITTING_KELVIN {
        return SampledSpectrum::ZERO;
    }
    match lambda {
        Some(w) => {
            let peak = 2.897_772e-3 / kelvin * 1e9;
            let b_max = crate::spectrum::blackbody(peak, kelvin);
            if b_max.is_nan() || b_max <= 0.0 {
                return SampledSpectrum::ZERO;
            }
            SampledSpectrum::from_array(
                w.lambda
                    .to_array()
                    .map(|l| crate::spectrum::blackbody(l, kelvin) / b_max),
            )
        }
        None => rgb_lanes(blackbody_rgb(kelvin)),
    }
}

/// Temperatures of the RGB table: log-spaced from 100 K to 10⁵ K.
const BB_N: usize = 512;
const BB_LOG_MIN: f32 = 4.605_170_2; // ln 100
const BB_LOG_MAX: f32 = 11.512_925; // ln 100000

/// The film RGB of the normalised black body at `kelvin` (clamped to the table's range),
/// interpolated linearly in ln T.
pub fn blackbody_rgb(kelvin: f32) -> Rgb {
    static TABLE: OnceLock<Vec<Rgb>> = OnceLock::new();
    let table = TABLE.get_or_init(|| {
        let y_integral = spectrum_to_xyz_unnormalised(&Spectrum::Constant(1.0))[1];
        (0..BB_N)
            .map(|i| {
                let lt = BB_LOG_MIN + (BB_LOG_MAX - BB_LOG_MIN) * i as f32 / (BB_N - 1) as f32;
                let xyz = spectrum_to_xyz_unnormalised(&Spectrum::Blackbody { kelvin: lt.exp() });
                xyz_to_srgb(xyz.map(|v| v / y_integral))
            })
            .collect()
    });
    let x = ((kelvin.max(1.0).ln() - BB_LOG_MIN) / (BB_LOG_MAX - BB_LOG_MIN) * (BB_N - 1) as f32)
        .clamp(0.0, (BB_N - 1) as f32);
    let i = (x as usize).min(BB_N - 2);
    let t = x - i as f32;
    table[i] * (1.0 - t) + table[i + 1] * t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grey_coefficients_are_constant_in_both_modes() {
        let c = Coefficient::new(Rgb::splat(0.7));
        assert_eq!(c.at(None), SampledSpectrum::splat(0.7));
        let w = SampledWavelengths::sample_visible(0.3);
        let s = c.at(Some(&w));
        assert!(
            (s - SampledSpectrum::splat(0.7)).abs().max_element() < 1e-4,
            "{s}"
        );
        assert!((c.max_value() - 0.7).abs() < 1e-4);
        // Negative components are clamped.
        assert_eq!(
            Coefficient::new(Rgb::new(-1.0, 2.0, 0.0)).rgb,
            Rgb::new(0.0, 2.0, 0.0)
        );
    }

    #[test]
    fn coloured_coefficient_max_bounds_its_spectrum() {
        let c = Coefficient::new(Rgb::new(0.9, 1.2, 1.5));
        let m = c.max_value();
        for i in 0..200 {
            let w = SampledWavelengths::sample_visible(i as f32 / 200.0);
            assert!(c.at(Some(&w)).max_element() <= m * (1.0 + 1e-5));
        }
        assert!(m >= 1.5);
    }

    #[test]
    fn blackbody_peaks_at_one_and_is_dark_when_cold() {
        assert_eq!(blackbody_at(None, 50.0), SampledSpectrum::ZERO);
        assert_eq!(blackbody_at(None, f32::NAN), SampledSpectrum::ZERO);
        // 5000 K peaks at 579.6 nm: the normalised value there is 1.
        let mut w = SampledWavelengths::sample_visible(0.5);
        w.lambda = SampledSpectrum::new(2.897_772e-3 / 5000.0 * 1e9, 400.0, 700.0, 800.0);
        let b = blackbody_at(Some(&w), 5000.0);
        assert!((b.x - 1.0).abs() < 1e-4, "{b}");
        assert!(b.y < 1.0 && b.z < 1.0 && b.w < 1.0);
        // A hot body looks bluer than a cold one in RGB.
        let cold = blackbody_rgb(1500.0);
        let hot = blackbody_rgb(12000.0);
        assert!(cold.x > cold.z && hot.z > hot.x, "{cold} {hot}");
        // The RGB of 6504 K (≈ D65's colour temperature) is close to grey.
        let d = blackbody_rgb(6504.0);
        assert!((d.x / d.z - 1.0).abs() < 0.1, "{d}");
    }

    #[test]
    fn blackbody_rgb_agrees_with_the_spectral_film_on_average() {
        let k = 3000.0;
        let mut sum = Rgb::ZERO;
        let n = 4000;
        for i in 0..n {
            let w = SampledWavelengths::sample_visible((i as f32 + 0.5) / n as f32);
            sum += w.to_film_rgb(blackbody_at(Some(&w), k));
        }
        let spectral = sum / n as f32;
        let rgb = blackbody_rgb(k);
        assert!(
            (spectral - rgb).abs().max_element() < 0.01 * rgb.max_element(),
            "{spectral} {rgb}"
        );
    }
}
