//! `lancer render model.gltf|model.glb`: a glTF model renders with no scene file, through its
//! own camera, Draco-compressed or not; a file lancer cannot read fails with exit status 2 and a message naming it.

use crate::common::*;
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
    let dir = ScratchDir::new("gltf-cameras");
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
fn a_draco_compressed_glb_renders() {
    let dir = ScratchDir::new("gltf-draco");
    let out = dir.join("box.exr");
    render_ok(&dir, &model("Box.glb"), &out, &["--spp", "4"]);
    let img = read_exr(&out);
    // The red cube (base colour (0.8, 0, 0)) fills the middle of the framed image: red there,
    // the grey sky (radiance 0.5 in every channel) at the top corners.
    let (w, h) = (img.width, img.height);
    let mean = |x0: f64, x1: f64, y0: f64, y1: f64| {
        let mut s = [0.0; 3];
        let mut n = 0.0;
        for y in (y0 * h as f64) as usize..(y1 * h as f64) as usize {
            for x in (x0 * w as f64) as usize..(x1 * w as f64) as usize {
                for (acc, v) in s.iter_mut().zip(img.rgb[y * w + x]) {
                    *acc += v;
                }
                n += 1.0;
            }
        }
        s.map(|v| v / n)
    };
    let centre = mean(0.4, 0.6, 0.4, 0.6);
    assert!(
        centre[0] > 0.1 && centre[1] < 0.2 * centre[0] && centre[2] < 0.2 * centre[0],
        "{centre:?}"
    );
    let corner = mean(0.0, 0.1, 0.0, 0.1);
    for c in corner {
        assert!((c - 0.5).abs() < 0.02, "{corner:?}");
    }
}

#[test]
fn an_unsupported_gltf_fails_with_a_clear_message() {
    let dir = ScratchDir::new("gltf-unsupported");
    let text = std::fs::read_to_string(model("Triangle/Triangle.gltf"))
        .unwrap()
        .replacen('{', r#"{ "extensionsRequired": ["EXT_not_in_lancer"],"#, 1);
    std::fs::write(dir.join("t.gltf"), text).unwrap();
    std::fs::copy(
        model("Triangle/simpleTriangle.bin"),
        dir.join("simpleTriangle.bin"),
    )
    .unwrap();
    let o = run_in(&dir, &["render", "t.gltf", "-o", "x.png", "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("t.gltf") && err.contains("EXT_not_in_lancer"),
        "{err}"
    );
    assert!(!dir.join("x.png").exists());
}
