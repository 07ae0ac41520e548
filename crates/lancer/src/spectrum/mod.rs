//! Spectra, converted to RGB once at load time.
//!
//! lancer renders in linear sRGB. Scene files may give colours as spectra (constants,
//! blackbodies, sampled data, pbrt's named measured spectra); they are reduced to RGB here,
//! according to what they describe ([`SpectrumKind`]).
//!
//! NOTE: the colour-matching functions below are the analytic fit of Wyman, Sloan and Shirley
//! (2013); tabulated CIE 1931 data, D65 and pbrt's named spectra are still to come.

use crate::math::Rgb;

/// A spectral distribution over wavelength in nanometres.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// Planck's law at temperature `kelvin`, normalised to a peak of 1.
    Blackbody {
        /// Temperature in kelvin.
        kelvin: f32,
    },
    /// Linear interpolation between samples (λ ascending); zero outside.
    PiecewiseLinear {
        /// Wavelengths, nm, ascending.
        lambda: Vec<f32>,
        /// Values at those wavelengths.
        values: Vec<f32>,
    },
}

/// What a spectrum describes, which decides how it becomes RGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumKind {
    /// A reflectance or transmittance in [0, 1], seen under the colour space's white.
    Albedo,
    /// An unbounded quantity such as an index of refraction.
    Unbounded,
    /// Emission: normalised to luminance 1 (pbrt's light normalisation).
    Illuminant,
}

/// Planck's law: emitted radiance of a black body at `lambda_nm` and temperature `t`.
pub fn blackbody(lambda_nm: f32, t: f32) -> f32 {
    if t <= 0.0 {
        return 0.0;
    }
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_069_57e-34;
    const KB: f64 = 1.380_648_8e-23;
    let l = lambda_nm as f64 * 1e-9;
    let le = (2.0 * H * C * C) / (l.powi(5) * (((H * C) / (l * KB * t as f64)).exp() - 1.0));
    le as f32
}

impl Spectrum {
    /// The value at wavelength `lambda` (nm).
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            Spectrum::Constant(c) => *c,
            Spectrum::Blackbody { kelvin } => {
                // Wien's displacement law gives the peak: λ_max = 2.8977721e-3 m·K / T.
                let lambda_max = 2.897_772e-3 / kelvin * 1e9;
                blackbody(lambda, *kelvin) / blackbody(lambda_max, *kelvin)
            }
            Spectrum::PiecewiseLinear { lambda: ls, values } => {
                if ls.is_empty() || lambda < ls[0] || lambda > ls[ls.len() - 1] {
                    return 0.0;
                }
                let i = ls.partition_point(|&l| l <= lambda).clamp(1, ls.len() - 1) - 1;
                let (l0, l1) = (ls[i], ls[(i + 1).min(ls.len() - 1)]);
                let t = if l1 > l0 {
                    (lambda - l0) / (l1 - l0)
                } else {
                    0.0
                };
                values[i] * (1.0 - t) + values[(i + 1).min(values.len() - 1)] * t
            }
        }
    }
}

fn g(x: f32, mu: f32, s1: f32, s2: f32) -> f32 {
    let t = (x - mu) / if x < mu { s1 } else { s2 };
    (-0.5 * t * t).exp()
}

/// CIE 1931 colour-matching functions x̄, ȳ, z̄ at `lambda` (Wyman, Sloan, Shirley 2013,
/// multi-lobe fit).
pub fn cie_xyz(lambda: f32) -> [f32; 3] {
    [
        1.056 * g(lambda, 599.8, 37.9, 31.0) + 0.362 * g(lambda, 442.0, 16.0, 26.7)
            - 0.065 * g(lambda, 501.1, 20.4, 26.2),
        0.821 * g(lambda, 568.8, 46.9, 40.5) + 0.286 * g(lambda, 530.9, 16.3, 31.1),
        1.217 * g(lambda, 437.0, 11.8, 36.0) + 0.681 * g(lambda, 459.0, 26.0, 13.8),
    ]
}

/// CIE XYZ → linear sRGB (D65 white).
pub fn xyz_to_srgb(xyz: [f32; 3]) -> Rgb {
    let [x, y, z] = xyz;
    Rgb::new(
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266 * x + 1.876_010_8 * y + 0.041_556 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    )
}

/// ∫ s(λ)·(x̄, ȳ, z̄)(λ) dλ over 360–830 nm (1 nm steps).
pub fn spectrum_to_xyz_unnormalised(s: &Spectrum) -> [f32; 3] {
    let mut acc = [0.0f64; 3];
    for l in 360..=830 {
        let v = s.eval(l as f32) as f64;
        let c = cie_xyz(l as f32);
        for k in 0..3 {
            acc[k] += v * c[k] as f64;
        }
    }
    [acc[0] as f32, acc[1] as f32, acc[2] as f32]
}

/// Reduces a spectrum to linear sRGB according to what it describes.
pub fn spectrum_to_rgb(s: &Spectrum, kind: SpectrumKind) -> Rgb {
    if let (Spectrum::Constant(c), SpectrumKind::Albedo | SpectrumKind::Unbounded) = (s, kind) {
        return Rgb::splat(*c);
    }
    let xyz = spectrum_to_xyz_unnormalised(s);
    let white = spectrum_to_xyz_unnormalised(&Spectrum::Constant(1.0));
    match kind {
        SpectrumKind::Illuminant => {
            if xyz[1] <= 0.0 {
                return Rgb::ZERO;
            }
            xyz_to_srgb([xyz[0] / xyz[1], 1.0, xyz[2] / xyz[1]])
        }
        SpectrumKind::Albedo | SpectrumKind::Unbounded => {
            let y = white[1];
            let rgb = xyz_to_srgb([xyz[0] / y, xyz[1] / y, xyz[2] / y]);
            // Chromatic adaptation from illuminant E (equal energy) is still to do; scale so
            // that a constant spectrum stays grey.
            let w = xyz_to_srgb([white[0] / y, 1.0, white[2] / y]);
            rgb / w
        }
    }
}

/// One of pbrt's named spectra (`metal-Au-eta`, `glass-BK7`, `stdillum-D65`, …).
pub fn named_spectrum(_name: &str) -> Option<Spectrum> {
    None
}

/// Parses a spectrum file (pbrt's `.spd`: pairs of wavelength and value, `#` comments).
pub fn parse_spd(text: &str) -> Result<Spectrum, String> {
    let mut nums = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        for tok in line.split_whitespace() {
            let v: f32 = tok
                .parse()
                .map_err(|_| format!("line {}: '{tok}' is not a number", i + 1))?;
            if !v.is_finite() {
                return Err(format!("line {}: '{tok}' is not finite", i + 1));
            }
            nums.push(v);
        }
    }
    if nums.len() < 2 || !nums.len().is_multiple_of(2) {
        return Err(format!(
            "expected pairs of wavelength and value, found {} numbers",
            nums.len()
        ));
    }
    let (lambda, values): (Vec<f32>, Vec<f32>) = nums.chunks(2).map(|p| (p[0], p[1])).unzip();
    if lambda.windows(2).any(|w| w[1] <= w[0]) {
        return Err("wavelengths must increase".to_string());
    }
    Ok(Spectrum::PiecewiseLinear { lambda, values })
}
