//! `lancer bench scene`: its figures are all there, its render is the one `lancer render`
//! makes with the same options, and a render compared with itself has a relMSE of 0.

use crate::common::{ScratchDir, data, render_ok, run_in};

const OPTS: [&str; 6] = ["--spp", "4", "--seed", "3", "--resolution", "24x16"];

#[test]
fn bench_scene_reports_every_figure_and_relmse_zero_against_its_own_image() {
    let dir = ScratchDir::new("bench-scene");
    let scene = data("pt/cbox.pbrt");
    let reference = dir.join("ref.exr");
    render_ok(&dir, &scene, &reference, &OPTS);
    let mut args = vec!["bench", "scene", scene.to_str().unwrap()];
    args.extend_from_slice(&OPTS);
    args.extend_from_slice(&["--threads", "2", "--json", "--reference"]);
    args.push(reference.to_str().unwrap());
    let o = run_in(&dir, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(24), Some(16))
    );
    assert_eq!(
        (v["spp"].as_u64(), v["threads"].as_u64()),
        (Some(4), Some(2))
    );
    assert_eq!(v["mode"], "spectral");
    // Every camera sample, and at least one ray each.
    assert_eq!(v["samples"].as_u64(), Some(24 * 16 * 4));
    assert!(v["rays"].as_u64().unwrap() >= 24 * 16 * 4);
    for phase in ["parse", "build", "render"] {
        let t = v["time_s"][phase].as_f64().unwrap();
        assert!(t >= 0.0 && t.is_finite(), "{phase}: {t}");
    }
    assert!(v["rays_per_s"].as_f64().unwrap() > 0.0);
    assert!(v["samples_per_s"].as_f64().unwrap() > 0.0);
    // A process that rendered holds at least a mebibyte.
    assert!(v["peak_memory_bytes"].as_u64().unwrap() > 1 << 20);
    // The same options give the same image, bit for bit.
    assert_eq!(v["relmse"].as_f64(), Some(0.0));

    // Text: one line per figure.
    let mut args = vec!["bench", "scene", scene.to_str().unwrap()];
    args.extend_from_slice(&OPTS);
    let o = run_in(&dir, &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8_lossy(&o.stdout);
    for key in ["time ", "throughput ", "peak memory "] {
        assert!(text.contains(key), "{key} missing in:\n{text}");
    }
    assert!(text.contains("render ") && text.contains("M rays/s") && text.contains("M samples/s"));
    assert!(!text.contains("relmse"), "no reference, no relmse:\n{text}");

    // A reference of another size is refused with the sizes.
    let mut args = vec!["bench", "scene", scene.to_str().unwrap(), "--spp", "1"];
    args.extend_from_slice(&["--resolution", "8x8", "--reference"]);
    args.push(reference.to_str().unwrap());
    let o = run_in(&dir, &args);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("the reference is 24x16, the render 8x8"),
        "{err}"
    );
}
