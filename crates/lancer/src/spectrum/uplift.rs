//! RGB → spectrum: the sigmoid-polynomial spectra of Jakob & Hanika 2019 ("A Low-Dimensional
//! Function Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2)), as
//! pbrt-v4 uses them for its spectral rendering.
//!
//! A colour becomes the smooth spectrum
//!
//! s(λ) = S(c₀t² + c₁t + c₂),  t = (λ − 360 nm)/(830 nm − 360 nm),  S(x) = ½ + x/(2√(1 + x²)),
//!
//! whose values lie in (0, 1). The three coefficients are fitted by Gauss–Newton so that the
//! spectrum, seen under D65 (the white of sRGB) and reduced to linear sRGB by the same rules as
//! [`super::spectrum_to_rgb`] with [`super::SpectrumKind::Albedo`], reproduces the colour:
//!
//! rgb(s) = M_XYZ→sRGB · Σ_λ s(λ)·D65(λ)·(x̄, ȳ, z̄)(λ) / Σ_λ D65(λ)·ȳ(λ)  (1 nm steps).
//!
//! pbrt-v4 precomputes the coefficients on a 64³×3 grid and interpolates; lancer fits each
//! distinct colour exactly when it first meets it and caches the result per thread (a fit takes
//! well under a millisecond; scenes whose colours are constants need a handful). Image
//! textures and environment maps would need one fit per distinct texel colour: correct but slow
//! the first time; a precomputed table would be the remedy if spectral mode met them often.
//!
//! Three uses, as pbrt-v4's `RGBAlbedoSpectrum`, `RGBUnboundedSpectrum` and
//! `RGBIlluminantSpectrum`:
//!
//! - a reflectance, clamped to [0, 1], is fitted as it is;
//! - an unbounded value with largest component m is written 2m · s(λ), s fitted to rgb/(2m)
//!   (whose components are at most ½, comfortably inside what a sigmoid spectrum can reach);
//! - an illuminant is the unbounded spectrum times D65(λ), divided by Σ D65·ȳ / Σ ȳ so that
//!   RGB (1, 1, 1) has luminance 1 on the film (lancer's light normalisation, pbrt-v4's for RGB
//!   lights): see [`super::sampled`].

use std::cell::RefCell;
use std::collections::HashMap;

use glam::{DMat3, DVec3};

use super::{INTEGRATION_RANGE, cie, weights, xyz_to_srgb_f64};
use crate::math::Rgb;

/// A spectrum s(λ) = S(c₀t² + c₁t + c₂) of the Jakob–Hanika family, or one of its limits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SigmoidSpectrum {
    /// The same value everywhere (greys, including black and white, are fitted exactly so).
    Constant(f32),
    /// Coefficients `[c₀, c₁, c₂]` of the polynomial in t = (λ − 360)/470.
    Poly([f32; 3]),
}

/// S(x) = ½ + x/(2√(1 + x²)): a sigmoid from 0 (x → −∞) to 1 (x → +∞).
#[inline]
fn sigmoid(x: f64) -> f64 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// dS/dx = 1 / (2 (1 + x²)^{3/2}).
#[inline]
fn sigmoid_derivative(x: f64) -> f64 {
    let q = 1.0 + x * x;
    0.5 / (q * q.sqrt())
}

/// Wavelength (nm) → the fit's normalised t ∈ [0, 1].
#[inline]
fn normalised(lambda: f64) -> f64 {
    (lambda - cie::LAMBDA_MIN) / (cie::LAMBDA_MAX - cie::LAMBDA_MIN)
}

impl SigmoidSpectrum {
    /// The value at `lambda` (nm), in [0, 1].
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        match *self {
            SigmoidSpectrum::Constant(v) => v,
            SigmoidSpectrum::Poly([c0, c1, c2]) => {
                // Single precision is plenty here (the fit's tolerance is far coarser).
                let t = (lambda - cie::LAMBDA_MIN as f32)
                    * (1.0 / (cie::LAMBDA_MAX - cie::LAMBDA_MIN) as f32);
                // Horner: (c₀t + c₁)t + c₂.
                let x = (c0 * t + c1) * t + c2;
                if x.is_infinite() {
                    return if x > 0.0 { 1.0 } else { 0.0 };
                }
                0.5 + x / (2.0 * (1.0 + x * x).sqrt())
            }
        }
    }

    /// The spectrum's colour: linear sRGB of s seen under D65 (the reduction the fit inverts).
    pub fn to_rgb(&self) -> Rgb {
        match *self {
            SigmoidSpectrum::Constant(v) => Rgb::splat(v),
            SigmoidSpectrum::Poly(c) => reduce(c.map(f64::from), false).0.as_vec3(),
        }
    }
}

