//! bdpt's `visualizeweights` and `visualizestrategies` through `lancer render`: one EXR per
//! strategy beside the output under pbrt-v4's names, the weighted ones adding up to the
//! image, and none for a part of a split render; the film's `maxcomponentvalue` does not clamp
//! them, as pbrt-v4's.

use crate::common::{Img, ScratchDir, read_exr, run_in};
use std::path::Path;

/// A grey floor under a small area light, 12 × 8 pixels, bdpt to depth 1.
fn scene(flag: &str) -> String {
    format!(
        r#"LookAt 0 2 3  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
Film "rgb" "integer xresolution" [12] "integer yresolution" [8]
Sampler "independent" "integer pixelsamples" [4]
Integrator "bdpt" "integer maxdepth" [1] "bool {flag}" true
WorldBegin
Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
Shape "trianglemesh" "point3 P" [-4 0 4  4 0 4  4 0 -4  -4 0 -4] "integer indices" [0 1 2 0 2 3]
AttributeBegin
  AreaLightSource "diffuse" "rgb L" [4 4 4]
  Shape "trianglemesh" "point3 P" [-0.5 3 -0.5  0.5 3 -0.5  0.5 3 0.5  -0.5 3 0.5] "integer indices" [0 1 2 0 2 3]
AttributeEnd
"#
    )
}

const NAMES: [&str; 4] = [
    "bdpt_d00_s00_t02.exr",
    "bdpt_d01_s00_t03.exr",
    "bdpt_d01_s01_t02.exr",
    "bdpt_d01_s02_t01.exr",
];

fn render(dir: &Path, flag: &str, extra: &[&str]) -> String {
    std::fs::write(dir.join("s.pbrt"), scene(flag)).unwrap();
    let mut args = vec!["render", "s.pbrt", "--quiet", "--threads", "2"];
    args.extend_from_slice(extra);
    let o = run_in(dir, &args);
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{e}");
    e
}

/// Adds `b` to `a`, pixel by pixel.
fn add(a: &mut [[f64; 3]], b: &Img) {
    for (s, p) in a.iter_mut().zip(&b.rgb) {
        for c in 0..3 {
            s[c] += p[c];
        }
    }
}

#[test]
fn strategy_images_are_written_beside_the_output_and_add_up_to_it() {
    let dir = ScratchDir::new("bdpt-strategies");
    std::fs::create_dir_all(dir.join("out")).unwrap();
    let e = render(&dir, "visualizeweights", &["-o", "out/img.exr"]);
    assert!(!e.contains("warning"), "{e}");
    let image = read_exr(&dir.join("out/img.exr"));
    assert!(image.rgb.iter().any(|p| p[1] > 0.0));
    let mut sum = vec![[0.0f64; 3]; image.rgb.len()];
    for name in NAMES {
        assert!(
            !dir.join(name).exists(),
            "{name} written in the working folder"
        );
        let img = read_exr(&dir.join("out").join(name));
        assert_eq!((img.width, img.height), (12, 8), "{name}");
        add(&mut sum, &img);
    }
    for (s, p) in sum.iter().zip(&image.rgb) {
        for c in 0..3 {
            assert!(
                (s[c] - p[c]).abs() <= 1e-4 * p[c].abs() + 1e-6,
                "{s:?} vs {p:?}"
            );
        }
    }
    // Unweighted: each depth-1 strategy alone estimates all the light of depth 1, so their
    // sum is about three times the image (the camera does not see the light: no depth 0).
    render(&dir, "visualizestrategies", &["-o", "out/img.exr"]);
    let mut sum = vec![[0.0f64; 3]; image.rgb.len()];
    for name in &NAMES[1..] {
        add(&mut sum, &read_exr(&dir.join("out").join(name)));
    }
    let total = |v: &[[f64; 3]]| v.iter().map(|p| p[1]).sum::<f64>();
    let ratio = total(&sum) / total(&image.rgb);
    assert!(
        (ratio - 3.0).abs() < 0.6,
        "unweighted sum / image = {ratio}"
    );
}

#[test]
fn a_part_of_a_split_render_writes_no_strategy_images() {
    let dir = ScratchDir::new("bdpt-strategies-part");
    let e = render(
        &dir,
        "visualizeweights",
        &["-o", "p0.exr", "--split", "0/2", "--split-by", "samples"],
    );
    assert!(e.contains("strategy images"), "{e}");
    for name in NAMES {
        assert!(!dir.join(name).exists(), "{name}");
    }
}

/// pbrt-v4 makes its strategy films without the scene film's `maxcomponentvalue` (their
/// `RGBFilm`s keep its default, infinity): the scene film's clamp changes the image, not the
/// strategy images, which then add up to more than the clamped image.
#[test]
fn maxcomponentvalue_clamps_the_image_not_the_strategy_images() {
    let dir = ScratchDir::new("bdpt-strategies-clamp");
    std::fs::create_dir_all(dir.join("free")).unwrap();
    std::fs::create_dir_all(dir.join("clamped")).unwrap();
    render(&dir, "visualizeweights", &["-o", "free/img.exr"]);
    let clamped = scene("visualizeweights").replace(
        r#""integer yresolution" [8]"#,
        r#""integer yresolution" [8] "float maxcomponentvalue" [0.05]"#,
    );
    assert!(clamped.contains("maxcomponentvalue"));
    std::fs::write(dir.join("c.pbrt"), clamped).unwrap();
    let o = run_in(
        &dir,
        &[
            "render",
            "c.pbrt",
            "--quiet",
            "--threads",
            "2",
            "-o",
            "clamped/img.exr",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let total = |v: &[[f64; 3]]| v.iter().map(|p| p[1]).sum::<f64>();
    let free = read_exr(&dir.join("free/img.exr"));
    let image = read_exr(&dir.join("clamped/img.exr"));
    // The clamp bites: the clamped image holds clearly less light.
    assert!(
        total(&image.rgb) < 0.9 * total(&free.rgb),
        "clamped {} vs free {}",
        total(&image.rgb),
        total(&free.rgb)
    );
    let mut sum = vec![[0.0f64; 3]; image.rgb.len()];
    for name in NAMES {
        let a = read_exr(&dir.join("free").join(name));
        let b = read_exr(&dir.join("clamped").join(name));
        assert_eq!(a, b, "{name} changed by maxcomponentvalue");
        add(&mut sum, &b);
    }
    // They still add up to the unclamped image.
    for (s, p) in sum.iter().zip(&free.rgb) {
        assert!(
            (s[1] - p[1]).abs() <= 1e-4 * p[1].abs() + 1e-6,
            "{s:?} vs {p:?}"
        );
    }
    assert!(total(&sum) > total(&image.rgb) / 0.9);
}
