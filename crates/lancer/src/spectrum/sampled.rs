//! Spectral rendering's wavelength samples: which wavelengths a camera path carries, how the
//! scene's RGB colours become values at them, and how the path's radiance becomes film RGB.
//!
//! In spectral mode (`lancer render --spectral`) each camera sample draws four wavelengths
//! λ₀…λ₃ (pbrt-v4's `NSpectrumSamples`), and the four lanes of every [`SampledSpectrum`] in
//! light transport hold the values at those wavelengths; in RGB mode the same lanes hold
//! (r, g, b, b), so both modes run the same code at the same cost. Only the colours that enter
//! transport (material parameters, emission) are converted, by [`SampledWavelengths::albedo`],
//! [`SampledWavelengths::unbounded`] and [`SampledWavelengths::illuminant`] (or, in RGB mode,
//! [`rgb_lanes`]), and the radiance that leaves it, by [`SampledWavelengths::to_film_rgb`] (or
//! [`lanes_rgb`]).
//!
//! Conventions are pbrt-v4's: wavelengths follow its visible-wavelength density, RGB colours are
//! uplifted by the Jakob–Hanika method ([`super::uplift`]), illuminants are the uplift times
//! D65, and the film integrates against the CIE 1931 functions. Constants given as spectra
//! (blackbody, named spectra, `.spd` files) are not uplifted: they come as tables
//! ([`super::dense`]) sampled at the path's wavelengths. A dielectric whose index varies
//! disperses: its index is taken at the hero wavelength
//! and the path keeps only that wavelength from then on ([`super::hero`]).

use super::cie::{self, INTEGRATION_RANGE};
use super::reduce::weights;
use super::uplift::{SigmoidSpectrum, albedo_spectrum, unbounded_spectrum};
use crate::math::{Rgb, SampledSpectrum, lanes_rgb, rgb_lanes};
use std::sync::OnceLock;

/// Where the sigmoid's argument is clamped in [`SampledWavelengths::eval`]: s(±10¹⁸) is 1 or 0
/// in f32, as s(±∞).
const SIGMOID_X_MAX: f32 = 1e18;

/// Shortest wavelength sampled (nm).
pub const LAMBDA_MIN: f32 = 360.0;
/// Longest wavelength sampled (nm).
pub const LAMBDA_MAX: f32 = 830.0;

/// Parameters of pbrt-v4's visible-wavelength density p(λ) ∝ 1/cosh²(A(λ − C)) on
/// [360, 830] nm.
const VIS_A: f64 = 0.0072;
const VIS_C: f64 = 538.0;

/// Samples pbrt-v4's visible-wavelength density by inverting its CDF:
/// λ = C + atanh(T_MIN + u·(T_MAX − T_MIN))/A.
pub fn sample_visible_wavelength(u: f32) -> f32 {
    // The density's CDF is (tanh(A(λ − C)) − t₀)/(t₁ − t₀), tᵢ = tanh at the range's ends.
    let n = norms();
    let (t0, t1) = (n.vis_t0, n.vis_t1);
    let x = (t0 + u.clamp(0.0, 1.0) * (t1 - t0)).clamp(t0, t1);
    (VIS_C as f32 + x.atanh() * (1.0 / VIS_A as f32)).clamp(LAMBDA_MIN, LAMBDA_MAX)
}

/// The density of [`sample_visible_wavelength`] at `lambda` (per nm):
/// p(λ) = A / ((T_MAX − T_MIN) · cosh²(A(λ − C))) on [360, 830], zero outside.
pub fn visible_wavelength_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let n = norms();
    let c = (VIS_A as f32 * (lambda - VIS_C as f32)).cosh();
    n.vis_pdf_scale / (c * c)
}

/// Slots of [`Norms::nodes`]: a power of two above the tables' 94 intervals, so that an index
/// masked to 7 bits is always in bounds (the slots past the last interval are never used).
const NODE_SLOTS: usize = 128;

/// 1.5·2²³: adding it to a float v ∈ [−2²², 2²²] rounds v to an integer n, held in the low
/// mantissa bits of the sum (which is exactly 1.5·2²³ + n).
const ROUND_MAGIC: f32 = 12_582_912.0;

