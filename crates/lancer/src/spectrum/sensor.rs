//! The film's sensor, as pbrt-v4's `PixelSensor`: how a sample's radiance becomes the output
//! colour space's RGB, with white balance.
//!
//! - The `cie1931` sensor (the default) measures XYZ with the CIE 1931 functions. With
//!   `"float whitebalance" [T]` (T ≠ 0) XYZ is adapted from the white of the illuminant
//!   D(T) to the output space's white (von Kries in Bradford's cone space,
//!   [`super::colorspace::white_balance`]).
//! - A named camera sensor (`canon_eos_5d_mkiv`, …, [`super::sensor_data::SENSORS`]) measures
//!   its own r, g, b with its response curves; a 3×3 matrix fitted by least squares takes them
//!   to XYZ, trained on reflectances so that, lit by D(T) (T = 6500 when not given), they
//!   come out as they look under the output space's white, the 24 measured ColorChecker
//!   spectra pbrt-v4 uses ([`super::sensor_data::CHART_SPECTRA`]).
//!
//! D(T) is pbrt-v4's `Spectra::D`: for a correlated colour temperature T' = T·1.4388/1.4380
//! below 4000 K a black body, else CIE daylight S₀ + M₁S₁ + M₂S₂ with M₁, M₂ from the
//! daylight locus' chromaticity at T'.
//!
//! [`FilmResponse`] is what the renderer applies to each camera sample when the film asks for
//! anything but the plain CIE 1931 observer into sRGB.

use glam::{DMat3, DVec3, Mat3, Vec3};

use super::cie;
use super::colorspace::{ColorSpace, white_balance};
use super::sampled::SampledWavelengths;
use super::sensor_data::{
    CHART_LAMBDA_MIN, CHART_SAMPLES, CHART_SPECTRA, CIE_S0, CIE_S1, CIE_S2, SENSOR_LAMBDA_MIN,
    SENSOR_LAMBDA_STEP, SENSOR_SAMPLES, SENSORS,
};
use crate::math::{Rgb, SampledSpectrum, lanes_rgb};

/// A film's sensor (pbrt-v4's `"string sensor"`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Sensor {
    /// The CIE 1931 observer: the sensor measures XYZ.
    #[default]
    Cie1931,
    /// A camera of [`SENSORS`], by index.
    Named(usize),
}

impl Sensor {
    /// The sensor pbrt-v4 calls `name`.
    pub fn from_name(name: &str) -> Option<Sensor> {
        if name == "cie1931" {
            return Some(Sensor::Cie1931);
        }
        SENSORS.iter().position(|s| s.0 == name).map(Sensor::Named)
    }

    /// pbrt-v4's name of the sensor.
    pub fn name(self) -> &'static str {
        match self {
            Sensor::Cie1931 => "cie1931",
            Sensor::Named(i) => SENSORS[i].0,
        }
    }

    /// Every name [`Sensor::from_name`] knows.
    pub fn names() -> impl Iterator<Item = &'static str> {
        std::iter::once("cie1931").chain(SENSORS.iter().map(|s| s.0))
    }

    /// The response (r̄, ḡ, b̄) at `lambda` nm: the CIE functions for `cie1931`, else the
    /// camera's curves interpolated linearly (zero outside 380–720 nm).
    pub fn response(self, lambda: f64) -> [f64; 3] {
        match self {
            Sensor::Cie1931 => cie::cmf(lambda),
            Sensor::Named(i) => {
                let x = (lambda - SENSOR_LAMBDA_MIN) / SENSOR_LAMBDA_STEP;
                if !(0.0..=(SENSOR_SAMPLES - 1) as f64).contains(&x) {
                    return [0.0; 3];
                }
                let j = (x.floor() as usize).min(SENSOR_SAMPLES - 2);
                let t = x - j as f64;
                SENSORS[i]
                    .1
                    .map(|c| c[j] as f64 * (1.0 - t) + c[j + 1] as f64 * t)
            }
        }
    }
}

