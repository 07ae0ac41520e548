//! The Hosek–Wilkie sky model (2012) and the sun's irradiance, as Mitsuba 3's `sunsky` emitter
//! evaluates them (its `include/mitsuba/render/sunsky.h` and `src/emitters/sunsky.cpp`).
//!
//! The sky's radiance towards a direction at angle θ from the zenith and γ from the sun is, per
//! channel (one of 11 wavelengths 320, 360, …, 720 nm, or R, G, B),
//!
//! L(θ, γ) = (1 + A·e^(B/(cos θ + 0.01))) · (C + D·e^(E·γ) + F·cos²γ + G·χ(H, γ) + I·√cos θ) · L_M
//! with χ(H, γ) = (1 + cos²γ) / (1 + H² − 2H·cos γ)^(3/2),
//!
//! whose nine parameters A…I and mean radiance L_M are the published tables (by turbidity
//! 1…10, ground albedo 0 and 1, and six control points of a quintic Bézier curve over the
//! sun's elevation) interpolated as Mitsuba does: linearly in turbidity, then in albedo, then
//! the Bézier curve at x = ∛(elevation / (π/2)).
//!
//! The sun is a uniform disk of half-angle 0.2679° whose radiance is its irradiance (a table
//! by turbidity and elevation 2°, 5°, …, 89°, interpolated linearly in both) divided by the
//! disk's solid angle: Mitsuba's default (`complex_sun` false).
//!
//! The tables are data: the sky's coefficients from Hosek & Wilkie's implementation (v1.4a,
//! <https://cgg.mff.cuni.cz/projects/SkylightModelling/>, as pbrt-v4 carries it under
//! src/ext/skymodel), the sun's irradiance from Mitsuba 3's `data/sunsky/sampling_data.bin`;
//! both under the 3-clause BSD licence (`hosek_wilkie.LICENSE`); `tools/sunsky_data.py` writes
//! `hosek_wilkie.bin` from them.

use crate::math::Rgb;
use crate::spectrum::cie;
use std::sync::OnceLock;

/// The model's wavelengths in nm: 320, 360, …, 720.
pub const WAVELENGTHS: [f32; SPECTRAL_CHANNELS] = [
    320.0, 360.0, 400.0, 440.0, 480.0, 520.0, 560.0, 600.0, 640.0, 680.0, 720.0,
];
/// Number of spectral channels of the tables.
pub const SPECTRAL_CHANNELS: usize = 11;
/// First wavelength and spacing of the spectral channels, in nm.
const LAMBDA_FIRST: f32 = 320.0;
const LAMBDA_STEP: f32 = 40.0;

/// Turbidity levels (1, 2, …, 10), albedo levels (0, 1), Bézier control points, parameters.
const TURBIDITIES: usize = 10;
const ALBEDOS: usize = 2;
const CONTROL_POINTS: usize = 6;
const PARAMS: usize = 9;
/// Solar elevations of the irradiance table: 2°, 5°, …, 89°.
const ELEVATIONS: usize = 30;

/// The sun's half-angle as Mitsuba's (0.5358° across): π·(0.5 · 0.5358)/180 radians.
pub const SUN_HALF_APERTURE: f64 = std::f64::consts::PI * (0.5 * 0.5358) / 180.0;

/// Mitsuba's `MI_CIE_Y_NORMALIZATION`, 1/∫ȳ over its CIE table: its RGB sky is the table's
/// value times it.
const CIE_Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;
/// Mitsuba's `SPEC_TO_RGB_SUN_CONV`, which turns the mean over its 11 wavelengths of the sun's
/// sRGB-weighted irradiance into the RGB sun's.
const SPEC_TO_RGB_SUN_CONV: f64 = 467.069_280_386;
/// Mitsuba's XYZ → linear sRGB matrix (its `xyz_to_srgb`; rounded differently from
/// [`cie::XYZ_TO_SRGB`] in the fifth digit, which would move the RGB sun by 10⁻⁴).
const MITSUBA_XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.240_479, -1.537_150, -0.498_535],
    [-0.969_256, 1.875_991, 0.041_556],
    [0.055_648, -0.204_043, 1.057_311],
];

/// The tables' layout in `hosek_wilkie.bin` (f32 little-endian): offsets and lengths.
const PARAMS_SPEC: (usize, usize) = (0, TURBIDITIES * ALBEDOS * CONTROL_POINTS * 11 * PARAMS);
const RAD_SPEC: (usize, usize) = (
    end(PARAMS_SPEC),
    TURBIDITIES * ALBEDOS * CONTROL_POINTS * 11,
);
const PARAMS_RGB: (usize, usize) = (
    end(RAD_SPEC),
    TURBIDITIES * ALBEDOS * CONTROL_POINTS * 3 * 9,
);
const RAD_RGB: (usize, usize) = (end(PARAMS_RGB), TURBIDITIES * ALBEDOS * CONTROL_POINTS * 3);
const SUN_IRRADIANCE: (usize, usize) = (end(RAD_RGB), TURBIDITIES * ELEVATIONS * 11);
const TABLE_FLOATS: usize = end(SUN_IRRADIANCE);

