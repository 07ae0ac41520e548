//! pbrt-v4's image area light (`AreaLightSource "diffuse" "string filename"`): the image read
//! beside the scene, `scale` and `power` applied as pbrt-v4 does, `L` refused beside it, and
//! the built light's radiance by uv and its power from the image's mean.

use crate::common::ScratchDir;
use lancer::Scene;
use lancer::light::{AreaLight, Light};
use lancer::math::{Rgb, Vec2};
use lancer_scene::load;
use std::f32::consts::PI;

/// A 2 × 1 image: left texel (1, 0, 0), right texel (0, 0, 3).
fn write_image(dir: &std::path::Path) {
    exr::prelude::write_rgb_file(dir.join("e.exr"), 2, 1, |x, _| {
        if x == 0 {
            (1.0, 0.0, 0.0)
        } else {
            (0.0, 0.0, 3.0)
        }
    })
    .unwrap();
}

/// A unit-square bilinear patch (area 1) with uv, emitting with `params`.
fn scene(dir: &std::path::Path, params: &str) -> Result<lancer_scene::LoadedScene, String> {
    let path = dir.join("s.pbrt");
    std::fs::write(
        &path,
        format!(
            "WorldBegin\nAreaLightSource \"diffuse\" {params}\nShape \"bilinearmesh\" \
             \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"integer indices\" [0 1 2 3] \
             \"point2 uv\" [0 0 1 0 0 1 1 1]\n"
        ),
    )
    .unwrap();
    load(&path).map_err(|e| e.to_string())
}

#[test]
fn image_area_lights_read_their_image_and_scale() {
    let dir = ScratchDir::new("area-image");
    write_image(&dir);
    let loaded = scene(&dir, r#""string filename" "e.exr" "float scale" 2"#).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let a = loaded.desc.shapes[0].area_light.expect("emits");
    assert_eq!(a.l, Rgb::splat(2.0));
    assert_eq!(a.image, Some(0));
    let scene = Scene::build(&loaded.desc).unwrap();
    let Light::Area(AreaLight { l, image, area, .. }) = &scene.lights()[0] else {
        panic!("{:?}", scene.lights()[0])
    };
    let image = image.as_ref().expect("an image");
    // Radiance 2·texel by uv: u = ¼ is the left texel's centre.
    assert_eq!(image.le(Vec2::new(0.25, 0.5)), Rgb::new(2.0, 0.0, 0.0));
    assert_eq!(image.le(Vec2::new(0.75, 0.5)), Rgb::new(0.0, 0.0, 6.0));
    // The light's colour for power and bounds: 2 · mean texel = (1, 0, 3); Φ = π·A·mean.
    assert_eq!(Rgb::from(*l), Rgb::new(1.0, 0.0, 3.0));
    assert!((scene.lights()[0].power() - PI * area * 4.0 / 3.0).abs() < 1e-5);
    // An image light has no constant colour: spectral mode uplifts each lookup.
    assert_eq!(scene.lights()[0].constant_colour(), None);
}

#[test]
fn image_area_lights_given_by_power_divide_by_the_mean_luminance() {
    let dir = ScratchDir::new("area-image-power");
    write_image(&dir);
    let loaded = scene(&dir, r#""string filename" "e.exr" "float power" 10"#).unwrap();
    let a = loaded.desc.shapes[0].area_light.expect("emits");
    // k = mean luminance = (Y(1, 0, 0) + Y(0, 0, 3)) / 2; the build divides by π·A (A = 1).
    let k = 0.5 * (lancer::math::luminance(Rgb::X) + lancer::math::luminance(Rgb::Z * 3.0));
    assert!(
        (a.l.x - 1.0 / k).abs() < 1e-4 * a.l.x,
        "{:?} vs {}",
        a.l,
        1.0 / k
    );
    let scene = Scene::build(&loaded.desc).unwrap();
    let Light::Area(AreaLight { image, .. }) = &scene.lights()[0] else {
        panic!()
    };
    // The emitted luminance, averaged over the image, times π·A is Φ.
    let img = image.as_ref().unwrap();
    let mean_y = lancer::math::luminance(img.mean() * img.scale);
    assert!((PI * mean_y - 10.0).abs() < 1e-3, "{}", PI * mean_y);
}

#[test]
fn image_area_lights_refuse_l_and_bad_images() {
    let dir = ScratchDir::new("area-image-errors");
    write_image(&dir);
    let e = scene(&dir, r#""string filename" "e.exr" "rgb L" [1 1 1]"#).unwrap_err();
    assert!(
        e.contains("s.pbrt:2:") && e.contains("either \"L\" or \"filename\", not both"),
        "{e}"
    );
    exr::prelude::write_rgb_file(dir.join("nan.exr"), 1, 1, |_, _| (f32::NAN, 0.0, 0.0)).unwrap();
    let e = scene(&dir, r#""string filename" "nan.exr""#).unwrap_err();
    assert!(e.contains("infinite or NaN values"), "{e}");
    let e = scene(&dir, r#""string filename" "missing.exr""#).unwrap_err();
    assert!(e.contains("missing.exr"), "{e}");
}

#[test]
fn area_lights_given_by_power_scale_l_by_power_over_pi_sides_area() {
    // pbrt-v4's DiffuseAreaLight with "power" and an RGB L: scale = Φ / (π · sides · A),
    // divided by the photometric value of L's illuminant only (not of its RGB), so the built
    // radiance is L · Φ / (π · sides · A) and the light emits Φ · Y(L) per primitive: Φ
    // exactly for an L of unit luminance.
    let dir = ScratchDir::new("area-power");
    for (params, rgb, sides) in [
        (r#""rgb L" [1 1 1] "float power" 10"#, Rgb::ONE, 1.0),
        (
            r#""rgb L" [4 2 1] "float power" 10"#,
            Rgb::new(4.0, 2.0, 1.0),
            1.0,
        ),
        (
            r#""rgb L" [1 1 1] "float power" 10 "bool twosided" true"#,
            Rgb::ONE,
            2.0,
        ),
    ] {
        let loaded = scene(&dir, params).unwrap();
        let scene = Scene::build(&loaded.desc).unwrap();
        let Light::Area(AreaLight { l, area, .. }) = &scene.lights()[0] else {
            panic!("{:?}", scene.lights()[0])
        };
        assert!((area - 1.0).abs() < 1e-6, "{area}");
        let want = rgb * (10.0 / (PI * sides * area));
        let l = Rgb::from(*l);
        assert!(
            (l - want).abs().max_element() < 1e-4 * want.max_element(),
            "{params}: {l:?} vs {want:?}"
        );
        let phi = PI * sides * area * lancer::math::luminance(l);
        let y = lancer::math::luminance(rgb);
        assert!((phi - 10.0 * y).abs() < 1e-3 * y, "{params}: {phi}");
    }
}
