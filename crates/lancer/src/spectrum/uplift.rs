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
//! [`fit_albedo`] fits one colour exactly (about 0.1 ms; the fit itself is in `fit.rs`).
//! Rendering instead looks colours up in a [`CoefficientTable`], as pbrt-v4 does:
//! coefficients fitted on a 3 × 40³ grid over the colour cube and interpolated trilinearly, so
//! that image textures and environment maps with many distinct texel colours cost a lookup each
//! rather than a fit. The table is fitted when the crate is compiled (by its build script, with
//! the same code) and shipped inside the library, so no process pays for it; its fits are
//! warm-started from their neighbours, as in rgb2spec_opt. Interpolated colours come back within
//! 2·10⁻³ of the input in [0, 1]³ (about 5·10⁻⁴ on average; up to 3·10⁻³ in the corner of
//! near-whites, all components above 0.85 and one within 2 % of 1), against about 10⁻⁷ for an
//! exact fit; the grid's spacing and the interpolation's measure along the brightest
//! component are chosen for that (see [`CoefficientTable`]). Lookups are pure functions of the
//! colour, so renders depend on neither threads nor the order colours are met.
//!
//! Three uses, as pbrt-v4's `RGBAlbedoSpectrum`, `RGBUnboundedSpectrum` and
//! `RGBIlluminantSpectrum`:
//!
//! - a reflectance, clamped to [0, 1], is uplifted as it is;
//! - an unbounded value with largest component m is written 2m · s(λ), s uplifted from rgb/(2m)
//!   (whose components are at most ½, comfortably inside what a sigmoid spectrum can reach);
//! - an illuminant is the unbounded spectrum times D65(λ), divided by Σ D65·ȳ / Σ ȳ so that
//!   RGB (1, 1, 1) has luminance 1 on the film (lancer's light normalisation, pbrt-v4's for RGB
//!   lights): see [`super::sampled`].

use std::sync::OnceLock;

use super::cie;
use super::fit::Fitter;
use crate::math::Rgb;

pub use super::fit::TABLE_RES;
pub use super::table::CoefficientTable;

/// A spectrum s(λ) = S(c₀t² + c₁t + c₂) of the Jakob–Hanika family, or one of its limits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SigmoidSpectrum {
    /// The same value everywhere (greys, including black and white, are fitted exactly so).
    Constant(f32),
    /// Coefficients `[c₀, c₁, c₂]` of the polynomial in t = (λ − 360)/470.
    Poly([f32; 3]),
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
            SigmoidSpectrum::Poly(c) => {
                Rgb::from_array(fitter().colour(c.map(f64::from)).map(|v| v as f32))
            }
        }
    }
}

/// The fitter of the process (its weights computed on first use).
fn fitter() -> &'static Fitter {
    static FITTER: OnceLock<Fitter> = OnceLock::new();
    FITTER.get_or_init(Fitter::new)
}

/// The sigmoid spectrum of a reflectance (clamped to [0, 1] first, as pbrt-v4's
/// `RGBAlbedoSpectrum` requires; NaN as 0). Greys, black and white are constant spectra.
pub fn fit_albedo(rgb: Rgb) -> SigmoidSpectrum {
    let rgb = clamp_albedo(rgb);
    if rgb.x == rgb.y && rgb.y == rgb.z {
        return SigmoidSpectrum::Constant(rgb.x);
    }
    SigmoidSpectrum::Poly(fitter().fit(rgb.as_dvec3().to_array()).map(|v| v as f32))
}

/// A colour clamped to [0, 1], NaN taken as 0.
fn clamp_albedo(rgb: Rgb) -> Rgb {
    Rgb::from_array(
        rgb.to_array()
            .map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }),
    )
}

/// The sigmoid spectrum of a reflectance for rendering: NaN taken as 0; greys, black and white
/// are constant spectra, every other colour of [0, 1]³ is looked up in the sRGB
/// [`CoefficientTable`] fitted at compile time (set up on the first such colour), and colours
/// outside the cube in the Rec. 2020 one (`wide_albedo_spectrum`).
pub fn albedo_spectrum(rgb: Rgb) -> SigmoidSpectrum {
    if rgb.min_element() < 0.0 || rgb.max_element() > 1.0 {
        return wide_albedo_spectrum(rgb);
    }
    let rgb = clamp_albedo(rgb);
    if rgb.x == rgb.y && rgb.y == rgb.z {
        return SigmoidSpectrum::Constant(rgb.x);
    }
    SigmoidSpectrum::Poly(CoefficientTable::get().lookup(rgb))
}