/// rgb(s) for coefficients `c` (see the module documentation) and, when `jacobian`, its
/// derivatives with respect to c₀, c₁, c₂ (the matrix's columns).
fn reduce(c: [f64; 3], jacobian: bool) -> (DVec3, DMat3) {
    let w = weights();
    let mut xyz = DVec3::ZERO;
    let mut d = [DVec3::ZERO; 3];
    for (l, wc) in INTEGRATION_RANGE.zip(&w.d65_cmf) {
        let t = normalised(l as f64);
        let x = (c[0] * t + c[1]) * t + c[2];
        let wc = DVec3::from(*wc);
        xyz += wc * sigmoid(x);
        if jacobian {
            // ∂s/∂cₖ = S'(x) · t^{2−k}.
            let ds = wc * sigmoid_derivative(x);
            d[0] += ds * (t * t);
            d[1] += ds * t;
            d[2] += ds;
        }
    }
    let to_rgb = |v: DVec3| xyz_to_srgb_f64(v / w.d65_y);
    (
        to_rgb(xyz),
        DMat3::from_cols(to_rgb(d[0]), to_rgb(d[1]), to_rgb(d[2])),
    )
}

/// The inverse of S: S(x) = v for v ∈ (0, 1) at x = (v − ½)/√(v(1 − v)).
fn sigmoid_inverse(v: f64) -> f64 {
    (v - 0.5) / (v * (1.0 - v)).sqrt()
}

/// Fits coefficients to a target colour in [0, 1]³ (not all equal): Gauss–Newton on
/// ‖rgb(s) − target‖², walking from the grey of the same mean to the target in a few steps
/// (each solution starts the next fit, as pbrt-v4's table is filled outwards from grey), with
/// step halving whenever a step would not reduce the residual. Colours a sigmoid spectrum
/// cannot reach exactly (on the edge of the gamut) end at the nearest point found.
fn fit(target: DVec3) -> [f64; 3] {
    let mean = ((target.x + target.y + target.z) / 3.0).clamp(0.02, 0.98);
    let grey = DVec3::splat(mean);
    let mut c = [0.0, 0.0, sigmoid_inverse(mean)];
    const STEPS: u32 = 4;
    for step in 1..=STEPS {
        let goal = grey + (target - grey) * (step as f64 / STEPS as f64);
        let (mut rgb, mut jac) = reduce(c, true);
        for _ in 0..30 {
            let r = rgb - goal;
            let err = r.length_squared();
            if err < 1e-14 {
                break;
            }
            // Gauss–Newton step: J·δ = −r.
            if jac.determinant().abs() < 1e-300 {
                break;
            }
            let delta = jac.inverse() * -r;
            if !delta.is_finite() {
                break;
            }
            let mut scale = 1.0;
            let mut improved = false;
            for _ in 0..12 {
                let trial = [
                    c[0] + scale * delta.x,
                    c[1] + scale * delta.y,
                    c[2] + scale * delta.z,
                ];
                let (trgb, tjac) = reduce(trial, true);
                if (trgb - goal).length_squared() < err {
                    c = trial;
                    rgb = trgb;
                    jac = tjac;
                    improved = true;
                    break;
                }
                scale *= 0.5;
            }
            if !improved {
                break;
            }
        }
    }
    c
}

/// The sigmoid spectrum of a reflectance (clamped to [0, 1] first, as pbrt-v4's
/// `RGBAlbedoSpectrum` requires; NaN as 0). Greys, black and white are constant spectra.
pub fn fit_albedo(rgb: Rgb) -> SigmoidSpectrum {
    let rgb = clamp_albedo(rgb);
    if rgb.x == rgb.y && rgb.y == rgb.z {
        return SigmoidSpectrum::Constant(rgb.x);
    }
    SigmoidSpectrum::Poly(fit(rgb.as_dvec3()).map(|v| v as f32))
}

/// A hasher for the cache's keys (three words of colour bits): one multiply-and-rotate round
/// per word (the Fx hash of rustc), much cheaper than the default SipHash on this hot path,
/// and the keys are not chosen by an adversary.
#[derive(Default)]
struct ColourHasher(u64);

