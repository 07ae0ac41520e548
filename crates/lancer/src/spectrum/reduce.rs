//! Spectra as scene files give them ([`Spectrum`]) and their reduction to linear sRGB by what
//! they describe ([`SpectrumKind`]); see the [parent module](super) for the rules.

use std::sync::OnceLock;

use glam::{DMat3, DVec3};

use super::cie;
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
    /// A measured spectrum known only through its RGB reductions, computed offline from the
    /// data (pbrt-v4's named spectra, see [`named_spectrum`](super::named_spectrum)).
    /// [`spectrum_to_rgb`] returns the stored triples; [`Spectrum::eval`] gives a three-band
    /// stand-in whose reduction as [`SpectrumKind::Unbounded`] is the stored `unbounded`
    /// triple.
    Precomputed(PrecomputedRgb),
}

/// The linear-sRGB reductions of a spectrum, computed ahead of time by the rules of
/// [`spectrum_to_rgb`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrecomputedRgb {
    /// Reduction as [`SpectrumKind::Unbounded`] (seen under D65, ≥ 0); as
    /// [`SpectrumKind::Albedo`] it is clamped to [0, 1].
    pub unbounded: Rgb,
    /// Reduction as [`SpectrumKind::Illuminant`] (luminance 1, ≥ 0).
    pub illuminant: Rgb,
}

/// What a spectrum describes, which decides how it becomes RGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumKind {
    /// A reflectance or transmittance in [0, 1], seen under the colour space's white (D65).
    Albedo,
    /// An unbounded quantity such as an index of refraction, seen under D65; kept ≥ 0.
    Unbounded,
    /// Emission: normalised to luminance 1 (pbrt's light normalisation).
    Illuminant,
}

/// Planck's law: emitted radiance of a black body at `lambda_nm` and temperature `t`
/// (W·sr⁻¹·m⁻³); 0 for `t` ≤ 0.
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
            Spectrum::Precomputed(p) => {
                let c = weights().band_inverse * p.unbounded.as_dvec3();
                c[band_of(lambda as f64)] as f32
            }
        }
    }
}

/// CIE 1931 2° colour-matching functions `[x̄, ȳ, z̄]` at `lambda` (nm), interpolated linearly
/// in the 5 nm table; zero outside 360–830 nm.
pub fn cie_xyz(lambda: f32) -> [f32; 3] {
    cie::cmf(lambda as f64).map(|v| v as f32)
}

/// CIE standard illuminant D65 at `lambda` (nm), relative power (100 at 560 nm), interpolated
/// linearly in the 5 nm table; zero outside 360–830 nm.
pub fn cie_d65(lambda: f32) -> f32 {
    cie::d65(lambda as f64) as f32
}

/// CIE XYZ → linear sRGB (D65 white), the standard matrix of IEC 61966-2-1.
pub fn xyz_to_srgb(xyz: [f32; 3]) -> Rgb {
    xyz_to_srgb_f64(DVec3::from(xyz.map(f64::from))).as_vec3a()
}

fn xyz_to_srgb_f64(xyz: DVec3) -> DVec3 {
    DVec3::from(cie::xyz_to_srgb(xyz.to_array()))
}

/// Boundaries (nm) of the three bands of [`Spectrum::Precomputed`]'s stand-in spectrum, between
/// integration wavelengths so that no sample sits on an edge.
const BAND_EDGES: [f64; 2] = [489.5, 589.5];

fn band_of(lambda: f64) -> usize {
    BAND_EDGES.iter().filter(|&&e| lambda >= e).count()
}

/// The integration weights, sampled once.
pub(super) struct Weights {
    /// (x̄, ȳ, z̄) at each integration wavelength.
    pub(super) cmf: Vec<[f64; 3]>,
    /// D65 · (x̄, ȳ, z̄) at each integration wavelength.
    d65_cmf: Vec<[f64; 3]>,
    /// ∑ D65 · ȳ.
    pub(super) d65_y: f64,
    /// Inverse of the matrix whose columns are the reductions (as [`SpectrumKind::Unbounded`])
    /// of the three unit bands: maps a triple to the band heights that reproduce it.
    band_inverse: DMat3,
}

/// The integration weights of the process, computed on first use.
pub(super) fn weights() -> &'static Weights {
    static WEIGHTS: OnceLock<Weights> = OnceLock::new();
    WEIGHTS.get_or_init(|| {
        let lambdas = cie::INTEGRATION_RANGE.map(f64::from);
        let cmf: Vec<[f64; 3]> = lambdas.clone().map(cie::cmf).collect();
        let d65_cmf: Vec<[f64; 3]> = lambdas
            .clone()
            .zip(&cmf)
            .map(|(l, c)| c.map(|v| v * cie::d65(l)))
            .collect();
        let d65_y = d65_cmf.iter().map(|c| c[1]).sum::<f64>();
        let mut bands = [DVec3::ZERO; 3];
        for (l, c) in lambdas.zip(&d65_cmf) {
            bands[band_of(l)] += DVec3::from(*c) / d65_y;
        }
        let band_rgb = bands.map(xyz_to_srgb_f64);
        let band_inverse = DMat3::from_cols(band_rgb[0], band_rgb[1], band_rgb[2]).inverse();
        Weights {
            cmf,
            d65_cmf,
            d65_y,
            band_inverse,
        }
    })
}

/// ∑ s(λ)·w(λ) over the integration wavelengths.
fn integrate(s: &Spectrum, w: &[[f64; 3]]) -> DVec3 {
    cie::INTEGRATION_RANGE
        .zip(w)
        .map(|(l, c)| DVec3::from(*c) * s.eval(l as f32) as f64)
        .sum()
}

/// ∫ s(λ)·(x̄, ȳ, z̄)(λ) dλ over 360–830 nm (1 nm steps, λ in nm). A constant 1 gives
/// Y ≈ 106.857.
pub fn spectrum_to_xyz_unnormalised(s: &Spectrum) -> [f32; 3] {
    integrate(s, &weights().cmf).as_vec3a().to_array()
}

/// Reduces a spectrum to linear sRGB according to what it describes (see the module
/// documentation): illuminants to luminance 1, reflectances and unbounded quantities under D65.
/// Albedos are clamped to [0, 1], everything else to ≥ 0. Constant reflectances and unbounded
/// quantities stay exactly grey.
pub fn spectrum_to_rgb(s: &Spectrum, kind: SpectrumKind) -> Rgb {
    let rgb = match (s, kind) {
        (Spectrum::Constant(c), SpectrumKind::Albedo | SpectrumKind::Unbounded) => Rgb::splat(*c),
        (Spectrum::Precomputed(p), SpectrumKind::Albedo | SpectrumKind::Unbounded) => p.unbounded,
        (Spectrum::Precomputed(p), SpectrumKind::Illuminant) => p.illuminant,
        (_, SpectrumKind::Illuminant) => {
            let xyz = integrate(s, &weights().cmf);
            if xyz.y.is_nan() || xyz.y <= 0.0 {
                return Rgb::ZERO;
            }
            xyz_to_srgb_f64(xyz / xyz.y).as_vec3a()
        }
        (_, SpectrumKind::Albedo | SpectrumKind::Unbounded) => {
            let w = weights();
            xyz_to_srgb_f64(integrate(s, &w.d65_cmf) / w.d65_y).as_vec3a()
        }
    };
    let rgb = rgb.max(Rgb::ZERO);
    match kind {
        SpectrumKind::Albedo => rgb.min(Rgb::ONE),
        SpectrumKind::Unbounded | SpectrumKind::Illuminant => rgb,
    }
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

#[cfg(test)]
mod tests;