/// pbrt-v4's `Spectra::D(T)` at `lambda` nm (up to a constant factor, which white balance
/// ignores): a black body below a correlated colour temperature of 4000 K, else CIE daylight.
pub fn daylight(temperature: f64, lambda: f64) -> f64 {
    let cct = temperature * 1.4388 / 1.4380;
    if cct < 4000.0 {
        return super::blackbody(lambda as f32, cct as f32) as f64;
    }
    // The daylight locus (CIE 015): x from 1/T', y = −3x² + 2.870x − 0.275.
    let x = if cct <= 7000.0 {
        -4.607e9 / cct.powi(3) + 2.9678e6 / (cct * cct) + 0.09911e3 / cct + 0.244063
    } else {
        -2.0064e9 / cct.powi(3) + 1.9018e6 / (cct * cct) + 0.24748e3 / cct + 0.23704
    };
    let y = -3.0 * x * x + 2.870 * x - 0.275;
    let m = 0.0241 + 0.2562 * x - 0.7341 * y;
    let m1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / m;
    let m2 = (0.0300 - 31.4424 * x + 30.0717 * y) / m;
    if !(cie::LAMBDA_MIN..=cie::LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let s = (lambda - cie::LAMBDA_MIN) / cie::LAMBDA_STEP;
    let i = (s.floor() as usize).min(cie::SAMPLES - 2);
    let t = s - i as f64;
    let at = |k: usize| CIE_S0[k] + m1 * CIE_S1[k] + m2 * CIE_S2[k];
    at(i) * (1.0 - t) + at(i + 1) * t
}

/// Σ over 360–830 nm (1 nm steps) of f(λ).
fn integrate(f: impl Fn(f64) -> DVec3) -> DVec3 {
    cie::INTEGRATION_RANGE.map(|l| f(l as f64)).sum()
}

/// The reflectance of ColorChecker patch `i` at `lambda` nm ([`CHART_SPECTRA`], interpolated
/// linearly; zero outside 380–730 nm, as pbrt-v4's piecewise-linear spectra).
fn chart(i: usize, lambda: f64) -> f64 {
    let x = (lambda - CHART_LAMBDA_MIN) / 10.0;
    if !(0.0..=(CHART_SAMPLES - 1) as f64).contains(&x) {
        return 0.0;
    }
    let j = (x.floor() as usize).min(CHART_SAMPLES - 2);
    let t = x - j as f64;
    CHART_SPECTRA[i][j] as f64 * (1.0 - t) + CHART_SPECTRA[i][j + 1] as f64 * t
}

/// The XYZ-from-sensor-RGB matrix of pbrt-v4's `PixelSensor`: for `cie1931`, the white balance
/// from D(T) to `output`'s white (identity when T = 0); for a camera, the least-squares fit
/// M = argmin Σᵢ ‖M·rgbᵢ − xyzᵢ‖² over the ColorChecker's reflectances ρᵢ, with
/// rgbᵢ = Σ ρᵢ·D(T)·(r̄, ḡ, b̄) / Σ D(T)·ḡ (the camera under D(T)) and
/// xyzᵢ = Σ ρᵢ·W·(x̄, ȳ, z̄) / Σ W·ȳ · Σ D(T)·ȳ / Σ D(T)·ḡ (the colour under the output white W).
pub fn xyz_from_sensor(sensor: Sensor, white_balance_k: f64, output: ColorSpace) -> DMat3 {
    let t = match (sensor, white_balance_k) {
        (Sensor::Cie1931, 0.0) => return DMat3::IDENTITY,
        (Sensor::Cie1931, t) => {
            let src = integrate(|l| DVec3::from(cie::cmf(l)) * daylight(t, l));
            return white_balance(src, output.white_xyz());
        }
        (Sensor::Named(_), 0.0) => 6500.0,
        (Sensor::Named(_), t) => t,
    };
    let illum = |l: f64| daylight(t, l);
    let sensor_white = integrate(|l| DVec3::from(sensor.response(l)) * illum(l));
    let y_white = integrate(|l| DVec3::splat(cie::cmf(l)[1] * illum(l))).x;
    let out_white = integrate(|l| DVec3::splat(cie::cmf(l)[1] * output.illuminant(l))).x;
    let (mut ata, mut atb) = (DMat3::ZERO, DMat3::ZERO);
    for i in 0..CHART_SPECTRA.len() {
        let cam = integrate(|l| DVec3::from(sensor.response(l)) * chart(i, l) * illum(l))
            / sensor_white.y;
        let xyz = integrate(|l| DVec3::from(cie::cmf(l)) * chart(i, l) * output.illuminant(l))
            / out_white
            * (y_white / sensor_white.y);
        // Normal equations: (AᵀA) Mᵀ = AᵀB, rows of A the camera colours, of B the XYZs.
        ata += outer(cam, cam);
        atb += outer(cam, xyz);
    }
    (ata.inverse() * atb).transpose()
}

/// a·bᵀ.
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// What the film does to each camera sample beyond the plain CIE 1931 → sRGB conversion: a
/// camera's response curves, white balance, an output colour space other than sRGB.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmResponse {
    /// A camera's curves (r̄, ḡ, b̄, 0) at 360, 365, …, 830 nm, divided by Σȳ; `None` for
    /// the CIE functions.
    rows: Option<Box<[SampledSpectrum; cie::SAMPLES]>>,
    /// Spectral mode: the output RGB from the sensor's RGB (with `rows`) or from the linear
    /// sRGB of the CIE functions' XYZ (without).
    spectral: Mat3,
    /// RGB mode: the output RGB from the sample's linear sRGB.
    rgb: Mat3,
    /// The sensor's RGB from the output RGB: the inverse of pbrt-v4's
    /// `outputRGBFromSensorRGB` (for the CIE 1931 sensor, whose RGB is XYZ, XYZ from output).
    sensor_from_output: Mat3,
}