/// Normalising constants of the conversions, computed once.
struct Norms {
    /// tanh(A(360 − C)) and tanh(A(830 − C)).
    vis_t0: f32,
    vis_t1: f32,
    /// A / (T_MAX − T_MIN), the visible density's numerator.
    vis_pdf_scale: f32,
    /// Per 5 nm interval i of the CIE tables (x = (λ − 360)/5 ∈ [i, i + 1]): the row at its
    /// start and the step to the next row, in f32. A row is (r̄, ḡ, b̄, k·D65): the sRGB matching
    /// functions (r̄, ḡ, b̄) = M_XYZ→sRGB · (x̄, ȳ, z̄) / (4 Σȳ) (the film's whole conversion,
    /// so that it is one weighted sum of rows) and k·D65 = D65 · Σȳ / Σ D65·ȳ (the illuminant
    /// of RGB white). A camera sample looks each wavelength up once, as one 4-lane linear
    /// interpolation.
    nodes: [[SampledSpectrum; 2]; NODE_SLOTS],
}

impl Norms {
    /// The rows at four wavelengths λ ∈ [360, 830] nm, interpolated linearly between the
    /// tables' nodes: x = (λ − 360)/5 ∈ [0, 94], i an integer in [0, 93] with
    /// f = x − i ∈ [0, 1], row = rᵢ + f·(rᵢ₊₁ − rᵢ).
    ///
    /// i = round(min(x − ½, 92.75)) (within ½ of x − ½, so f ∈ [0, 1]; at most 93), rounded and
    /// read out of the float's bits by [`ROUND_MAGIC`]: four lanes at once, with neither a
    /// float-to-integer conversion nor a bounds check per wavelength.
    #[inline]
    fn rows_at(&self, lambda: SampledSpectrum) -> [SampledSpectrum; 4] {
        let x = ((lambda - SampledSpectrum::splat(LAMBDA_MIN)) * (1.0 / cie::LAMBDA_STEP as f32))
            .clamp(
                SampledSpectrum::ZERO,
                SampledSpectrum::splat((cie::SAMPLES - 1) as f32),
            );
        let magic = SampledSpectrum::splat(ROUND_MAGIC);
        let y = (x - 0.5).min(SampledSpectrum::splat(cie::SAMPLES as f32 - 2.25)) + magic;
        let f = x - (y - magic);
        let i = y
            .to_array()
            .map(|v| (v.to_bits() & (NODE_SLOTS as u32 - 1)) as usize);
        std::array::from_fn(|k| {
            let [a, d] = self.nodes[i[k]];
            a + f[k] * d
        })
    }
}

fn norms() -> &'static Norms {
    static NORMS: OnceLock<Norms> = OnceLock::new();
    NORMS.get_or_init(|| {
        let w = weights();
        let y_integral: f64 = w.cmf.iter().map(|c| c[1]).sum();
        debug_assert_eq!(w.cmf.len(), INTEGRATION_RANGE.count());
        let vis_t0 = (VIS_A * (LAMBDA_MIN as f64 - VIS_C)).tanh();
        let vis_t1 = (VIS_A * (LAMBDA_MAX as f64 - VIS_C)).tanh();
        let rows: [SampledSpectrum; cie::SAMPLES] = std::array::from_fn(|i| {
            let s = 1.0 / (N_SPECTRUM_SAMPLES as f64 * y_integral);
            let [r, g, b] = cie::xyz_to_srgb(cie::CMF_1931[i].map(|c| c * s));
            // Σ ȳ / Σ D65·ȳ scales D65 so that an illuminant RGB (1, 1, 1) has luminance 1.
            let d = cie::D65[i] * (y_integral / w.d65_y);
            SampledSpectrum::new(r as f32, g as f32, b as f32, d as f32)
        });
        Norms {
            vis_t0: vis_t0 as f32,
            vis_t1: vis_t1 as f32,
            vis_pdf_scale: (VIS_A / (vis_t1 - vis_t0)) as f32,
            nodes: std::array::from_fn(|i| {
                let i = i.min(cie::SAMPLES - 2);
                [rows[i], rows[i + 1] - rows[i]]
            }),
        }
    })
}

