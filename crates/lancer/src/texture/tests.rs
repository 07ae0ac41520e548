//! The texture families' lookups against pbrt-v4's formulas, float, RGB and at the sampled
//! wavelengths (a measured leaf sampled, not reduced to RGB).

use super::*;
use crate::math::{Rgb, Transform, Vec2, Vec3};
use crate::spectrum::dense::Measured;
use crate::spectrum::sampled::{ColourKind, SampledWavelengths};
use crate::spectrum::{Spectrum, SpectrumKind};

fn at(uv: Vec2, p: Vec3, n: Vec3) -> TexCoord {
    TexCoord {
        uv,
        p,
        n,
        ..TexCoord::default()
    }
}

#[test]
fn float_textures_follow_pbrt_v4s_formulas() {
    let floats = vec![
        // 0: bilerp v00 0.05, v01 1, v10 0.05, v11 1 (procedural.pbrt's "fade").
        FloatTexture::Bilerp(BilerpTexture {
            mapping: Mapping2D::default(),
            v: [0.05, 1.0, 0.05, 1.0],
        }),
        // 1: 3D checkerboard of 0.2-unit cells.
        FloatTexture::Checkerboard3D(Checkerboard3DTexture {
            mapping: Mapping3D {
                texture_from_world: Transform::scale(Vec3::splat(0.2)).unwrap().inverse(),
            },
            tex1: FloatTex::Const(1.0),
            tex2: FloatTex::Const(0.0),
        }),
        // 2: directionmix along +y of 1 and 0.
        FloatTexture::DirectionMix(DirectionMixTexture {
            tex1: FloatTex::Const(1.0),
            tex2: FloatTex::Const(0.0),
            dir: Vec3::Y,
        }),
        // 3: scale of texture 0 by 0: 0 without looking at it.
        FloatTexture::Scale(ScaleTexture {
            tex: FloatTex::Tex(0),
            scale: FloatTex::Const(0.0),
        }),
        // 4: 2D checker with uscale 4.
        FloatTexture::Checkerboard(CheckerboardTexture {
            mapping: UvMapping {
                su: 4.0,
                ..UvMapping::default()
            }
            .into(),
            tex1: FloatTex::Const(0.25),
            tex2: FloatTex::Const(0.75),
        }),
    ];
    let ev = TextureEval {
        floats: &floats,
        spectra: &[],
    };
    let f = |i, tc: &TexCoord| ev.float(FloatTex::Tex(i), tc);
    // Bilerp at (s, t) = (0.3, 0.5): 0.05 + 0.5·0.95 = 0.525.
    let tc = at(Vec2::new(0.3, 0.5), Vec3::ZERO, Vec3::Z);
    assert!((f(0, &tc) - 0.525).abs() < 1e-6);
    // (0.1, 0.1, 0.1) is cell (0, 0, 0): even; (0.3, 0.1, 0.1) is cell (1, 0, 0): odd;
    // (−0.1, −0.1, 0.1) is (−1, −1, 0): even.
    for (p, want) in [
        (Vec3::splat(0.1), 1.0),
        (Vec3::new(0.3, 0.1, 0.1), 0.0),
        (Vec3::new(-0.1, -0.1, 0.1), 1.0),
    ] {
        assert_eq!(f(1, &at(Vec2::ZERO, p, Vec3::Z)), want, "{p}");
    }
    // |n·dir| = cos 60° = ½ → ½·1 + ½·0.
    let n = Vec3::new(0.0, 0.5, 0.75f32.sqrt());
    assert!((f(2, &at(Vec2::ZERO, Vec3::ZERO, n)) - 0.5).abs() < 1e-6);
    assert_eq!(f(3, &tc), 0.0);
    // u = 0.3 → s = 1.2: odd column.
    assert_eq!(f(4, &tc), 0.75);
}

#[test]
fn spectrum_dots_draw_the_dot_value_inside() {
    let spectra = vec![SpectrumTexture::Dots(DotsTexture {
        mapping: Mapping2D::default(),
        dot: SpectrumTex::Const(Rgb::X),
        background: SpectrumTex::Const(Rgb::Y),
    })];
    let ev = TextureEval {
        floats: &[],
        spectra: &spectra,
    };
    let c = |u: f32, v: f32| {
        ev.spectrum(
            SpectrumTex::Tex(0),
            &at(Vec2::new(u, v), Vec3::ZERO, Vec3::Z),
        )
    };
    // Cell corners are always between the dots.
    assert_eq!(c(0.5, 0.5), Rgb::Y);
    let cells: Vec<Rgb> = (0..16).map(|i| c(i as f32, 0.0)).collect();
    assert!(cells.contains(&Rgb::X) && cells.contains(&Rgb::Y));
}