impl std::hash::Hasher for ColourHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        // Arrays of u32 arrive here as one slice of bytes: four at a time.
        let mut chunks = bytes.chunks_exact(4);
        for c in &mut chunks {
            self.write_u32(u32::from_le_bytes([c[0], c[1], c[2], c[3]]));
        }
        for b in chunks.remainder() {
            self.write_u32(*b as u32);
        }
    }

    #[inline]
    fn write_u32(&mut self, v: u32) {
        self.0 = (self.0.rotate_left(5) ^ v as u64).wrapping_mul(0x517c_c1b7_2722_0a95);
    }

    #[inline]
    fn write_usize(&mut self, v: usize) {
        self.0 = (self.0.rotate_left(5) ^ v as u64).wrapping_mul(0x517c_c1b7_2722_0a95);
    }

    #[inline]
    fn finish(&self) -> u64 {
        self.0
    }
}

type ColourMap = HashMap<[u32; 3], SigmoidSpectrum, std::hash::BuildHasherDefault<ColourHasher>>;

/// Entries of the per-thread direct-mapped cache in front of the map.
const RECENT_SIZE: usize = 256;

/// A key no clamped colour has (NaN bits), marking an empty entry of the direct-mapped cache.
const EMPTY_KEY: [u32; 3] = [u32::MAX; 3];

thread_local! {
    /// This thread's fits, by the bits of the (clamped) colour.
    static CACHE: RefCell<ColourMap> = RefCell::new(ColourMap::default());
    /// A direct-mapped cache of the most recent fits, checked first: one hash and compare on
    /// the common path (a scene's few constant colours, met at every hit).
    static RECENT: RefCell<[([u32; 3], SigmoidSpectrum); RECENT_SIZE]> =
        const { RefCell::new([(EMPTY_KEY, SigmoidSpectrum::Constant(0.0)); RECENT_SIZE]) };
}

/// Most entries a thread's cache holds before it starts again (bounds memory on textured
/// scenes; each entry is a few dozen bytes).
const CACHE_LIMIT: usize = 1 << 20;

/// A colour clamped to [0, 1], NaN taken as 0.
fn clamp_albedo(rgb: Rgb) -> Rgb {
    Rgb::from_array(
        rgb.to_array()
            .map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }),
    )
}

/// [`fit_albedo`], cached per thread by the exact colour.
pub fn albedo_spectrum(rgb: Rgb) -> SigmoidSpectrum {
    let rgb = clamp_albedo(rgb);
    if rgb.x == rgb.y && rgb.y == rgb.z {
        return SigmoidSpectrum::Constant(rgb.x);
    }
    let key = rgb.to_array().map(f32::to_bits);
    // The slot: the top bits of a multiplicative hash of the three words.
    let slot = (((key[0] as u64 | (key[1] as u64) << 32).wrapping_mul(0x9e37_79b9_7f4a_7c15)
        ^ (key[2] as u64).wrapping_mul(0xc2b2_ae3d_27d4_eb4f))
    .wrapping_mul(0x517c_c1b7_2722_0a95)
        >> (64 - RECENT_SIZE.trailing_zeros())) as usize;
    RECENT.with(|recent| {
        let mut recent = recent.borrow_mut();
        if recent[slot].0 == key {
            return recent[slot].1;
        }
        let s = CACHE.with(|c| {
            if let Some(s) = c.borrow().get(&key) {
                return *s;
            }
            let s = fit_albedo(rgb);
            let mut c = c.borrow_mut();
            if c.len() >= CACHE_LIMIT {
                c.clear();
            }
            c.insert(key, s);
            s
        });
        recent[slot] = (key, s);
        s
    })
}

/// An unbounded colour (components ≥ 0, negatives clamped) as pbrt-v4's
/// `RGBUnboundedSpectrum`: a scale 2m, m the largest component, and the albedo spectrum of
/// rgb/(2m). Evaluate as `scale · spectrum.eval(λ)`; black is scale 0.
pub fn unbounded_spectrum(rgb: Rgb) -> (f32, SigmoidSpectrum) {
    let rgb = rgb.max(Rgb::ZERO);
    let m = rgb.max_element();
    if m.is_nan() || m <= 0.0 || m.is_infinite() {
        return (0.0, SigmoidSpectrum::Constant(0.0));
    }
    let scale = 2.0 * m;
    (scale, albedo_spectrum(rgb / scale))
}

#[cfg(test)]
mod tests {
    use super::super::{Spectrum, SpectrumKind, spectrum_to_rgb};
    use super::*;