/// How many wavelengths a camera path carries, as pbrt-v4's `NSpectrumSamples`: one per lane of
/// [`SampledSpectrum`].
pub const N_SPECTRUM_SAMPLES: usize = 4;

/// The four wavelengths a camera path carries and their densities, one per lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampledWavelengths {
    /// Wavelengths in nm.
    pub lambda: glam::Vec4,
    /// Density of each, per nm (each is drawn from the same density, stratified).
    pub pdf: glam::Vec4,
    /// D65(λᵢ) · Σȳ / Σ D65·ȳ, the illuminant of RGB white at each wavelength (looked up once
    /// per camera sample rather than at each light sample).
    d65: SampledSpectrum,
    /// Per wavelength λᵢ, (r̄, ḡ, b̄)(λᵢ) / (4 Σȳ) (the sRGB matching functions, see
    /// [`Norms::nodes`]) and k·D65(λᵢ), looked up once per camera sample so that
    /// [`SampledWavelengths::to_film_rgb`] is one weighted sum of four rows.
    film: [SampledSpectrum; N_SPECTRUM_SAMPLES],
}

/// atanh of four lanes at once, each in (−1, 1): atanh(x) = ½ ln((1 + x)/(1 − x)), the
/// logarithm from [`ln_lanes`] (replaces four scalar `log1p` calls per camera sample).
fn atanh_lanes(x: SampledSpectrum) -> SampledSpectrum {
    0.5 * ln_lanes((SampledSpectrum::ONE + x) / (SampledSpectrum::ONE - x))
}

/// Natural logarithm of four positive, finite, normal lanes at once: y = 2ᵉ·m with
/// m ∈ [√½, √2), ln y = e·ln 2 + ln m, and with s = (m − 1)/(m + 1),
/// ln m = 2·(s + s³/3 + s⁵/5 + s⁷/7 + s⁹/9) (|s| ≤ 0.172, so the next term, 2s¹¹/11 < 4·10⁻⁹,
/// is below f32 resolution).
fn ln_lanes(y: SampledSpectrum) -> SampledSpectrum {
    let bits = y.to_array().map(f32::to_bits);
    // Exponent and mantissa in [1, 2) from the IEEE-754 fields.
    let e = SampledSpectrum::from_array(bits.map(|b| ((b >> 23) & 0xff) as f32 - 127.0));
    let m =
        SampledSpectrum::from_array(bits.map(|b| f32::from_bits((b & 0x007f_ffff) | 0x3f80_0000)));
    let big = m.cmpgt(SampledSpectrum::splat(std::f32::consts::SQRT_2));
    let m = SampledSpectrum::select(big, m * 0.5, m);
    let e = SampledSpectrum::select(big, e + 1.0, e);
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let poly = SampledSpectrum::ONE
        + s2 * (1.0 / 3.0 + s2 * (1.0 / 5.0 + s2 * (1.0 / 7.0 + s2 * (1.0 / 9.0))));
    e * std::f32::consts::LN_2 + 2.0 * s * poly
}

impl SampledWavelengths {
    /// Four wavelengths from one uniform number: λᵢ from uᵢ = (u + i/4) mod 1 through
    /// [`sample_visible_wavelength`], each with its own density p(λᵢ), all four lanes at once.
    ///
    /// The density comes from the same tanh as the sample, without a cosh: with
    /// x = tanh(A(λ − C)) = T_MIN + u·(T_MAX − T_MIN), 1/cosh²(A(λ − C)) = 1 − x², so
    /// p(λ) = A·(1 − x²)/(T_MAX − T_MIN).
    pub fn sample_visible(u: f32) -> SampledWavelengths {
        let n = norms();
        let (t0, t1) = (n.vis_t0, n.vis_t1);
        let mut ui = SampledSpectrum::splat(u) + SampledSpectrum::new(0.0, 0.25, 0.5, 0.75);
        ui = SampledSpectrum::select(ui.cmpge(SampledSpectrum::ONE), ui - 1.0, ui);
        let x = (t0 + ui.clamp(SampledSpectrum::ZERO, SampledSpectrum::ONE) * (t1 - t0))
            .clamp(SampledSpectrum::splat(t0), SampledSpectrum::splat(t1));
        let lambda = (VIS_C as f32 + atanh_lanes(x) * (1.0 / VIS_A as f32)).clamp(
            SampledSpectrum::splat(LAMBDA_MIN),
            SampledSpectrum::splat(LAMBDA_MAX),
        );
        let pdf = n.vis_pdf_scale * (SampledSpectrum::ONE - x * x);
        Self::at(n, lambda, pdf)
    }

