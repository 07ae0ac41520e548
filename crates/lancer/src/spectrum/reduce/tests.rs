//! Tests of the CIE tables and of the spectrum → RGB rules.

use super::*;
use crate::math::luminance;

fn close(a: Rgb, b: Rgb, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

fn chromaticity(xyz: [f32; 3]) -> (f32, f32) {
    let s = xyz[0] + xyz[1] + xyz[2];
    (xyz[0] / s, xyz[1] / s)
}

/// D65 as a sampled spectrum, at an arbitrary scale.
fn d65_sampled(scale: f32) -> Spectrum {
    Spectrum::PiecewiseLinear {
        lambda: (0..cie::SAMPLES).map(|i| 360.0 + 5.0 * i as f32).collect(),
        values: cie::D65.iter().map(|&v| v as f32 * scale).collect(),
    }
}

#[test]
fn tables_integrate_to_the_cie_y_integral() {
    // ∫ ȳ dλ = 106.857 (the 1 nm CIE table gives 106.856895).
    let y5 = cie::CMF_1931.iter().map(|c| c[1]).sum::<f64>() * cie::LAMBDA_STEP;
    assert!((y5 - 106.857).abs() < 1e-3, "5 nm table: {y5}");
    let xyz = spectrum_to_xyz_unnormalised(&Spectrum::Constant(1.0));
    assert!((xyz[1] - 106.857).abs() < 1e-2, "1 nm sum: {}", xyz[1]);
    // The CIE 1931 functions have equal integrals: the equal-energy white is x = y = 1/3.
    assert!((xyz[0] / xyz[1] - 1.0).abs() < 1e-3, "{xyz:?}");
    assert!((xyz[2] / xyz[1] - 1.0).abs() < 1e-3, "{xyz:?}");
}

#[test]
fn tables_hold_the_published_values() {
    assert_eq!(cie_xyz(555.0)[1], 1.0);
    assert_eq!(cie_xyz(600.0), [1.0622, 0.631, 0.0008]);
    assert_eq!(cie_xyz(445.0)[2], 1.7826);
    assert_eq!(cie_d65(560.0), 100.0);
    assert_eq!(cie_d65(830.0), 60.3125);
    // Linear between entries, zero outside 360–830 nm.
    assert!((cie_xyz(557.5)[1] - 0.9975).abs() < 1e-6);
    assert_eq!(cie_xyz(359.0), [0.0; 3]);
    assert_eq!(cie_xyz(831.0), [0.0; 3]);
    assert_eq!(cie_d65(300.0), 0.0);
}

#[test]
fn d65_as_an_illuminant_is_white() {
    for scale in [1.0, 0.01, 37.0] {
        let rgb = spectrum_to_rgb(&d65_sampled(scale), SpectrumKind::Illuminant);
        assert!(close(rgb, Rgb::ONE, 1e-3), "scale {scale}: {rgb}");
    }
    let (x, y) = chromaticity(spectrum_to_xyz_unnormalised(&d65_sampled(1.0)));
    assert!(
        (x - 0.3127).abs() < 2e-4 && (y - 0.3290).abs() < 2e-4,
        "({x}, {y})"
    );
}

#[test]
fn the_srgb_matrix_maps_the_d65_white_to_one() {
    let rgb = xyz_to_srgb([0.95047, 1.0, 1.08883]);
    assert!(close(rgb, Rgb::ONE, 1e-4), "{rgb}");
}

#[test]
fn blackbody_at_2856_k_has_the_chromaticity_of_illuminant_a() {
    let (x, y) = chromaticity(spectrum_to_xyz_unnormalised(&Spectrum::Blackbody {
        kelvin: 2856.0,
    }));
    assert!(
        (x - 0.4476).abs() < 2e-3 && (y - 0.4074).abs() < 2e-3,
        "({x}, {y})"
    );
}

#[test]
fn illuminants_have_luminance_one() {
    for kelvin in [3000.0, 4500.0, 6500.0, 10000.0] {
        let rgb = spectrum_to_rgb(&Spectrum::Blackbody { kelvin }, SpectrumKind::Illuminant);
        assert!((luminance(rgb) - 1.0).abs() < 1e-3, "{kelvin} K: {rgb}");
    }
    let warm = spectrum_to_rgb(
        &Spectrum::Blackbody { kelvin: 3000.0 },
        SpectrumKind::Illuminant,
    );
    let cool = spectrum_to_rgb(
        &Spectrum::Blackbody { kelvin: 10000.0 },
        SpectrumKind::Illuminant,
    );
    assert!(warm.x > warm.y && warm.y > warm.z, "{warm}");
    assert!(cool.z > cool.x, "{cool}");
    // A very cold black body is out of gamut: its blue is clamped to 0, not negative.
    let ember = spectrum_to_rgb(
        &Spectrum::Blackbody { kelvin: 1000.0 },
        SpectrumKind::Illuminant,
    );
    assert!(ember.min_element() >= 0.0 && ember.x > 1.0, "{ember}");
}

#[test]
fn an_equal_energy_illuminant_is_pinkish_in_srgb() {
    // Illuminant E: X = Y = Z, which sRGB (white D65) sees as (1.2049, 0.9484, 0.9086).
    let e = spectrum_to_rgb(&Spectrum::Constant(3.0), SpectrumKind::Illuminant);
    assert!(close(e, Rgb::new(1.2049, 0.9484, 0.9086), 2e-3), "{e}");
}

#[test]
fn black_illuminants_stay_black() {
    assert_eq!(
        spectrum_to_rgb(&Spectrum::Constant(0.0), SpectrumKind::Illuminant),
        Rgb::ZERO
    );
    let infrared = Spectrum::PiecewiseLinear {
        lambda: vec![900.0, 1000.0],
        values: vec![1.0, 1.0],
    };
    assert_eq!(
        spectrum_to_rgb(&infrared, SpectrumKind::Illuminant),
        Rgb::ZERO
    );
}

#[test]
fn constant_spectra_are_exactly_grey() {
    let rgb = |c, kind| spectrum_to_rgb(&Spectrum::Constant(c), kind);
    assert_eq!(rgb(0.5, SpectrumKind::Albedo), Rgb::splat(0.5));
    assert_eq!(rgb(1.5, SpectrumKind::Albedo), Rgb::ONE);
    assert_eq!(rgb(1.5, SpectrumKind::Unbounded), Rgb::splat(1.5));
    assert_eq!(rgb(-1.0, SpectrumKind::Unbounded), Rgb::ZERO);
}

#[test]
fn flat_sampled_spectra_are_grey_under_d65() {
    let flat = Spectrum::PiecewiseLinear {
        lambda: vec![300.0, 900.0],
        values: vec![0.5, 0.5],
    };
    for kind in [SpectrumKind::Albedo, SpectrumKind::Unbounded] {
        let rgb = spectrum_to_rgb(&flat, kind);
        assert!(close(rgb, Rgb::splat(0.5), 1e-3), "{kind:?}: {rgb}");
    }
}

#[test]
fn coloured_albedos_are_clamped_to_the_unit_cube() {
    let red = Spectrum::PiecewiseLinear {
        lambda: vec![599.0, 600.0, 830.0],
        values: vec![0.0, 1.0, 1.0],
    };
    let rgb = spectrum_to_rgb(&red, SpectrumKind::Albedo);
    assert!(rgb.x > 0.5 && rgb.y < 0.2 && rgb.z < 0.1, "{rgb}");
    // A narrow green band lies outside the sRGB gamut: its red would be negative.
    let green = Spectrum::PiecewiseLinear {
        lambda: vec![515.0, 520.0, 525.0],
        values: vec![0.0, 20.0, 0.0],
    };
    let albedo = spectrum_to_rgb(&green, SpectrumKind::Albedo);
    assert_eq!(albedo.x, 0.0, "{albedo}");
    assert!(albedo.y > 0.0 && albedo.max_element() <= 1.0, "{albedo}");
    let unbounded = spectrum_to_rgb(&green, SpectrumKind::Unbounded);
    assert_eq!(unbounded.x, 0.0, "{unbounded}");
    assert!(unbounded.y > 1.0, "{unbounded}");
}

#[test]
fn precomputed_spectra_return_their_triples() {
    let p = PrecomputedRgb {
        unbounded: Rgb::new(0.1, 0.98, 1.2),
        illuminant: Rgb::new(0.3, 1.2, 1.4),
    };
    let s = Spectrum::Precomputed(p);
    assert_eq!(spectrum_to_rgb(&s, SpectrumKind::Unbounded), p.unbounded);
    assert_eq!(
        spectrum_to_rgb(&s, SpectrumKind::Albedo),
        Rgb::new(0.1, 0.98, 1.0)
    );
    assert_eq!(spectrum_to_rgb(&s, SpectrumKind::Illuminant), p.illuminant);
    // Its three-band stand-in, integrated like any sampled spectrum, gives the same triple.
    let sampled = Spectrum::PiecewiseLinear {
        lambda: (360..=830).map(|l| l as f32).collect(),
        values: (360..=830).map(|l| s.eval(l as f32)).collect(),
    };
    let rgb = spectrum_to_rgb(&sampled, SpectrumKind::Unbounded);
    assert!(close(rgb, p.unbounded, 1e-4), "{rgb}");
    // A grey triple has a nearly flat stand-in.
    let grey = Spectrum::Precomputed(PrecomputedRgb {
        unbounded: Rgb::splat(2.0),
        illuminant: Rgb::ONE,
    });
    for l in [400.0, 550.0, 700.0] {
        assert!(
            (grey.eval(l) - 2.0).abs() < 2e-3,
            "{l} nm: {}",
            grey.eval(l)
        );
    }
}

#[test]
fn spd_files_parse() {
    let s = parse_spd("# a comment\n400 0.1\n500 0.5 # trailing\n600 0.9\n").unwrap();
    assert_eq!(
        s,
        Spectrum::PiecewiseLinear {
            lambda: vec![400.0, 500.0, 600.0],
            values: vec![0.1, 0.5, 0.9],
        }
    );
    assert!((s.eval(450.0) - 0.3).abs() < 1e-6);
    assert_eq!(s.eval(399.0), 0.0);
    assert!(parse_spd("400 0.1 500").is_err());
    assert!(parse_spd("500 0.1 400 0.2").is_err());
    assert!(parse_spd("400 x").is_err());
    assert!(parse_spd("400 inf").is_err());
}