/// A ramp 0 at 300 nm to 1 at 800 nm: (λ − 300)/500.
fn ramp() -> Measured {
    let s = Spectrum::PiecewiseLinear {
        lambda: vec![300.0, 800.0],
        values: vec![0.0, 1.0],
    };
    Measured::new(&s, Rgb::splat(0.5), SpectrumKind::Albedo)
}

#[test]
fn a_measured_leaf_is_sampled_at_the_wavelengths_not_through_rgb() {
    let spectra = vec![
        // 0: checkerboard, the ramp on even cells, grey 0.25 on odd ones.
        SpectrumTexture::Checkerboard(CheckerboardTexture {
            mapping: Mapping2D::default(),
            tex1: SpectrumTex::Measured(ramp()),
            tex2: SpectrumTex::Const(Rgb::splat(0.25)),
        }),
        // 1: mix of the ramp and black, amount 0.25: 0.75 · ramp.
        SpectrumTexture::Mix(MixTexture {
            tex1: SpectrumTex::Measured(ramp()),
            tex2: SpectrumTex::Const(Rgb::ZERO),
            amount: FloatTex::Const(0.25),
        }),
        // 2: a checkerboard of constants only.
        SpectrumTexture::Checkerboard(CheckerboardTexture {
            mapping: Mapping2D::default(),
            tex1: SpectrumTex::Const(Rgb::ONE),
            tex2: SpectrumTex::Const(Rgb::ZERO),
        }),
    ];
    let ev = TextureEval {
        floats: &[],
        spectra: &spectra,
    };
    let lambda = SampledWavelengths::sample_visible(0.3);
    let want = (lambda.lambda - glam::Vec4::splat(300.0)) / 500.0;
    let tc = |u: f32| TexCoord {
        uv: Vec2::new(u, 0.5),
        n: Vec3::Z,
        ..TexCoord::default()
    };
    let at = |i, u| ev.spectrum_sampled(SpectrumTex::Tex(i), &tc(u), &lambda, ColourKind::Albedo);
    // u = 0.5: cell (0, 0), even: the ramp itself.
    assert!(
        (at(0, 0.5) - want).abs().max_element() < 2e-3,
        "{}",
        at(0, 0.5)
    );
    // u = 1.5: cell (1, 0), odd: uplifted grey 0.25, flat.
    let grey = at(0, 1.5);
    assert!(
        (grey - glam::Vec4::splat(0.25)).abs().max_element() < 2e-3,
        "{grey}"
    );
    assert!((at(1, 0.5) - 0.75 * want).abs().max_element() < 2e-3);
    assert!(ev.has_measured(SpectrumTex::Tex(0)) && ev.has_measured(SpectrumTex::Tex(1)));
    assert!(!ev.has_measured(SpectrumTex::Tex(2)));
    // What a material reads (`spectrum_at`) is the ramp, not the uplift of the tree's RGB
    // value (the ramp's RGB is grey 0.5: a flat 0.5 across the wavelengths).
    let read = ev.spectrum_at(SpectrumTex::Tex(0), &tc(0.5), &lambda, ColourKind::Albedo);
    assert_eq!(read, at(0, 0.5));
    let through_rgb = ev.uplifted(SpectrumTex::Tex(0), &tc(0.5), &lambda, ColourKind::Albedo);
    assert!((through_rgb - glam::Vec4::splat(0.5)).abs().max_element() < 2e-3);
    assert!(
        (read - through_rgb).abs().max_element() > 0.1,
        "{read} {through_rgb}"
    );
    // A tree of constants only reads as its uplift.
    let plain = ev.spectrum_at(SpectrumTex::Tex(2), &tc(0.5), &lambda, ColourKind::Albedo);
    assert_eq!(
        plain,
        ev.uplifted(SpectrumTex::Tex(2), &tc(0.5), &lambda, ColourKind::Albedo)
    );
}