    /// Four wavelengths spread evenly over [lambda_min, lambda_max] from one uniform
    /// number, as pbrt-v4's `SampleUniform` (the `spectral` film's wavelengths):
    /// λ₀ = lerp(u, min, max), λᵢ = λᵢ₋₁ + (max − min)/4 wrapped back into the range, each of
    /// density 1/(max − min).
    pub fn sample_uniform(u: f32, lambda_min: f32, lambda_max: f32) -> SampledWavelengths {
        let span = lambda_max - lambda_min;
        let mut l = [0.0f32; N_SPECTRUM_SAMPLES];
        l[0] = crate::math::lerp(u, lambda_min, lambda_max);
        for i in 1..N_SPECTRUM_SAMPLES {
            l[i] = l[i - 1] + span / N_SPECTRUM_SAMPLES as f32;
            if l[i] > lambda_max {
                l[i] = lambda_min + (l[i] - lambda_max);
            }
        }
        Self::at(
            norms(),
            SampledSpectrum::from_array(l),
            SampledSpectrum::splat(1.0 / span),
        )
    }

    /// The wavelengths `lambda` (in [360, 830] nm) with densities `pdf`, and their table rows.
    #[inline]
    fn at(n: &Norms, lambda: SampledSpectrum, pdf: SampledSpectrum) -> SampledWavelengths {
        // One row (r̄, ḡ, b̄, k·D65) per wavelength from the f32 table; the illuminant's lane of
        // each gathered into one value per wavelength.
        let film = n.rows_at(lambda);
        SampledWavelengths {
            lambda,
            pdf,
            d65: SampledSpectrum::new(film[0].w, film[1].w, film[2].w, film[3].w),
            film,
        }
    }

    /// The sigmoid spectrum at the four wavelengths, lane-wise:
    /// t = (λ − 360)/470, x = (c₀t + c₁)t + c₂, s = ½ + x / (2√(1 + x²)) (1 or 0 where x = ±∞,
    /// and where |x| ≥ 10¹⁸).
    #[inline]
    pub fn eval(&self, s: &SigmoidSpectrum) -> SampledSpectrum {
        match *s {
            SigmoidSpectrum::Constant(v) => SampledSpectrum::splat(v),
            SigmoidSpectrum::Poly([c0, c1, c2]) => {
                let t = (self.lambda - SampledSpectrum::splat(LAMBDA_MIN))
                    * (1.0 / (LAMBDA_MAX - LAMBDA_MIN));
                // x clamped to ±10¹⁸: x² stays finite (below 3.4·10³⁸), and there
                // x/(2√(1 + x²)) is ±½ exactly, so s is 1 or 0 as at x = ±∞.
                let x = ((c0 * t + SampledSpectrum::splat(c1)) * t + SampledSpectrum::splat(c2))
                    .clamp(
                        SampledSpectrum::splat(-SIGMOID_X_MAX),
                        SampledSpectrum::splat(SIGMOID_X_MAX),
                    );
                SampledSpectrum::splat(0.5)
                    + x / (2.0 * (SampledSpectrum::ONE + x * x).map(f32::sqrt))
            }
        }
    }

    /// A reflectance (clamped to [0, 1]) at the four wavelengths, as pbrt-v4's
    /// `RGBAlbedoSpectrum`.
    pub fn albedo(&self, rgb: Rgb) -> SampledSpectrum {
        self.eval(&albedo_spectrum(rgb))
    }