const fn end(t: (usize, usize)) -> usize {
    t.0 + t.1
}

static TABLE_BYTES: &[u8] = include_bytes!("hosek_wilkie.bin");
const _: () = assert!(TABLE_BYTES.len() == 4 * TABLE_FLOATS);

/// The tables as numbers (decoded once).
fn tables() -> &'static [f32] {
    static TABLES: OnceLock<Vec<f32>> = OnceLock::new();
    TABLES.get_or_init(|| {
        TABLE_BYTES
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect()
    })
}

/// Which of the model's two sets of tables: 11 wavelengths, or linear sRGB.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Basis {
    /// The spectral tables (320, 360, …, 720 nm).
    Spectral,
    /// The RGB tables.
    Rgb,
}

impl Basis {
    /// Number of channels.
    pub fn channels(self) -> usize {
        match self {
            Basis::Spectral => SPECTRAL_CHANNELS,
            Basis::Rgb => 3,
        }
    }
}

/// The sky of one channel for one sun, turbidity and albedo: the parameters A…I and the mean
/// radiance L_M of the formula in the module's documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkyChannel {
    /// A, B, C, D, E, F, G, I, H (the published order: I before H).
    pub params: [f32; PARAMS],
    /// L_M (for the RGB tables already times Mitsuba's CIE Y normalisation).
    pub radiance: f32,
}

/// Linear interpolation along a table axis as Dr.Jit's `take_interp`: the pair (i, i + 1) with
/// i = ⌊x⌋ clamped to [0, n − 2], weighted (1 − w, w) with w = x − i (extrapolating outside).
fn take_interp(x: f32, n: usize) -> (usize, f32) {
    let i = (x.max(0.0) as usize).min(n - 2);
    (i, x - i as f32)
}

/// Weights of the quintic Bézier curve's six control points at the sun's elevation `eta`
/// (radians): x = min(∛(2η/π), 1 − ε), wₖ = C(5, k)·xᵏ·(1 − x)⁵⁻ᵏ.
fn bezier_weights(eta: f32) -> [f32; CONTROL_POINTS] {
    let x = (2.0 * eta / std::f32::consts::PI)
        .cbrt()
        .min(1.0 - f32::EPSILON / 2.0);
    const BINOMIAL: [f32; CONTROL_POINTS] = [1.0, 5.0, 10.0, 10.0, 5.0, 1.0];
    std::array::from_fn(|k| BINOMIAL[k] * x.powi(k as i32) * (1.0 - x).powi(5 - k as i32))
}

/// The sky of `channel` (of `basis`) for turbidity `turbidity` ∈ [1, 10], ground albedo
/// `albedo` ∈ [0, 1] and a sun at elevation `eta` radians above the horizon.
pub fn sky_channel(
    basis: Basis,
    channel: usize,
    turbidity: f32,
    albedo: f32,
    eta: f32,
) -> SkyChannel {
    let t = tables();
    let n = basis.channels();
    let (params, rad) = match basis {
        Basis::Spectral => (PARAMS_SPEC.0, RAD_SPEC.0),
        Basis::Rgb => (PARAMS_RGB.0, RAD_RGB.0),
    };
    let (ti, tw) = take_interp(turbidity - 1.0, TURBIDITIES);
    let bezier = bezier_weights(eta);
    // Turbidity, then albedo, then the curve; `stride` and `k` pick one value of a record.
    let value = |base: usize, stride: usize, k: usize| -> f32 {
        let at = |turb: usize, alb: usize, ctrl: usize| {
            t[base + (((turb * ALBEDOS + alb) * CONTROL_POINTS + ctrl) * n + channel) * stride + k]
        };
        (0..CONTROL_POINTS)
            .map(|c| {
                let a0 = at(ti, 0, c) * (1.0 - tw) + at(ti + 1, 0, c) * tw;
                let a1 = at(ti, 1, c) * (1.0 - tw) + at(ti + 1, 1, c) * tw;
                bezier[c] * (a0 * (1.0 - albedo) + a1 * albedo)
            })
            .sum()
    };
    let norm = match basis {
        Basis::Spectral => 1.0,
        Basis::Rgb => CIE_Y_NORMALIZATION as f32,
    };
    SkyChannel {
        params: std::array::from_fn(|k| value(params, PARAMS, k)),
        radiance: value(rad, 1, 0) * norm,
    }
}