impl FilmResponse {
    /// The response of a film with `sensor`, white balance `white_balance_k` (0: none) and
    /// output space `output`; `None` when it is the plain CIE 1931 observer into sRGB.
    pub fn new(sensor: Sensor, white_balance_k: f32, output: ColorSpace) -> Option<FilmResponse> {
        if sensor == Sensor::Cie1931 && white_balance_k == 0.0 && output == ColorSpace::Srgb {
            return None;
        }
        let out = output.xyz_to_rgb() * xyz_from_sensor(sensor, white_balance_k as f64, output);
        let srgb_to_xyz = ColorSpace::Srgb.rgb_to_xyz();
        let y_integral = integrate(|l| DVec3::splat(cie::cmf(l)[1])).x;
        let (rows, spectral, rgb) = match sensor {
            Sensor::Cie1931 => (None, out * srgb_to_xyz, out * srgb_to_xyz),
            Sensor::Named(_) => {
                let rows = Box::new(std::array::from_fn(|i| {
                    let l = cie::LAMBDA_MIN + i as f64 * cie::LAMBDA_STEP;
                    let r = sensor.response(l).map(|v| (v / y_integral) as f32);
                    SampledSpectrum::new(r[0], r[1], r[2], 0.0)
                }));
                // RGB mode: the camera's colour of each sRGB primary as an illuminant (its
                // smooth spectrum times D65, at luminance 1 for white), a column each.
                let d65_y = integrate(|l| DVec3::splat(cie::cmf(l)[1] * cie::d65(l))).x;
                let cols = [Rgb::X, Rgb::Y, Rgb::Z].map(|p| {
                    let (scale, s) = super::uplift::unbounded_spectrum(p);
                    integrate(|l| {
                        DVec3::from(sensor.response(l))
                            * (scale * s.eval(l as f32)) as f64
                            * cie::d65(l)
                    }) / d65_y
                });
                let camera_from_srgb = DMat3::from_cols(cols[0], cols[1], cols[2]);
                (Some(rows), out, out * camera_from_srgb)
            }
        };
        Some(FilmResponse {
            rows,
            spectral: spectral.as_mat3(),
            rgb: rgb.as_mat3(),
            sensor_from_output: out.inverse().as_mat3(),
        })
    }

    /// The sensor's RGB of a sample whose output RGB is `output` (pbrt-v4's `ToSensorRGB`,
    /// before `outputRGBFromSensorRGB`).
    pub fn sensor_rgb(&self, output: Rgb) -> Rgb {
        (self.sensor_from_output * Vec3::from(output)).into()
    }

    /// The output colour of a camera sample's radiance `l`: in spectral mode (`lambda`) the
    /// sensor's RGB, (1/4) Σᵢ (r̄, ḡ, b̄)(λᵢ)·L(λᵢ)/p(λᵢ) / Σȳ, or the CIE functions' sRGB,
    /// then the spectral matrix; in RGB mode the lanes' sRGB times the RGB matrix.
    pub fn film_rgb(&self, lambda: Option<&SampledWavelengths>, l: SampledSpectrum) -> Rgb {
        let v = match (lambda, &self.rows) {
            (None, _) => return (self.rgb * Vec3::from(lanes_rgb(l))).into(),
            (Some(w), None) => w.to_film_rgb(l),
            (Some(w), Some(rows)) => {
                let live = w.pdf.cmpgt(SampledSpectrum::ZERO) & l.cmpne(SampledSpectrum::ZERO);
                let q = SampledSpectrum::select(live, l / w.pdf, SampledSpectrum::ZERO) * 0.25;
                let mut sum = SampledSpectrum::ZERO;
                for i in 0..4 {
                    sum += row_at(rows, w.lambda[i]) * q[i];
                }
                Rgb::new(sum[0], sum[1], sum[2])
            }
        };
        (self.spectral * Vec3::from(v)).into()
    }
}

