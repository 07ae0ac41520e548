//! The path tracer against other renderers: Mitsuba 3's Cornell box (`pt/cbox.pbrt`, the same
//! scene written as pbrt-v4) agrees with Mitsuba's reference in RGB mode and with pbrt-v4's in
//! spectral mode, and a long render of it has no NaN, no infinity and no pixel brighter than
//! its light.

use crate::common::*;

/// 64 spp in RGB mode (`--rgb`) against Mitsuba 3 (`llvm_ad_rgb`, 4096 spp; both renderers
/// are RGB, so the means must agree within 1.5 %). Both images are box-filtered 4× (the stored reference already
/// is), which leaves the RMSE to catch misplaced light or shadows.
#[test]
fn cornell_box_agrees_with_mitsuba() {
    let dir = ScratchDir::new("cbox");
    let out = dir.join("cbox.exr");
    render_ok(&dir, &data("pt/cbox.pbrt"), &out, &["--spp", "64", "--rgb"]);
    let img = read_exr(&out).shrink(4);
    let reference = read_exr(&data("references/pt/cbox-mitsuba.exr"));
    compare("cbox", &img, &reference, 0.015, 0.06);
}

/// Spectral mode (the default; `--spectral` is accepted too) against pbrt-v4 (which renders spectrally; its 256 × 256 reference,
/// `references/pt/cbox-pbrt.exr`, is stored box-filtered 4× to 64 × 64). RGB mode misses
/// pbrt-v4's channel means by 2.5 % (red) and 3.2 % (blue), because saturated colours
/// multiplied over many bounces do not commute with the reduction to RGB; spectral mode must
/// be within 1 %, and the test checks that RGB mode does fail that bound, so that it tells the
/// two apart. Spectral: 256 × 256 at 64 spp, box-filtered like the reference; RGB, which only
/// needs its means: 64 × 64 at 64 spp.
#[test]
fn spectral_cornell_box_agrees_with_pbrt_v4() {
    let dir = ScratchDir::new("cbox-spectral");
    let reference = read_exr(&data("references/pt/cbox-pbrt.exr"));
    let spectral = dir.join("spectral.exr");
    render_ok(
        &dir,
        &data("pt/cbox.pbrt"),
        &spectral,
        &["--spp", "64", "--spectral"],
    );
    let img = read_exr(&spectral).shrink(4);
    // The wavelengths add colour noise (nrmse ≈ 0.1 on 64 × 64, twice the RGB image's),
    // which would hide a misplaced shadow: the shapes are compared on 4 × 4 blocks,
    // where the noise is a quarter of that.
    compare(
        "cbox spectral vs pbrt-v4, 4 x 4 blocks",
        &img.shrink(4),
        &reference.shrink(4),
        0.01,
        0.05,
    );
    let rgb = dir.join("rgb.exr");
    render_ok(
        &dir,
        &data("pt/cbox.pbrt"),
        &rgb,
        &["--spp", "64", "--resolution", "64x64", "--rgb"],
    );
    let rgb_mre = read_exr(&rgb).mean_rel_error(&reference);
    println!("cbox RGB vs pbrt-v4: mre {rgb_mre:.4}");
    assert!(
        rgb_mre > 0.02,
        "RGB mode should miss pbrt-v4 by > 2 %: {rgb_mre:.4}"
    );
}

/// The acceptance's long render: 512 × 512 at 256 spp, in RGB, where no channel of a pixel
/// can exceed the light's (a spectral sample's colour noise can push one channel past it).
#[test]
fn long_render_has_no_nan_and_nothing_brighter_than_the_light() {
    let dir = ScratchDir::new("cbox-long");
    let out = dir.join("long.exr");
    render_ok(
        &dir,
        &data("pt/cbox.pbrt"),
        &out,
        &["--spp", "256", "--resolution", "512x512", "--rgb"],
    );
    let img = read_exr(&out);
    assert_eq!((img.width, img.height), (512, 512));
    // The light's radiance, from the scene file. Its surface is also white diffuse, so seen
    // directly it shows L plus the room's light reflected, at most ρ·L (irradiance never
    // exceeds π·L when L is the brightest radiance present). A firefly would exceed that.
    let emitted = [18.387, 13.9873, 6.75357];
    let white = [0.885809, 0.698859, 0.666422];
    let light: Vec<f64> = (0..3).map(|c| emitted[c] * (1.0 + white[c])).collect();
    let mut on_light = 0;
    for p in &img.rgb {
        for c in 0..3 {
            assert!(p[c].is_finite(), "non-finite pixel {p:?}");
            assert!(p[c] >= 0.0, "negative pixel {p:?}");
            assert!(
                p[c] <= light[c] * 1.0001,
                "pixel {p:?} brighter than the light {light:?}"
            );
        }
        if p[0] >= emitted[0] {
            on_light += 1;
        }
    }
    // The light is seen directly, so some pixels are at least as bright as its emission.
    assert!(on_light > 100, "only {on_light} pixels show the light");
}
