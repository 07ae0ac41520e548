//! pbrt-v4's `LightSource "infinite" "string filename"`: the image read beside the scene, its
//! layout checked, `scale` and `illuminance` applied as pbrt-v4 does, and the light built.

use crate::common::ScratchDir;
use lancer::Scene;
use lancer::light::{EnvMapping, Light};
use lancer::math::{PackedRgb, Vec3};
use lancer::scene::desc::LightDesc;
use lancer_scene::load;

fn write_exr(path: &std::path::Path, w: usize, h: usize, f: impl Fn(usize, usize) -> f32 + Sync) {
    exr::prelude::write_rgb_file(path, w, h, |x, y| {
        let v = f(x, y);
        (v, 0.5 * v, 0.25 * v)
    })
    .unwrap();
}

fn scene_with(dir: &std::path::Path, light: &str) -> Result<lancer_scene::LoadedScene, String> {
    let path = dir.join("s.pbrt");
    std::fs::write(
        &path,
        format!("WorldBegin\n{light}\nShape \"sphere\" \"float radius\" 1\n"),
    )
    .unwrap();
    load(&path).map_err(|e| e.to_string())
}

#[test]
fn infinite_lights_read_their_image() {
    let dir = ScratchDir::new("read");
    write_exr(&dir.join("sky.exr"), 8, 8, |x, y| (x + y) as f32);
    let loaded = scene_with(
        &dir,
        r#"LightSource "infinite" "string filename" "sky.exr" "float scale" 2"#,
    )
    .unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let LightDesc::ImageInfinite(lancer::light::ImageInfiniteDesc { l, image, .. }) =
        &loaded.desc.lights[0]
    else {
        panic!("{:?}", loaded.desc.lights)
    };
    assert_eq!((image.width, image.height), (8, 8));
    assert_eq!(image.texels[8 + 3], PackedRgb::new(4.0, 2.0, 1.0));
    assert_eq!(*l, Vec3::splat(2.0));

    // Built: an importance-sampled image light that escaping rays see.
    let scene = Scene::build(&loaded.desc).unwrap();
    let Light::ImageInfinite(light) = &scene.lights()[0] else {
        panic!("{:?}", scene.lights()[0])
    };
    assert_eq!(light.mapping(), EnvMapping::EqualArea);
    assert_eq!(scene.infinite_lights(), [0]);
    // Every corner of the equal-area square is −z; with x, y = +0 it is the corner (1, 1),
    // the bright texel (7, 7): Le there is 2·(14, 7, 3.5). Straight up is the centre.
    assert_eq!(
        scene.lights()[0].le(Vec3::new(0.0, 0.0, -1.0)),
        Vec3::new(28.0, 14.0, 7.0)
    );
    assert_eq!(scene.lights()[0].le(Vec3::Z), Vec3::new(16.0, 8.0, 4.0));
}

#[test]
fn illuminance_scales_as_pbrt_does() {
    let dir = ScratchDir::new("illum");
    write_exr(&dir.join("flat.exr"), 64, 64, |_, _| 1.0);
    write_exr(&dir.join("latlong.exr"), 64, 32, |_, _| 1.0);
    for f in ["flat.exr", "latlong.exr"] {
        let loaded = scene_with(
            &dir,
            &format!(r#"LightSource "infinite" "string filename" "{f}" "float illuminance" 10"#),
        )
        .unwrap();
        let LightDesc::ImageInfinite(lancer::light::ImageInfiniteDesc { l, .. }) =
            &loaded.desc.lights[0]
        else {
            panic!()
        };
        // pbrt-v4 takes the image's illuminance to be 2π/N·Σ Y cos θ over the upper
        // texels: for this map Y = 0.2127 + 0.7152·0.5 + 0.0722·0.25 = 0.5883, and the sum is
        // π/2·Y, so the scale is 10/(π/2·Y) = 10.82.
        let y = 0.212671 + 0.715160 * 0.5 + 0.072169 * 0.25;
        let want = 10.0 / (std::f32::consts::FRAC_PI_2 * y);
        assert!((l.x - want).abs() < 0.01 * want, "{f}: {} vs {want}", l.x);
    }
}

#[test]
fn bad_environment_images_are_errors_naming_the_file() {
    let dir = ScratchDir::new("bad");
    write_exr(&dir.join("wide.exr"), 12, 4, |_, _| 1.0);
    let e = scene_with(
        &dir,
        r#"LightSource "infinite" "string filename" "wide.exr""#,
    )
    .unwrap_err();
    assert!(e.contains("wide.exr") && e.contains("12×4"), "{e}");
    let e = scene_with(
        &dir,
        r#"LightSource "infinite" "string filename" "none.exr""#,
    )
    .unwrap_err();
    assert!(e.contains("none.exr") && e.contains("s.pbrt:2"), "{e}");
    let e = scene_with(
        &dir,
        r#"LightSource "infinite" "string filename" "wide.exr" "rgb L" [1 1 1]"#,
    )
    .unwrap_err();
    assert!(e.contains("not both"), "{e}");
}