/// `rows` at `lambda` nm, interpolated linearly between its 5 nm nodes.
fn row_at(rows: &[SampledSpectrum; cie::SAMPLES], lambda: f32) -> SampledSpectrum {
    let x = ((lambda - cie::LAMBDA_MIN as f32) / cie::LAMBDA_STEP as f32).max(0.0);
    let i = (x as usize).min(cie::SAMPLES - 2);
    let (a, b) = (rows[i], rows[i + 1]);
    a + (x - i as f32) * (b - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sensors_are_known_by_name() {
        assert_eq!(Sensor::from_name("cie1931"), Some(Sensor::Cie1931));
        let s = Sensor::from_name("canon_eos_5d_mkiv").unwrap();
        assert_eq!(s.name(), "canon_eos_5d_mkiv");
        assert_eq!(Sensor::from_name("leica"), None);
        assert_eq!(Sensor::names().count(), 18);
        // The curves are zero outside 380–720 nm and interpolate between 10 nm nodes.
        assert_eq!(s.response(375.0), [0.0; 3]);
        let (a, b) = (s.response(550.0), s.response(560.0));
        let mid = s.response(555.0);
        assert!((mid[1] - 0.5 * (a[1] + b[1])).abs() < 1e-12);
    }

    #[test]
    fn daylight_is_blackbody_below_4000_k_and_d65_at_6504_k() {
        // Below 4000 K: a black body of T·1.4388/1.4380.
        let t = 3000.0 * 1.4388 / 1.4380;
        let ratio = daylight(3000.0, 500.0) / daylight(3000.0, 600.0);
        let want = crate::spectrum::blackbody(500.0, t as f32) as f64
            / crate::spectrum::blackbody(600.0, t as f32) as f64;
        assert!((ratio - want).abs() < 1e-6 * want);
        // D(6500) has D65's chromaticity (D65's CCT is 6504 K; 6500 gives T' = 6503.6 K).
        let xyz = integrate(|l| DVec3::from(cie::cmf(l)) * daylight(6500.0, l));
        let (x, y) = (xyz.x / xyz.element_sum(), xyz.y / xyz.element_sum());
        assert!(
            (x - 0.3127).abs() < 1e-3 && (y - 0.3290).abs() < 1e-3,
            "{x} {y}"
        );
    }

    #[test]
    fn plain_film_has_no_response_and_white_balance_keeps_the_output_white() {
        assert_eq!(
            FilmResponse::new(Sensor::Cie1931, 0.0, ColorSpace::Srgb),
            None
        );
        // White balance at 3000 K: the 3000 K white becomes the output white (sRGB 1, 1, 1).
        let m = xyz_from_sensor(Sensor::Cie1931, 3000.0, ColorSpace::Srgb);
        let src = integrate(|l| DVec3::from(cie::cmf(l)) * daylight(3000.0, l));
        let rgb = ColorSpace::Srgb.xyz_to_rgb() * m * (src / src.y);
        assert!((rgb - DVec3::ONE).abs().max_element() < 2e-3, "{rgb}");
    }

    /// The sensor's RGB taken back from the output: with a camera's curves, its own RGB
    /// (the output is `out` times it); with white balance on the CIE 1931 sensor, XYZ before
    /// the balance.
    #[test]
    fn sensor_rgb_inverts_the_output_matrix() {
        let s = Sensor::from_name("canon_eos_5d_mkiv").unwrap();
        let r = FilmResponse::new(s, 5000.0, ColorSpace::Srgb).unwrap();
        let out = ColorSpace::Srgb.xyz_to_rgb() * xyz_from_sensor(s, 5000.0, ColorSpace::Srgb);
        let cam = DVec3::new(0.3, 0.5, 0.2);
        let back = r.sensor_rgb((out * cam).as_vec3().into());
        assert!((back.as_dvec3() - cam).abs().max_element() < 1e-6, "{back}");
        let r = FilmResponse::new(Sensor::Cie1931, 3000.0, ColorSpace::Srgb).unwrap();
        let m = xyz_from_sensor(Sensor::Cie1931, 3000.0, ColorSpace::Srgb);
        let xyz = DVec3::new(0.4, 0.35, 0.1);
        let output = ColorSpace::Srgb.xyz_to_rgb() * m * xyz;
        let back = r.sensor_rgb(output.as_vec3().into());
        assert!((back.as_dvec3() - xyz).abs().max_element() < 1e-6, "{back}");
    }

    #[test]
    fn a_camera_sees_its_white_as_white() {
        // A camera balanced for 5000 K: a white reflectance under D(5000) comes out as the
        // output white, with the luminance it has under D(5000).
        let s = Sensor::from_name("canon_eos_5d_mkiv").unwrap();
        let m = xyz_from_sensor(s, 5000.0, ColorSpace::Srgb);
        let cam = integrate(|l| DVec3::from(s.response(l)) * daylight(5000.0, l));
        let y = integrate(|l| DVec3::splat(cie::cmf(l)[1] * daylight(5000.0, l))).x;
        let xyz = m * cam;
        let rgb = ColorSpace::Srgb.xyz_to_rgb() * xyz / y;
        assert!((rgb - DVec3::ONE).abs().max_element() < 0.03, "{rgb}");
    }
}