    /// The spectrum tabulated every 1 nm, reduced by the independent code of
    /// [`spectrum_to_rgb`] (this also checks `eval` with the f32 coefficients), and its
    /// extreme values.
    fn reduce_independently(s: &SigmoidSpectrum) -> (Rgb, f32, f32) {
        let lambda: Vec<f32> = (360..=830).map(|l| l as f32).collect();
        let values: Vec<f32> = lambda.iter().map(|&l| s.eval(l)).collect();
        let (lo, hi) = values
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let rgb = spectrum_to_rgb(
            &Spectrum::PiecewiseLinear { lambda, values },
            SpectrumKind::Unbounded,
        );
        (rgb, lo, hi)
    }

    #[test]
    fn albedo_spectra_reproduce_in_gamut_colours() {
        let grid = [0.05f32, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95];
        let mut worst = 0.0f32;
        for &r in &grid {
            for &g in &grid {
                for &b in &grid {
                    let c = Rgb::new(r, g, b);
                    let s = fit_albedo(c);
                    let (back, lo, hi) = reduce_independently(&s);
                    let err = (back - c).abs().max_element();
                    worst = worst.max(err);
                    assert!(err <= 2e-3, "{c} came back as {back} ({s:?})");
                    assert!((0.0..=1.0).contains(&lo) && hi <= 1.0, "{c}: {lo}..{hi}");
                    // The fit's own reduction agrees with the independent one (greys are
                    // constants, whose independent reduction carries the ~1e-4 mismatch
                    // between the tabulated D65 white and the sRGB matrix's).
                    let d = (s.to_rgb() - back).abs().max_element();
                    assert!(d < 3e-4, "{c}: {} vs {back}", s.to_rgb());
                }
            }
        }
        println!("worst round-trip error {worst:.2e}");
    }

    #[test]
    fn saturated_colours_come_back_closely() {
        // The bitterli-coffee scene's orange plastic, and strong primaries and secondaries.
        for c in [
            Rgb::new(1.0, 0.379, 0.013),
            Rgb::new(0.9, 0.05, 0.05),
            Rgb::new(0.05, 0.8, 0.1),
            Rgb::new(0.05, 0.1, 0.9),
            Rgb::new(0.95, 0.9, 0.05),
        ] {
            let (back, lo, hi) = reduce_independently(&fit_albedo(c));
            assert!(
                (back - c).abs().max_element() <= 5e-3,
                "{c} came back as {back}"
            );
            assert!(lo >= 0.0 && hi <= 1.0);
        }
    }

    #[test]
    fn greys_are_constant_and_albedos_are_clamped() {
        assert_eq!(fit_albedo(Rgb::ZERO), SigmoidSpectrum::Constant(0.0));
        assert_eq!(fit_albedo(Rgb::ONE), SigmoidSpectrum::Constant(1.0));
        assert_eq!(fit_albedo(Rgb::splat(0.3)), SigmoidSpectrum::Constant(0.3));
        // Above 1 and below 0 are clamped first (pbrt's albedo spectra live in [0, 1]).
        assert_eq!(fit_albedo(Rgb::splat(1.7)), SigmoidSpectrum::Constant(1.0));
        assert_eq!(
            albedo_spectrum(Rgb::new(1.5, -0.2, 0.5)),
            fit_albedo(Rgb::new(1.0, 0.0, 0.5))
        );
        // The cache returns the fit itself.
        let c = Rgb::new(0.3, 0.6, 0.2);
        assert_eq!(albedo_spectrum(c), fit_albedo(c));
        assert_eq!(albedo_spectrum(c), fit_albedo(c));
    }

    #[test]
    fn unbounded_spectra_scale_by_twice_the_largest_component() {
        assert_eq!(unbounded_spectrum(Rgb::ZERO).0, 0.0);
        assert_eq!(unbounded_spectrum(Rgb::new(-1.0, f32::NAN, 0.0)).0, 0.0);
        for c in [
            Rgb::new(3.0, 1.5, 0.2),
            Rgb::new(0.2, 0.9, 1.1),
            Rgb::splat(2.5),
        ] {
            let (scale, s) = unbounded_spectrum(c);
            assert_eq!(scale, 2.0 * c.max_element());
            let (back, _, hi) = reduce_independently(&s);
            assert!(hi <= 1.0);
            let back = back * scale;
            assert!(
                (back - c).abs().max_element() <= 2e-3 * scale,
                "{c} came back as {back}"
            );
        }
    }
}
