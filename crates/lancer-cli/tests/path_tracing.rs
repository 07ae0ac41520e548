//! The path tracer against other renderers: Mitsuba 3's Cornell box (`pt/cbox.pbrt`, the same
//! scene written as pbrt-v4) agrees with Mitsuba's reference, and a long render of it has no
//! NaN, no infinity and no pixel brighter than its light.

mod common;
use common::*;

/// 64 spp against Mitsuba 3 (`llvm_ad_rgb`, 4096 spp; both renderers are RGB, so the means
/// must agree within 1.5 %). Both images are box-filtered 4× (the stored reference already
/// is), which leaves the RMSE to catch misplaced light or shadows.
#[test]
fn cornell_box_agrees_with_mitsuba() {
    let dir = temp_dir("cbox");
    let out = dir.join("cbox.exr");
    render_ok(&dir, &data("pt/cbox.pbrt"), &out, &["--spp", "64"]);
    let img = read_exr(&out).shrink(4);
    let reference = read_exr(&data("references/pt/cbox-mitsuba.exr"));
    compare("cbox", &img, &reference, 0.015, 0.06);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The acceptance's long render: 512 × 512 at 256 spp.
#[test]
fn long_render_has_no_nan_and_nothing_brighter_than_the_light() {
    let dir = temp_dir("cbox-long");
    let out = dir.join("long.exr");
    render_ok(
        &dir,
        &data("pt/cbox.pbrt"),
        &out,
        &["--spp", "256", "--resolution", "512x512"],
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
    let _ = std::fs::remove_dir_all(&dir);
}