    /// An unbounded quantity (an index of refraction; negatives clamped to 0) at the four
    /// wavelengths, as pbrt-v4's `RGBUnboundedSpectrum`: 2m · s(λ), m the largest component.
    pub fn unbounded(&self, rgb: Rgb) -> SampledSpectrum {
        let (scale, s) = unbounded_spectrum(rgb);
        if scale == 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.eval(&s) * scale
    }

    /// Emitted radiance of RGB colour `rgb` at the four wavelengths, as pbrt-v4's
    /// `RGBIlluminantSpectrum` with its light normalisation:
    /// L(λ) = 2m · s(λ) · D65(λ) · Σȳ / Σ D65·ȳ, so that (1, 1, 1) gives film luminance 1 and
    /// every colour comes back as itself through [`SampledWavelengths::to_film_rgb`] (on
    /// average over wavelengths).
    pub fn illuminant(&self, rgb: Rgb) -> SampledSpectrum {
        let (scale, s) = unbounded_spectrum(rgb);
        if scale == 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.eval(&s) * self.d65 * scale
    }

    /// The film colour of radiance `l` (its lanes the values at the four wavelengths):
    /// the Monte Carlo estimate XYZ = (1/4) Σᵢ (x̄, ȳ, z̄)(λᵢ) · L(λᵢ)/p(λᵢ) / ∫ȳ, in linear
    /// sRGB, M_XYZ→sRGB · XYZ = Σᵢ (r̄, ḡ, b̄)(λᵢ)/(4∫ȳ) · L(λᵢ)/p(λᵢ) with the rows looked up
    /// at sampling. Wavelengths of zero density contribute nothing.
    #[inline]
    pub fn to_film_rgb(&self, l: SampledSpectrum) -> Rgb {
        // wᵢ = L(λᵢ)/p(λᵢ), zero where the density is.
        let live = self.pdf.cmpgt(SampledSpectrum::ZERO);
        let w = SampledSpectrum::select(live, l / self.pdf, SampledSpectrum::ZERO);
        let [r0, r1, r2, r3] = self.film;
        // Lane 3 sums k·D65 and is dropped.
        Rgb::from_vec4((r0 * w.x + r1 * w.y) + (r2 * w.z + r3 * w.w))
    }
}

/// What an RGB colour describes, which decides its spectrum ([`RgbSpectrum::new`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourKind {
    /// A reflectance in [0, 1] (pbrt-v4's `RGBAlbedoSpectrum`).
    Albedo,
    /// An unbounded quantity such as an index of refraction, or emission before D65 is
    /// applied (pbrt-v4's `RGBUnboundedSpectrum`).
    Unbounded,
}

/// An RGB colour turned into a spectrum once, at scene preparation, so that spectral mode
/// only evaluates it at each path's wavelengths: `scale · s(λ)`, s a sigmoid spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbSpectrum {
    /// 1 for an albedo; 2m (m the largest component) for an unbounded colour; 0 for black.
    pub scale: f32,
    /// The sigmoid spectrum.
    pub s: SigmoidSpectrum,
}

impl RgbSpectrum {
    /// The spectrum of `rgb` taken as `kind`: an albedo is clamped to [0, 1] and uplifted
    /// (scale 1); an unbounded colour is 2m · s(λ), s the albedo spectrum of rgb / 2m.
    pub fn new(rgb: Rgb, kind: ColourKind) -> RgbSpectrum {
        match kind {
            ColourKind::Albedo => RgbSpectrum {
                scale: 1.0,
                s: albedo_spectrum(rgb),
            },
            ColourKind::Unbounded => {
                let (scale, s) = unbounded_spectrum(rgb);
                RgbSpectrum { scale, s }
            }
        }
    }
}

impl SampledWavelengths {
    /// A prepared spectrum at the four wavelengths: scale · s(λᵢ) (exactly
    /// [`SampledWavelengths::albedo`] or [`SampledWavelengths::unbounded`] of its colour).
    #[inline]
    pub fn sample(&self, sp: &RgbSpectrum) -> SampledSpectrum {
        if sp.scale == 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.eval(&sp.s) * sp.scale
    }