/// The sky's radiance of one channel towards a direction at cos θ = `cos_theta` from the
/// zenith (≥ 0) and angle `gamma` from the sun (the formula in the module's documentation).
#[inline]
pub fn sky_radiance(c: &SkyChannel, cos_theta: f32, gamma: f32, cos_gamma: f32) -> f32 {
    let [a, b, c_, d, e, f, g, i, h] = c.params;
    let cos2_gamma = cos_gamma * cos_gamma;
    let chi = (1.0 + cos2_gamma) / (1.0 + h * h - 2.0 * h * cos_gamma).powf(1.5);
    let c1 = 1.0 + a * (b / (cos_theta + 0.01)).exp();
    let c2 = c_ + d * (e * gamma).exp() + f * cos2_gamma + g * chi + i * cos_theta.max(0.0).sqrt();
    c1 * c2 * c.radiance
}

/// The sun's irradiance at the model's 11 wavelengths (W m⁻² nm⁻¹ on a surface facing it) for
/// turbidity `turbidity` and a sun at elevation `eta` radians: the table at elevations 2°, 5°,
/// …, 89° interpolated linearly in turbidity, then in elevation (clamped to the table).
pub fn sun_irradiance(turbidity: f32, eta: f32) -> [f32; SPECTRAL_CHANNELS] {
    let t = &tables()[SUN_IRRADIANCE.0..end(SUN_IRRADIANCE)];
    let (ti, tw) = take_interp(turbidity - 1.0, TURBIDITIES);
    let e = ((eta.to_degrees() - 2.0) / 3.0).clamp(0.0, ELEVATIONS as f32 - 1.0);
    let (ei, ew) = take_interp(e, ELEVATIONS);
    std::array::from_fn(|w| {
        let at = |turb: usize, elev: usize| t[(turb * ELEVATIONS + elev) * SPECTRAL_CHANNELS + w];
        let lo = at(ti, ei) * (1.0 - tw) + at(ti + 1, ei) * tw;
        let hi = at(ti, ei + 1) * (1.0 - tw) + at(ti + 1, ei + 1) * tw;
        lo * (1.0 - ew) + hi * ew
    })
}

/// The RGB irradiance Mitsuba's RGB mode gives the sun of spectral irradiance `e` (at the
/// model's wavelengths): E_rgb = K · (1/11) Σᵢ M·x̄ȳz̄(λᵢ)·e(λᵢ) / ∫ȳ, K = 467.069 (its
/// `SPEC_TO_RGB_SUN_CONV`), M Mitsuba's XYZ → linear sRGB matrix (320 nm lies outside the CIE table
/// and counts as zero).
pub fn sun_rgb(e: &[f32; SPECTRAL_CHANNELS]) -> Rgb {
    let mut sum = [0.0f64; 3];
    for (lambda, e) in WAVELENGTHS.iter().zip(e) {
        let xyz = cie::cmf(*lambda as f64);
        for (s, m) in sum.iter_mut().zip(MITSUBA_XYZ_TO_SRGB) {
            *s += (m[0] * xyz[0] + m[1] * xyz[1] + m[2] * xyz[2]) * *e as f64;
        }
    }
    let k = SPEC_TO_RGB_SUN_CONV * CIE_Y_NORMALIZATION / SPECTRAL_CHANNELS as f64;
    Rgb::new(
        (sum[0] * k) as f32,
        (sum[1] * k) as f32,
        (sum[2] * k) as f32,
    )
}

