//! Spectra carried as spectra in spectral mode: pbrt-v4's named spectra (metals' `eta`/`k`,
//! illuminants), `blackbody` and sampled (`.spd`, pairs) spectra, tabulated every 1 nm over the
//! sampled range ([`DenseSpectrum`], as pbrt-v4's `DenselySampledSpectrum`) so that a path
//! evaluates one at its four wavelengths with four table lookups.
//!
//! A scene's constant of this kind is a [`Measured`]: its RGB reduction, which RGB mode uses
//! exactly as before, and its table, which spectral mode samples. Scene preparation turns every
//! constant colour into a [`PreparedSpectrum`] (an uplifted RGB or such a table) once.

use std::sync::{Mutex, OnceLock};

use super::cie;
use super::reduce::{Spectrum, SpectrumKind};
use super::sampled::{LAMBDA_MAX, LAMBDA_MIN, RgbSpectrum, SampledWavelengths};
use crate::math::{Rgb, SampledSpectrum};

/// Number of 1 nm samples of a [`DenseSpectrum`]: 360, 361, …, 830 nm.
pub const DENSE_SAMPLES: usize = (LAMBDA_MAX - LAMBDA_MIN) as usize + 1;

/// A spectrum sampled every 1 nm over 360–830 nm, read by linear interpolation.
#[derive(Clone, PartialEq)]
pub struct DenseSpectrum {
    values: [f32; DENSE_SAMPLES],
}

impl std::fmt::Debug for DenseSpectrum {
    /// The table as its length and digest ([`Digest`](crate::math::digest::Digest)): a scene's
    /// debug form (which the CLI hashes) need not print 471 numbers per constant.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DenseSpectrum")
            .field("values", &crate::math::digest::Digest(&self.values[..]))
            .finish()
    }
}

impl DenseSpectrum {
    /// The table of `f(λ)` at λ = 360, 361, …, 830 nm.
    pub fn from_fn(f: impl Fn(f32) -> f32) -> DenseSpectrum {
        DenseSpectrum {
            values: std::array::from_fn(|i| f(LAMBDA_MIN + i as f32)),
        }
    }

    /// The table of a scene's spectrum ([`Spectrum::eval`] at every nanometre).
    pub fn from_spectrum(s: &Spectrum) -> DenseSpectrum {
        DenseSpectrum::from_fn(|l| s.eval(l))
    }

    /// The same table with `f` applied to every value.
    pub fn map(&self, f: impl Fn(f32) -> f32) -> DenseSpectrum {
        DenseSpectrum {
            values: self.values.map(f),
        }
    }

    /// The value at `lambda` (nm): linear between the two nearest nanometres, the end values
    /// outside 360–830 nm.
    #[inline]
    pub fn at(&self, lambda: f32) -> f32 {
        let x = (lambda - LAMBDA_MIN).clamp(0.0, (DENSE_SAMPLES - 1) as f32);
        let i = (x as usize).min(DENSE_SAMPLES - 2);
        let t = x - i as f32;
        self.values[i] * (1.0 - t) + self.values[i + 1] * t
    }

    /// The values at the four wavelengths of `lambda`, lane-wise. Out of line: callers that
    /// also evaluate uplifted colours (the commoner kind) keep that path short.
    #[inline(never)]
    pub fn sample(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        let l = lambda.lambda;
        SampledSpectrum::new(self.at(l.x), self.at(l.y), self.at(l.z), self.at(l.w))
    }

    /// Whether every value is the same, to single-precision rounding (relative 10⁻⁶: a
    /// constant given as pairs comes back from interpolation a few ulps apart), as a
    /// refractive index that does not disperse.
    pub fn is_constant(&self) -> bool {
        let (lo, hi) = self
            .values
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        hi - lo <= 1e-6 * hi.abs().max(lo.abs())
    }

    /// The luminance the film gives this spectrum taken as radiance: ∫ s·ȳ / ∫ ȳ (1 nm sums,
    /// the CIE table interpolated as [`super::cie::cmf`] does), 1 for a constant 1.
    pub fn luminance(&self) -> f64 {
        let (mut sy, mut y) = (0.0, 0.0);
        for (i, &v) in self.values.iter().enumerate() {
            let ybar = cie::cmf((LAMBDA_MIN as f64) + i as f64)[1];
            sy += v as f64 * ybar;
            y += ybar;
        }
        sy / y
    }
}

/// A constant given as a spectrum: the RGB reduction RGB mode renders with (what lancer stored
/// before spectra were carried as spectra, so RGB renders keep their bits) and the table
/// spectral mode samples. Tables are shared by every scene of the process ([`intern`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// The reduction to linear sRGB by the rule of what the constant describes.
    pub rgb: Rgb,
    /// The spectrum, ready to sample: an albedo clamped to [0, 1], an unbounded quantity to
    /// ≥ 0; an illuminant scaled to the luminance of `rgb`.
    pub spectrum: &'static DenseSpectrum,
}

impl Measured {
    /// The constant `s` whose reduction as `kind` is `rgb`, its table made ready for what it
    /// describes: an albedo clamped to [0, 1] (pbrt-v4 clamps reflectances), an unbounded
    /// quantity to ≥ 0, an illuminant scaled so that the film sees the luminance of `rgb`
    /// (pbrt-v4 divides a light's scale by its spectrum's luminance, see
    /// [`PreparedSpectrum::light`]).
    pub fn new(s: &Spectrum, rgb: Rgb, kind: SpectrumKind) -> Measured {
        Measured::from_table(DenseSpectrum::from_spectrum(s), rgb, kind)
    }

