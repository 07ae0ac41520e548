//! pbrt-v4's `spectral` film through `lancer render`: the EXR's colour and bucket channels
//! with pbrt-v4's names, half floats by default, buckets that split a sample's wavelengths
//! exactly, and what it refuses (an RGB render, PNG output, renders in pieces).

use crate::common::{ScratchDir, run_in};
use exr::prelude::{FlatSamples, read_all_flat_layers_from_file};
use std::path::Path;

/// A grey diffuse plane lit head-on by a distant light, 4 × 4 pixels; `film` is the `Film`
/// line.
fn scene(film: &str) -> String {
    format!(
        r#"Camera "perspective" "float fov" [90]
{film}
Sampler "zsobol" "integer pixelsamples" [16]
WorldBegin
LightSource "distant" "point3 from" [0 0 0] "point3 to" [0 0 1] "rgb L" [2 2 2]
Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
Shape "trianglemesh" "point3 P" [-10 -10 3  10 -10 3  10 10 3  -10 10 3]
  "integer indices" [0 1 2 0 2 3]
"#
    )
}

fn render(dir: &Path, name: &str, film: &str, extra: &[&str]) -> std::process::Output {
    let path = dir.join(name);
    std::fs::write(&path, scene(film)).unwrap();
    let mut args = vec!["render", path.to_str().unwrap(), "--quiet"];
    args.extend_from_slice(extra);
    run_in(dir, &args)
}

/// Every channel of the file's first layer: name, values, and whether they are half floats.
fn channels(path: &Path) -> Vec<(String, Vec<f32>, bool)> {
    let img = read_all_flat_layers_from_file(path).unwrap();
    let layer = img.layer_data.into_iter().next().unwrap();
    layer
        .channel_data
        .list
        .iter()
        .map(|c| {
            let (v, half) = match &c.sample_data {
                FlatSamples::F16(v) => (v.iter().map(|h| h.to_f32()).collect(), true),
                FlatSamples::F32(v) => (v.clone(), false),
                FlatSamples::U32(_) => panic!("UINT channel"),
            };
            (c.name.to_string(), v, half)
        })
        .collect()
}

#[test]
fn spectral_film_writes_pbrt_v4_bucket_channels() {
    let dir = ScratchDir::new("spectral-film");
    let two = r#"Film "spectral" "integer xresolution" 4 "integer yresolution" 4
        "integer nbuckets" 2 "float lambdamin" 400 "float lambdamax" 700 "bool savefp16" false"#;
    let o = render(&dir, "two.pbrt", two, &["-o", "two.exr"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let c = channels(&dir.join("two.exr"));
    let mut names: Vec<&str> = c.iter().map(|c| c.0.as_str()).collect();
    names.sort();
    // Bucket centres 475 and 625 nm, '.' written ',' as pbrt-v4 does.
    assert_eq!(names, ["B", "G", "R", "S0.475,000nm", "S0.625,000nm"]);
    assert!(
        c.iter().all(|c| !c.2),
        "savefp16 false writes 32-bit floats"
    );
    let get =
        |c: &[(String, Vec<f32>, bool)], n: &str| c.iter().find(|c| c.0 == n).unwrap().1.clone();
    // One bucket over the same range: the four stratified wavelengths of a sample fall two in
    // each half, so the single bucket's mean is exactly the mean of the two halves'.
    let one = r#"Film "spectral" "integer xresolution" 4 "integer yresolution" 4
        "integer nbuckets" 1 "float lambdamin" 400 "float lambdamax" 700 "bool savefp16" false"#;
    let o = render(&dir, "one.pbrt", one, &["-o", "one.exr"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let c1 = channels(&dir.join("one.exr"));
    let (a, b, all) = (
        get(&c, "S0.475,000nm"),
        get(&c, "S0.625,000nm"),
        get(&c1, "S0.550,000nm"),
    );
    for i in 0..16 {
        assert!(a[i] > 0.0 && b[i] > 0.0);
        assert!(
            (all[i] - 0.5 * (a[i] + b[i])).abs() < 1e-5 * all[i],
            "{} vs {} {}",
            all[i],
            a[i],
            b[i]
        );
    }
    // The default: 16 buckets over 360–830 nm, half floats.
    let o = render(
        &dir,
        "d.pbrt",
        r#"Film "spectral" "integer xresolution" 4 "integer yresolution" 4"#,
        &["-o", "d.exr"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let c = channels(&dir.join("d.exr"));
    assert_eq!(c.len(), 19);
    assert!(c.iter().all(|c| c.2));
    assert!(c.iter().any(|c| c.0 == "S0.374,688nm"));
}

#[test]
fn spectral_film_refuses_rgb_mode_png_and_pieces() {
    let dir = ScratchDir::new("spectral-film-refusals");
    let film = r#"Film "spectral" "integer xresolution" 4 "integer yresolution" 4"#;
    let o = render(&dir, "s.pbrt", film, &["-o", "s.exr", "--rgb"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(e.contains("needs the spectral mode: drop --rgb"), "{e}");
    let o = render(&dir, "s.pbrt", film, &["-o", "s.png"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        e.contains("s.png: a spectral film is written only as OpenEXR (.exr)"),
        "{e}"
    );
    for extra in [
        ["--split", "1/2"],
        ["--samples", "0..8"],
        ["--checkpoint-every", "1"],
    ] {
        let mut args = vec!["-o", "p.exr"];
        args.extend_from_slice(&extra);
        let o = render(&dir, "s.pbrt", film, &args);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?}");
        assert!(
            e.contains("a spectral film cannot be rendered as") && e.contains("spectral channels"),
            "{extra:?}: {e}"
        );
    }
    assert!(!dir.join("s.png").exists() && !dir.join("p.exr").exists());
}