/// A reflectance outside the sRGB cube (a component below 0 or above 1: a colour read in a
/// wider space and converted to linear sRGB, [`super::ColorSpace`]; pbrt-v4 refuses sRGB
/// reflectances above 1), uplifted through the Rec. 2020 table: its Rec. 2020 coordinates
/// c = M_XYZ→2020 · M_sRGB→XYZ · rgb, clamped to [0, 1] (as pbrt-v4 clamps in the space it
/// was given in), looked up there. Both tables fit the colour seen under D65, so the spectrum
/// is the one the colour's own space would give.
fn wide_albedo_spectrum(rgb: Rgb) -> SigmoidSpectrum {
    use std::sync::OnceLock;
    static TO_2020: OnceLock<glam::Mat3> = OnceLock::new();
    let m = TO_2020.get_or_init(|| {
        let srgb = glam::DMat3::from_cols_array_2d(&cie::XYZ_TO_SRGB).transpose();
        let rec = glam::DMat3::from_cols_array_2d(&cie::XYZ_TO_REC2020).transpose();
        (rec * srgb.inverse()).as_mat3()
    });
    let c = clamp_albedo(Rgb::from(*m * glam::Vec3::from(rgb)));
    if c.x == c.y && c.y == c.z {
        return SigmoidSpectrum::Constant(c.x);
    }
    SigmoidSpectrum::Poly(CoefficientTable::get_rec2020().lookup(c))
}

