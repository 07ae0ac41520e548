//! pbrt-v4's `gbuffer` film through `lancer render`: the EXR's 25 channels and their order,
//! hand-checkable values on a plane at a known depth (camera and world space), the header
//! attributes, the colour identical to an `rgb` film's, and the outputs it refuses.

use crate::common::{ScratchDir, run_in};
use exr::prelude::{FlatSamples, read_all_flat_layers_from_file};
use std::path::Path;

/// A layer of the EXR read back, every channel flat.
type Flat = exr::prelude::Layer<exr::prelude::AnyChannels<FlatSamples>>;

/// A plane z = 3 (world) facing a camera at z = 1 (camera space is the world moved by
/// −1 in z), 4 × 4 pixels over a 90° field of view, 16 unjittered strata per pixel and a box
/// filter (so each pixel's samples average to its centre), a diffuse reflectance of 0.5, uv
/// running over [−10, 10]² as (x + 10)/20, (y + 10)/20; `film` is the `Film` line.
fn scene(film: &str) -> String {
    format!(
        r#"Translate 0 0 -1
Camera "perspective" "float fov" [90]
{film}
Sampler "stratified" "integer xsamples" [4] "integer ysamples" [4] "bool jitter" false
PixelFilter "box" "float xradius" [0.5] "float yradius" [0.5]
WorldBegin
LightSource "distant" "point3 from" [0 0 0] "point3 to" [0 0 1] "rgb L" [2 2 2]
Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
Shape "trianglemesh" "point3 P" [-10 -10 3  10 -10 3  10 10 3  -10 10 3]
  "integer indices" [0 1 2 0 2 3] "point2 uv" [0 0 1 0 1 1 0 1]
"#
    )
}

/// One channel's values as f32, row-major.
fn channel(layer: &Flat, name: &str) -> Vec<f32> {
    let c = layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.eq(name))
        .unwrap_or_else(|| panic!("no channel {name}"));
    match &c.sample_data {
        FlatSamples::F16(v) => v.iter().map(|h| h.to_f32()).collect(),
        FlatSamples::F32(v) => v.clone(),
        FlatSamples::U32(_) => panic!("{name} is UINT"),
    }
}

fn render(dir: &Path, name: &str, film: &str, out: &str) -> std::process::Output {
    let path = dir.join(name);
    std::fs::write(&path, scene(film)).unwrap();
    run_in(
        dir,
        &["render", path.to_str().unwrap(), "-o", out, "--quiet"],
    )
}

fn read(path: &Path) -> Flat {
    let img = read_all_flat_layers_from_file(path).unwrap();
    img.layer_data.into_iter().next().unwrap()
}