/// The two spectral channels around wavelength `lambda` (nm) and the weight of the second:
/// channel i = ⌊(λ − 320)/40⌋, value = (1 − w)·vᵢ + w·vᵢ₊₁; `None` outside [320, 720] nm, where
/// Mitsuba's model gives nothing.
#[inline]
pub fn spectral_channels(lambda: f32) -> Option<(usize, usize, f32)> {
    let x = (lambda - LAMBDA_FIRST) / LAMBDA_STEP;
    if !(0.0..=(SPECTRAL_CHANNELS - 1) as f32).contains(&x) {
        return None;
    }
    let i = (x as usize).min(SPECTRAL_CHANNELS - 1);
    Some((i, (i + 1).min(SPECTRAL_CHANNELS - 1), x - i as f32))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sun and view of the reference scene (sky/sunsky.pbrt), light space: its elevation
    /// η and the (cos θ, γ) of a view direction.
    fn sun() -> (glam::DVec3, f32) {
        let s = glam::DVec3::new(-0.45, 0.6, 0.65).normalize();
        (s, (std::f64::consts::FRAC_PI_2 - s.z.acos()) as f32)
    }

    fn view(basis: Basis, d: [f64; 3]) -> Vec<f32> {
        let (s, eta) = sun();
        let d = glam::DVec3::from(d).normalize();
        let gamma = d.angle_between(s) as f32;
        (0..basis.channels())
            .map(|c| {
                let ch = sky_channel(basis, c, 3.0, 0.3, eta);
                sky_radiance(&ch, d.z as f32, gamma, gamma.cos())
            })
            .collect()
    }

    fn close(a: f32, b: f32, rel: f32) -> bool {
        (a - b).abs() <= rel * b.abs()
    }

    /// The sky against Mitsuba 3.9.1's `sunsky` emitter (`eval` of scalar_rgb and
    /// scalar_spectral, turbidity 3, albedo 0.3, sun (−0.45, 0.6, 0.65)) at three directions:
    /// within 2·10⁻⁶ (float rounding).
    #[test]
    fn sky_is_mitsubas() {
        let cases: [([f64; 3], [f32; 3], [f32; 3]); 3] = [
            (
                [0.0, 0.0, 1.0],
                [0.021_624_332, 0.038_651_697, 0.078_380_43],
                [0.039_511_163, 0.062_919_304, 0.086_352_66],
            ),
            (
                [1.0, 0.0, 0.2],
                [0.077_834_52, 0.127_631_65, 0.197_790_53],
                [0.041_666_567, 0.098_051_01, 0.175_666_24],
            ),
            (
                [0.0, 1.0, 0.01],
                [0.191_210_94, 0.227_137_48, 0.227_847_08],
                [0.033_457_2, 0.083_567_39, 0.171_760_99],
            ),
        ];
        for (d, rgb, spec) in cases {
            let got = view(Basis::Rgb, d);
            for c in 0..3 {
                assert!(
                    close(got[c], rgb[c], 2e-6),
                    "{d:?} rgb {c}: {} vs {}",
                    got[c],
                    rgb[c]
                );
            }
            // 320, 360, 400 nm: the first three channels.
            let got = view(Basis::Spectral, d);
            for (c, want) in spec.into_iter().enumerate() {
                assert!(
                    close(got[c], want, 2e-6),
                    "{d:?} λ{c}: {} vs {want}",
                    got[c]
                );
            }
        }
    }

    /// The sun's RGB irradiance over the disk's solid angle 2π(1 − cos_f32(0.2679°)) against
    /// Mitsuba's sun + sky towards the sun's centre (21157.408, 17235.344, 12450.383) less
    /// the sky there (from our own model, about 0.2): within 10⁻⁵.
    #[test]
    fn sun_is_mitsubas() {
        let (s, eta) = sun();
        let e = sun_irradiance(3.0, eta);
        let omega = 2.0 * std::f64::consts::PI * (1.0 - (SUN_HALF_APERTURE as f32).cos() as f64);
        let sky = view(Basis::Rgb, s.to_array());
        let want = [21_157.408, 17_235.344, 12_450.383];
        let rgb = sun_rgb(&e).to_array();
        for c in 0..3 {
            let got = (rgb[c] as f64 / omega) as f32 + sky[c];
            assert!(
                close(got, want[c], 1e-5),
                "channel {c}: {got} vs {}",
                want[c]
            );
        }
        // Spectral at 320 nm: 895.3046 (sun and sky).
        let sky = view(Basis::Spectral, s.to_array());
        let got = (e[0] as f64 / omega) as f32 + sky[0];
        assert!(close(got, 895.304_6, 1e-5), "{got}");
    }

    /// Channels around a wavelength: the ends of the table included, nothing outside it.
    #[test]
    fn spectral_channels_bracket_the_wavelength() {
        assert_eq!(spectral_channels(320.0), Some((0, 1, 0.0)));
        assert_eq!(spectral_channels(340.0), Some((0, 1, 0.5)));
        assert_eq!(spectral_channels(720.0), Some((10, 10, 0.0)));
        assert_eq!(spectral_channels(719.0).map(|c| (c.0, c.1)), Some((9, 10)));
        assert_eq!(spectral_channels(721.0), None);
        assert_eq!(spectral_channels(319.0), None);
    }

    /// Interpolation in turbidity reaches the tables' rows exactly at whole turbidities and
    /// the last row at 10 (extrapolation weights, as Dr.Jit's `take_interp`).
    #[test]
    fn take_interp_clamps_the_index_not_the_weight() {
        assert_eq!(take_interp(2.0, 10), (2, 0.0));
        assert_eq!(take_interp(9.0, 10), (8, 1.0));
        assert_eq!(take_interp(2.25, 10), (2, 0.25));
        assert_eq!(take_interp(-0.5, 10), (0, -0.5));
    }
}