/// An unbounded colour as pbrt-v4's `RGBUnboundedSpectrum`: a scale 2m, m the largest
/// component, and the albedo spectrum of rgb/(2m). Components ≥ 0 (negatives clamped), unless
/// the colour lies outside the sRGB gamut with a positive largest component (a colour of a
/// wider space), which keeps them for [`albedo_spectrum`]. Evaluate as
/// `scale · spectrum.eval(λ)`; black is scale 0.
pub fn unbounded_spectrum(rgb: Rgb) -> (f32, SigmoidSpectrum) {
    let m = rgb.max_element();
    let rgb = if m > 0.0 && rgb.min_element() < 0.0 {
        rgb
    } else {
        rgb.max(Rgb::ZERO)
    };
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
            albedo_spectrum(Rgb::splat(-0.5)),
            SigmoidSpectrum::Constant(0.0)
        );
        assert_eq!(
            albedo_spectrum(Rgb::new(1.0, 0.0, f32::NAN)),
            albedo_spectrum(Rgb::new(1.0, 0.0, 0.0))
        );
        // Other colours come from the table.
        let c = Rgb::new(0.3, 0.6, 0.2);
        assert_eq!(
            albedo_spectrum(c),
            SigmoidSpectrum::Poly(CoefficientTable::get().lookup(c))
        );
    }

    /// A deterministic stream of numbers in [0, 1) (a 64-bit LCG's top 24 bits).
    fn uniforms(seed: u64) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn table_lookups_reproduce_colours_across_the_cube() {
        // Every colour of [0, 1]³ is within reach of a sigmoid spectrum to ~10⁻⁷ (exact fits of
        // this same set come back so), so the whole cube is the test set: uniform colours,
        // plus colours near the faces, edges and corners, where the coefficients grow fastest.
        let mut u = uniforms(7);
        let mut near_end = uniforms(11);
        let table = CoefficientTable::get();
        let (mut worst, mut sum, count) = (0.0f32, 0.0f64, 20_000);
        for n in 0..count {
            let mut c = Rgb::new(u(), u(), u());
            if n % 4 == 0 {
                // Push one or two components within 2 % of 0 or 1.
                for k in 0..(1 + n / 4 % 2) {
                    let v = 0.02 * near_end();
                    c[(n / 8 + k) % 3] = if near_end() < 0.5 { v } else { 1.0 - v };
                }
            }
            if c.x == c.y && c.y == c.z {
                continue;
            }
            let s = SigmoidSpectrum::Poly(table.lookup(c));
            let (back, lo, hi) = reduce_independently(&s);
            let err = (back - c).abs().max_element();
            // Near white (all components near 1) the coefficients grow like the inverse
            // square root of the distance to 1, and linear interpolation loses accuracy: a
            // looser bound in that corner only.
            let near_white = c.min_element() >= 0.85 && c.max_element() >= 0.98;
            let bound = if near_white { 4e-3 } else { 2e-3 };
            assert!(err <= bound, "{c} came back as {back} ({s:?})");
            assert!((0.0..=1.0).contains(&lo) && hi <= 1.0, "{c}: {lo}..{hi}");
            worst = worst.max(err);
            sum += err as f64;
        }
        let mean = sum / count as f64;
        // A table whose fits or interpolation had gone wrong anywhere would show here.
        assert!(mean < 8e-4, "mean error {mean:.2e}");
        println!("worst {worst:.2e}, mean {mean:.2e}");
        // Colours on the faces of the cube (a component exactly 0 or 1, as in 8-bit
        // textures), not all reachable exactly: the table gives what an exact fit gives.
        for c in [
            Rgb::new(1.0, 0.0, 0.0),
            Rgb::new(0.0, 1.0, 1.0),
            Rgb::new(1.0, 0.5, 0.2),
            Rgb::new(0.3, 1.0, 0.0),
            Rgb::new(0.0, 0.0, 0.4),
            Rgb::new(1.0, 1.0, 0.7),
            Rgb::new(0.9, 0.0, 1.0),
        ] {
            let table_rgb = SigmoidSpectrum::Poly(table.lookup(c)).to_rgb();
            let exact = fit_albedo(c).to_rgb();
            assert!(
                (table_rgb - exact).abs().max_element() <= 2e-3,
                "{c}: table {table_rgb}, exact fit {exact}"
            );
        }
        // The grid's own colours come back as closely as their fits.
        for (l, k, i, j) in [
            (0, 10, 3, 30),
            (1, 25, 39, 0),
            (2, 39, 20, 21),
            (0, 1, 5, 5),
        ] {
            let c =
                Rgb::from_array(crate::spectrum::fit::grid_colour(l, k, i, j).map(|v| v as f32));
            let back = SigmoidSpectrum::Poly(table.lookup(c)).to_rgb();
            assert!(
                (back - c).abs().max_element() < 1e-5,
                "{c} came back as {back}"
            );
        }
    }

    #[test]
    fn colours_outside_the_srgb_gamut_keep_their_colour() {
        // Rec. 2020 colours (a green, a blue) in linear sRGB leave the unit cube;
        // their spectra, from the Rec. 2020 table, reduce back to that sRGB colour.
        let to_srgb = crate::spectrum::ColorSpace::Rec2020;
        // (A bright saturated red such as (0.8, 0.15, 0.1) lies beyond what a sigmoid spectrum
        // reaches: it comes back 4 % redder, the nearest reachable colour.)
        for c in [[0.2f32, 0.6, 0.25], [0.1, 0.2, 0.8]] {
            let srgb = Rgb::from_array(to_srgb.rgb_to_srgb(c));
            assert!(
                srgb.min_element() < 0.0 || srgb.max_element() > 1.0,
                "{srgb}"
            );
            // (The fitter's own reduction: the independent one clamps negatives.)
            let s = albedo_spectrum(srgb);
            let back = s.to_rgb();
            assert!(
                (back - srgb).abs().max_element() < 5e-3,
                "{srgb} came back as {back}"
            );
            let (_, lo, hi) = reduce_independently(&s);
            assert!(lo >= 0.0 && hi <= 1.0);
            // As an unbounded colour: 2m · s(λ), s of rgb / 2m.
            let (scale, s) = unbounded_spectrum(srgb * 3.0);
            assert_eq!(scale, 6.0 * srgb.max_element());
            let back = s.to_rgb() * scale;
            assert!((back - srgb * 3.0).abs().max_element() < 2e-2, "{back}");
        }
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