    /// A prepared unbounded spectrum as emission: scale · s(λ) · D65(λ) · Σȳ / Σ D65·ȳ
    /// (exactly [`SampledWavelengths::illuminant`] of its colour).
    #[inline]
    pub fn sample_illuminant(&self, sp: &RgbSpectrum) -> SampledSpectrum {
        if sp.scale == 0.0 {
            return SampledSpectrum::ZERO;
        }
        self.eval(&sp.s) * self.d65 * sp.scale
    }
}

/// [`SampledWavelengths::albedo`] in spectral mode, the colour's lanes (r, g, b, b) in RGB mode.
#[inline]
pub fn albedo_at(lambda: Option<&SampledWavelengths>, rgb: Rgb) -> SampledSpectrum {
    lambda.map_or(rgb_lanes(rgb), |w| w.albedo(rgb))
}

/// [`SampledWavelengths::unbounded`] in spectral mode, the colour's lanes in RGB mode.
#[inline]
pub fn unbounded_at(lambda: Option<&SampledWavelengths>, rgb: Rgb) -> SampledSpectrum {
    lambda.map_or(rgb_lanes(rgb), |w| w.unbounded(rgb))
}

/// [`SampledWavelengths::illuminant`] in spectral mode, the colour's lanes in RGB mode.
#[inline]
pub fn illuminant_at(lambda: Option<&SampledWavelengths>, rgb: Rgb) -> SampledSpectrum {
    lambda.map_or(rgb_lanes(rgb), |w| w.illuminant(rgb))
}