#[test]
fn gbuffer_channels_hold_the_plane_seen_by_each_pixel() {
    let dir = ScratchDir::new("gbuffer-plane");
    let o = render(
        &dir,
        "g.pbrt",
        r#"Film "gbuffer" "integer xresolution" 4 "integer yresolution" 4"#,
        "g.exr",
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let layer = read(&dir.join("g.exr"));
    // pbrt-v4's 25 channels, in the file's order (OpenEXR sorts them by name), as half floats.
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    let mut expected: Vec<String> = lancer::gbuffer::CHANNELS
        .iter()
        .map(|s| s.to_string())
        .collect();
    expected.sort();
    assert_eq!(names, expected);
    assert_eq!(
        names[..6],
        ["Albedo.B", "Albedo.G", "Albedo.R", "B", "G", "N.X"]
    );
    assert!(
        layer
            .channel_data
            .list
            .iter()
            .all(|c| matches!(c.sample_data, FlatSamples::F16(_)))
    );
    // Pixel (i, j) looks through screen point (−0.75 + 0.5i, 0.75 − 0.5j); the plane is at
    // camera depth 2, so P = 2·screen point, z = 2.
    let (px, py, pz) = (
        channel(&layer, "P.X"),
        channel(&layer, "P.Y"),
        channel(&layer, "P.Z"),
    );
    let (u, v) = (channel(&layer, "u"), channel(&layer, "v"));
    for j in 0..4 {
        for i in 0..4 {
            let k = j * 4 + i;
            let (x, y) = (
                2.0 * (-0.75 + 0.5 * i as f32),
                2.0 * (0.75 - 0.5 * j as f32),
            );
            assert!((px[k] - x).abs() < 2e-3, "P.X[{i},{j}] = {}", px[k]);
            assert!((py[k] - y).abs() < 2e-3, "P.Y[{i},{j}] = {}", py[k]);
            assert_eq!(pz[k], 2.0);
            // World x = camera x; u = (x + 10)/20.
            assert!((u[k] - (x + 10.0) / 20.0).abs() < 1e-3, "u = {}", u[k]);
            assert!((v[k] - (y + 10.0) / 20.0).abs() < 1e-3, "v = {}", v[k]);
        }
    }
    // The normal faces the camera: −z, geometric and shading; the plane keeps its depth.
    for (name, want) in [
        ("N.X", 0.0),
        ("N.Y", 0.0),
        ("N.Z", -1.0),
        ("Ns.X", 0.0),
        ("Ns.Y", 0.0),
        ("Ns.Z", -1.0),
        ("dzdx", 0.0),
        ("dzdy", 0.0),
        ("Albedo.R", 0.5),
        ("Albedo.G", 0.5),
        ("Albedo.B", 0.5),
    ] {
        for (k, got) in channel(&layer, name).iter().enumerate() {
            assert!((got - want).abs() < 1e-3, "{name}[{k}] = {got}, not {want}");
        }
    }
    // Header: worldToCamera is the camera's Translate 0 0 −1, row-major (translation in the
    // last column); worldToNDC exists for a perspective camera; samplesPerPixel, a render
    // time.
    let a = &layer.attributes;
    let m = a.world_to_camera.expect("worldToCamera");
    assert_eq!(m[3], 0.0);
    assert_eq!(m[11], -1.0);
    assert_eq!((m[0], m[5], m[10], m[15]), (1.0, 1.0, 1.0, 1.0));
    assert!(a.world_to_normalized_device.is_some());
    let other = |k: &str| a.other.get(&exr::prelude::Text::from(k)).cloned();
    assert_eq!(
        other("samplesPerPixel"),
        Some(exr::prelude::AttributeValue::I32(16))
    );
    assert!(matches!(
        other("renderTimeSeconds"),
        Some(exr::prelude::AttributeValue::F32(t)) if t >= 0.0
    ));
}

#[test]
fn world_space_gbuffer_and_colour_identical_to_an_rgb_film() {
    let dir = ScratchDir::new("gbuffer-world");
    let o = render(
        &dir,
        "w.pbrt",
        r#"Film "gbuffer" "integer xresolution" 4 "integer yresolution" 4 "string coordinatesystem" "world" "bool savefp16" false"#,
        "w.exr",
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let g = read(&dir.join("w.exr"));
    assert!(matches!(
        g.channel_data.list[0].sample_data,
        FlatSamples::F32(_)
    ));
    // World space: the plane is at z = 3, and its normal still faces the camera.
    assert!(channel(&g, "P.Z").iter().all(|&z| (z - 3.0).abs() < 1e-5));
    assert!(channel(&g, "N.Z").iter().all(|&z| (z + 1.0).abs() < 1e-6));
    // The colour is an rgb film's, bit for bit.
    let o = render(
        &dir,
        "r.pbrt",
        r#"Film "rgb" "integer xresolution" 4 "integer yresolution" 4"#,
        "r.exr",
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let r = read(&dir.join("r.exr"));
    for c in ["R", "G", "B"] {
        let (a, b) = (channel(&g, c), channel(&r, c));
        assert!(a.iter().any(|&x| x > 0.0));
        assert_eq!(a, b, "channel {c}");
    }
    // Spectral samples of a grey surface still differ (their wavelengths do): a positive
    // variance, and a relative variance of variance / mean.
    assert!(channel(&g, "Variance.G").iter().all(|&x| x > 0.0));
}

#[test]
fn gbuffer_refuses_png_and_split_renders() {
    let dir = ScratchDir::new("gbuffer-refusals");
    let film = r#"Film "gbuffer" "integer xresolution" 4 "integer yresolution" 4"#;
    let o = render(&dir, "g.pbrt", film, "g.png");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        e.contains("g.png: a gbuffer film is written only as OpenEXR (.exr)"),
        "{e}"
    );
    assert!(!dir.join("g.png").exists());
    let scene = dir.join("g.pbrt");
    for extra in [
        ["--split", "1/2"],
        ["--samples", "0..8"],
        ["--checkpoint-every", "1"],
    ] {
        let mut args = vec!["render", scene.to_str().unwrap(), "-o", "p.exr", "--quiet"];
        args.extend_from_slice(&extra);
        let o = run_in(&dir, &args);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?}");
        assert!(
            e.contains("a gbuffer film cannot be rendered as") && e.contains("g-buffer channels"),
            "{extra:?}: {e}"
        );
    }
}
