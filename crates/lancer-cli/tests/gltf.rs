//! `lancer render model.gltf|model.glb`: a glTF model renders with no scene file, through its
//! own camera; a file lancer cannot read fails with exit status 2 and a message naming it.

mod common;
use common::*;
use std::path::PathBuf;

fn model(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../lancer-scene/tests/data/gltf")
        .join(rel)
}

/// Mean of the pixels in the fractions [x0, x1) × [y0, y1) of the image (y down).
fn region_mean(img: &Img, x0: f64, x1: f64, y0: f64, y1: f64) -> f64 {
    let (w, h) = (img.width as f64, img.height as f64);
    let (mut s, mut n) = (0.0, 0);
    for y in (y0 * h) as usize..(y1 * h) as usize {
        for x in (x0 * w) as usize..(x1 * w) as usize {
            let p = img.rgb[y * img.width + x];
            s += (p[0] + p[1] + p[2]) / 3.0;
            n += 1;
        }
    }
    s / n as f64
}

#[test]
fn a_gltf_model_renders_through_its_own_camera() {
    let dir = temp_dir("gltf-cameras");
    let out = dir.join("cameras.exr");
    render_ok(&dir, &model("Cameras/Cameras.gltf"), &out, &["--spp", "4"]);
    let img = read_exr(&out);
    // The file's camera asks for a square image.
    assert_eq!(img.width, img.height);
    // Seen from (0.5, 0.5, 3): the tilted unit square fills the lower middle of the image
    // (it spans y from 0 to 0.71, below the camera's height), lit by the key light; the sky
    // (radiance 0.5) is everywhere else. The square's light grey under sky and key light is
    // brighter than the sky.
    let square = region_mean(&img, 0.4, 0.6, 0.55, 0.7);
    let sky_top = region_mean(&img, 0.0, 1.0, 0.0, 0.15);
    let sky_side = region_mean(&img, 0.0, 0.15, 0.5, 0.7);
    assert!((sky_top - 0.5).abs() < 0.02, "{sky_top}");
    assert!((sky_side - 0.5).abs() < 0.02, "{sky_side}");
    assert!(square > sky_top + 0.1, "square {square} sky {sky_top}");
}

#[test]
fn an_unsupported_gltf_fails_with_a_clear_message() {
    let dir = temp_dir("gltf-draco");
    let file = model("Box.glb");
    let o = run_in(
        &dir,
        &["render", file.to_str().unwrap(), "-o", "x.png", "--quiet"],
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("Box.glb") && err.contains("KHR_draco_mesh_compression"),
        "{err}"
    );
    assert!(!dir.join("x.png").exists());
}