    /// [`Measured::new`] of a spectrum already tabulated.
    pub fn from_table(table: DenseSpectrum, rgb: Rgb, kind: SpectrumKind) -> Measured {
        let table = match kind {
            SpectrumKind::Albedo => table.map(|v| v.clamp(0.0, 1.0)),
            SpectrumKind::Unbounded => table.map(|v| v.max(0.0)),
            SpectrumKind::Illuminant => {
                let y = table.luminance();
                let k = if y > 0.0 {
                    (crate::math::luminance(rgb) as f64 / y) as f32
                } else {
                    0.0
                };
                table.map(|v| (v * k).max(0.0))
            }
        };
        Measured {
            rgb,
            spectrum: intern(table),
        }
    }
}

/// A table stored for the rest of the process, shared with any equal table stored before
/// (scenes name the same few spectra again and again, so the store stays small).
pub fn intern(s: DenseSpectrum) -> &'static DenseSpectrum {
    static STORE: OnceLock<Mutex<Vec<&'static DenseSpectrum>>> = OnceLock::new();
    let mut store = STORE
        .get_or_init(Default::default)
        .lock()
        .unwrap_or_else(|e| e.into_inner());
    if let Some(&t) = store.iter().find(|t| ***t == s) {
        return t;
    }
    let t: &'static DenseSpectrum = Box::leak(Box::new(s));
    store.push(t);
    t
}

/// A constant colour made ready for spectral mode at scene preparation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PreparedSpectrum {
    /// An RGB colour, uplifted.
    Rgb(RgbSpectrum),
    /// A spectrum given as a spectrum, times a factor (1 for material constants; for a light,
    /// its colour's luminance over that of the table's reduction).
    Dense {
        /// The factor.
        scale: f32,
        /// The table.
        spectrum: &'static DenseSpectrum,
    },
}

impl PreparedSpectrum {
    /// Nothing: black.
    pub const BLACK: PreparedSpectrum = PreparedSpectrum::Rgb(RgbSpectrum {
        scale: 0.0,
        s: super::uplift::SigmoidSpectrum::Constant(0.0),
    });

    /// The light colour `colour` (a multiple s·m.rgb of a measured constant's reduction) as
    /// s·table: s = luminance(colour) / luminance(m.rgb), 0 when the reduction is black.
    pub fn light(colour: Rgb, m: &Measured) -> PreparedSpectrum {
        let y = crate::math::luminance(m.rgb);
        PreparedSpectrum::Dense {
            scale: if y > 0.0 {
                crate::math::luminance(colour) / y
            } else {
                0.0
            },
            spectrum: m.spectrum,
        }
    }
}

impl SampledWavelengths {
    /// A prepared constant at the four wavelengths: [`SampledWavelengths::sample`] of an
    /// uplifted colour, the table's values times its factor otherwise.
    #[inline]
    pub fn sample_prepared(&self, p: &PreparedSpectrum) -> SampledSpectrum {
        match p {
            PreparedSpectrum::Rgb(sp) => self.sample(sp),
            PreparedSpectrum::Dense { scale, spectrum } => spectrum.sample(self) * *scale,
        }
    }

    /// A prepared light colour as emission: [`SampledWavelengths::sample_illuminant`] of an
    /// uplifted colour (which multiplies by D65); a table is already the emitted spectrum.
    #[inline]
    pub fn sample_prepared_illuminant(&self, p: &PreparedSpectrum) -> SampledSpectrum {
        match p {
            PreparedSpectrum::Rgb(sp) => self.sample_illuminant(sp),
            PreparedSpectrum::Dense { scale, spectrum } => spectrum.sample(self) * *scale,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_interpolates_between_nanometres() {
        let d = DenseSpectrum::from_fn(|l| 2.0 * l);
        assert_eq!(d.at(360.0), 720.0);
        assert_eq!(d.at(830.0), 1660.0);
        assert!((d.at(500.25) - 1000.5).abs() < 1e-3);
        // Outside the range: the end values.
        assert_eq!(d.at(300.0), 720.0);
        assert_eq!(d.at(900.0), 1660.0);
        assert!(!d.is_constant() && DenseSpectrum::from_fn(|_| 1.5).is_constant());
    }

    #[test]
    fn a_constant_one_has_luminance_one() {
        let y = DenseSpectrum::from_fn(|_| 1.0).luminance();
        assert!((y - 1.0).abs() < 1e-12, "{y}");
    }

    #[test]
    fn equal_tables_are_stored_once() {
        let a = intern(DenseSpectrum::from_fn(|l| l * 0.25 + 1.0));
        let b = intern(DenseSpectrum::from_fn(|l| l * 0.25 + 1.0));
        let c = intern(DenseSpectrum::from_fn(|l| l * 0.5));
        assert!(std::ptr::eq(a, b) && !std::ptr::eq(a, c));
    }

    #[test]
    fn a_light_scales_its_table_by_its_colours_luminance() {
        let m = Measured {
            rgb: Rgb::new(1.2, 1.0, 0.5),
            spectrum: intern(DenseSpectrum::from_fn(|_| 3.0)),
        };
        let p = PreparedSpectrum::light(m.rgb * 4.0, &m);
        let w = SampledWavelengths::sample_visible(0.3);
        let v = w.sample_prepared_illuminant(&p);
        assert!(
            (v - SampledSpectrum::splat(12.0)).abs().max_element() < 1e-5,
            "{v}"
        );
    }
}