/// The film colour of a path's radiance: [`SampledWavelengths::to_film_rgb`] in spectral mode,
/// the lanes' RGB (the first three of (r, g, b, b)) in RGB mode.
#[inline]
pub fn film_rgb(lambda: Option<&SampledWavelengths>, l: SampledSpectrum) -> Rgb {
    lambda.map_or(lanes_rgb(l), |w| w.to_film_rgb(l))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{cie_d65, cie_xyz};

    /// Average film colour of `f(wavelengths)` over `n` stratified wavelength samples.
    fn film_average(n: u32, f: impl Fn(&SampledWavelengths) -> SampledSpectrum) -> Rgb {
        let mut sum = glam::DVec3::ZERO;
        for j in 0..n {
            let w = SampledWavelengths::sample_visible((j as f32 + 0.5) / n as f32);
            sum += w.to_film_rgb(f(&w)).as_dvec3();
        }
        (sum / n as f64).as_vec3a()
    }

    #[test]
    fn wavelength_density_is_normalised_and_matches_the_sampling() {
        // ∫ p(λ) dλ = 1 over 360–830 nm (midpoint rule, 0.1 nm).
        let integral: f64 = (0..4700)
            .map(|i| visible_wavelength_pdf(360.05 + 0.1 * i as f32) as f64 * 0.1)
            .sum();
        assert!((integral - 1.0).abs() < 1e-4, "{integral}");
        // pbrt-v4's constant: p(538) = 0.0039398042.
        assert!((visible_wavelength_pdf(538.0) - 0.003_939_804).abs() < 1e-8);
        assert_eq!(visible_wavelength_pdf(359.0), 0.0);
        // Inverse CDF: the mass below sample(u) is u.
        for u in [0.0f32, 0.1, 0.37, 0.5, 0.8, 0.999] {
            let l = sample_visible_wavelength(u);
            let n = ((l - 360.0) / 0.01) as usize;
            let mass: f64 = (0..n)
                .map(|i| visible_wavelength_pdf(360.005 + 0.01 * i as f32) as f64 * 0.01)
                .sum();
            assert!((mass - u as f64).abs() < 2e-3, "u {u}: λ {l}, mass {mass}");
        }
        assert_eq!(sample_visible_wavelength(0.0), 360.0);
        assert_eq!(sample_visible_wavelength(1.0), 830.0);
        // Four wavelengths spread a quarter of the CDF apart: u = 0.9, 0.15, 0.4, 0.65.
        let w = SampledWavelengths::sample_visible(0.9);
        for (i, u) in [(0, 0.9f32), (1, 0.15), (2, 0.4), (3, 0.65)] {
            assert!((w.lambda[i] - sample_visible_wavelength(u)).abs() < 1e-3);
            // The density from 1 − tanh² is the density from cosh², to rounding.
            let p = visible_wavelength_pdf(w.lambda[i]);
            assert!((w.pdf[i] - p).abs() < 1e-5 * p, "{} vs {p}", w.pdf[i]);
        }
    }

    #[test]
    fn lane_wise_atanh_matches_the_scalar_one() {
        // ln of exact powers of two and of e, then atanh over the range the sampling uses.
        let y = SampledSpectrum::new(1.0, 8.0, 0.25, std::f32::consts::E);
        let ln = ln_lanes(y);
        let want = [
            0.0,
            3.0 * std::f32::consts::LN_2,
            -2.0 * std::f32::consts::LN_2,
            1.0,
        ];
        for i in 0..4 {
            assert!(
                (ln[i] - want[i]).abs() < 2e-7,
                "ln {}: {} vs {}",
                y[i],
                ln[i],
                want[i]
            );
        }
        for k in 0..=1000 {
            let x = -0.86 + 1.83 * k as f32 / 1000.0;
            let got = atanh_lanes(SampledSpectrum::splat(x))[0];
            let want = (x as f64).atanh();
            assert!(
                (got as f64 - want).abs() < 1e-6 * (1.0 + want.abs()),
                "atanh {x}: {got}"
            );
        }
    }

    #[test]
    fn f32_rows_interpolate_the_cie_tables() {
        // Every node, every midpoint, both ends and points just off the nodes, against the f64
        // tables: (r̄, ḡ, b̄) = M_XYZ→sRGB · (x̄, ȳ, z̄) / (4 Σȳ) and D65 · Σȳ / Σ D65·ȳ.
        let n = norms();
        let y_integral: f64 = weights().cmf.iter().map(|c| c[1]).sum();
        let k = (y_integral / weights().d65_y) as f32;
        let mut lambdas: Vec<f32> = (0..cie::SAMPLES)
            .flat_map(|i| {
                let l = 360.0 + 5.0 * i as f32;
                [l, l + 2.5, l + 0.001, l - 0.001]
            })
            .filter(|l| (360.0..=830.0).contains(l))
            .collect();
        lambdas.extend([362.5, 557.3, 701.9, 829.99]);
        for l in lambdas {
            // Four wavelengths at once, each in its own lane.
            let r = n.rows_at(SampledSpectrum::new(l, 560.0, l, 360.0));
            assert_eq!(r[0], r[2]);
            let c = cie_xyz(l).map(|v| v as f64 / (4.0 * y_integral));
            let want = cie::xyz_to_srgb(c);
            for j in 0..3 {
                assert!(
                    (r[0][j] as f64 - want[j]).abs() < 1e-8,
                    "{l} nm [{j}]: {} vs {want:?}",
                    r[0]
                );
            }
            let d = cie_d65(l) * k;
            assert!(
                (r[0][3] - d).abs() < 1e-5 * d,
                "{l} nm: D65 {} vs {d}",
                r[0][3]
            );
        }
        // A node: 560 nm, (x̄, ȳ, z̄) = (0.5945, 0.995, 0.0039), D65 = 100.
        let want = cie::xyz_to_srgb([0.5945, 0.995, 0.0039].map(|v| v / (4.0 * y_integral)));
        let r = n.rows_at(SampledSpectrum::splat(560.0))[1];
        for j in 0..3 {
            assert!((r[j] as f64 - want[j]).abs() < 1e-9, "{r} vs {want:?}");
        }
        assert!((r[3] - 100.0 * k).abs() < 1e-5 * r[3]);
    }

    #[test]
    fn film_rgb_is_the_f64_monte_carlo_estimate() {
        // XYZ = (1/4) Σ cmf(λᵢ) L/p / Σȳ, then sRGB, computed here in f64, lane 2 of zero
        // density (and infinite radiance, which it must ignore).
        let mut w = SampledWavelengths::sample_visible(0.61);
        w.pdf[2] = 0.0;
        let l = SampledSpectrum::new(0.7, 2.0, f32::INFINITY, 0.0);
        let mut xyz = [0.0f64; 3];
        for i in [0, 1] {
            let c = cie_xyz(w.lambda[i]);
            for k in 0..3 {
                xyz[k] += c[k] as f64 * l[i] as f64 / w.pdf[i] as f64;
            }
        }
        let y_integral: f64 = weights().cmf.iter().map(|c| c[1]).sum();
        let want = cie::xyz_to_srgb(xyz.map(|v| v / (4.0 * y_integral)));
        let want = Rgb::new(want[0] as f32, want[1] as f32, want[2] as f32);
        let got = w.to_film_rgb(l);
        assert!(
            (got - want).abs().max_element() < 1e-5 * want.abs().max_element(),
            "{got} vs {want}"
        );
    }

    #[test]
    fn lane_wise_sigmoid_is_the_scalar_one_and_saturates() {
        let w = SampledWavelengths::sample_visible(0.37);
        for c in [[-3.2f32, 4.1, -1.7], [10.5, -12.0, 2.0], [0.0, 0.0, 0.3]] {
            let s = SigmoidSpectrum::Poly(c);
            let got = w.eval(&s);
            for i in 0..4 {
                assert_eq!(got[i], s.eval(w.lambda[i]), "{c:?} at {} nm", w.lambda[i]);
            }
        }
        // Beyond ±10¹⁸ and at ±∞ the sigmoid is 1 or 0 exactly.
        for (c2, want) in [
            (1e19f32, 1.0f32),
            (-3e30, 0.0),
            (f32::INFINITY, 1.0),
            (f32::NEG_INFINITY, 0.0),
        ] {
            let got = w.eval(&SigmoidSpectrum::Poly([0.0, 0.0, c2]));
            assert_eq!(got, SampledSpectrum::splat(want), "c₂ = {c2}");
        }
    }

    #[test]
    fn illuminants_come_back_as_their_rgb_through_the_film() {
        for c in [
            Rgb::ONE,
            Rgb::new(17.0, 12.0, 4.0),
            Rgb::new(1.0, 0.2, 0.05),
            Rgb::new(0.1, 0.3, 2.0),
        ] {
            let back = film_average(3000, |w| w.illuminant(c));
            // 1 % of each channel (the wavelength sampling), plus the uplift table's error,
            // 2·10⁻³ of the spectrum's scale 2m.
            let tolerance = c * 0.01 + Rgb::splat(4e-3 * c.max_element());
            assert!(
                (back - c).abs().cmple(tolerance).all(),
                "{c} came back as {back}"
            );
        }
        // White light has luminance 1 per unit (lancer's and pbrt-v4's normalisation).
        let y = crate::math::luminance(film_average(3000, |w| w.illuminant(Rgb::ONE)));
        assert!((y - 1.0).abs() < 3e-3, "{y}");
        assert_eq!(
            SampledWavelengths::sample_visible(0.3).illuminant(Rgb::ZERO),
            SampledSpectrum::ZERO
        );
    }

    #[test]
    fn reflectance_times_white_light_gives_the_reflectance() {
        // A reflectance lit by white light, seen on film: the reflectance's colour under D65.
        for c in [
            Rgb::new(0.8, 0.3, 0.1),
            Rgb::new(0.2, 0.6, 0.9),
            Rgb::splat(0.5),
        ] {
            let back = film_average(3000, |w| w.albedo(c) * w.illuminant(Rgb::ONE));
            assert!(
                (back - c).abs().max_element() < 5e-3,
                "{c} came back as {back}"
            );
        }
        // An albedo and an unbounded value in RGB mode are the colour itself.
        let c = Rgb::new(0.2, 3.0, 0.5);
        let lanes = SampledSpectrum::new(0.2, 3.0, 0.5, 0.5);
        assert_eq!(albedo_at(None, c), lanes);
        assert_eq!(unbounded_at(None, c), lanes);
        assert_eq!(illuminant_at(None, c), lanes);
        assert_eq!(film_rgb(None, lanes), c);
        let w = SampledWavelengths::sample_visible(0.25);
        assert!(w.albedo(Rgb::new(2.0, 0.5, 0.5)).max_element() <= 1.0);
    }
}
