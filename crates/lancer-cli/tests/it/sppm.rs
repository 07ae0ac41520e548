//! pbrt-v4's `sppm` through `lancer render`: read without a warning, a split by tiles merges to
//! the single render's exact pixels, `--stats json` counts the photons, and what it refuses (a
//! range of samples, checkpoints at intervals, the denoiser).

use crate::common::{ScratchDir, read_exr, run_in};
use std::path::Path;

/// A glass sphere on a grey floor under a distant light, 16 × 40 pixels (three tile rows).
pub const SCENE: &str = r#"LookAt 0 2 3  0 0.3 0  0 1 0
Camera "perspective" "float fov" [40]
Film "rgb" "integer xresolution" [16] "integer yresolution" [40]
Sampler "zsobol" "integer pixelsamples" [4]
Integrator "sppm" "integer maxdepth" [6] "integer photonsperiteration" [4000] "float radius" [0.1]
WorldBegin
LightSource "distant" "point3 from" [1 4 1] "point3 to" [0 0 0] "rgb L" [3 3 3]
Material "diffuse" "rgb reflectance" [0.5 0.5 0.5]
Shape "trianglemesh" "point3 P" [-4 0 4  4 0 4  4 0 -4  -4 0 -4] "integer indices" [0 1 2 0 2 3]
Material "dielectric" "float eta" [1.5]
AttributeBegin
  Translate 0 0.4 0
  Shape "sphere" "float radius" [0.4]
AttributeEnd
"#;

fn render(dir: &Path, extra: &[&str]) -> std::process::Output {
    render_scene(dir, SCENE, extra)
}

/// Renders `scene` (written to `dir`/s.pbrt) quietly with the options `extra`.
pub fn render_scene(dir: &Path, scene: &str, extra: &[&str]) -> std::process::Output {
    let path = dir.join("s.pbrt");
    std::fs::write(&path, scene).unwrap();
    let mut args = vec!["render", path.to_str().unwrap(), "--quiet"];
    args.extend_from_slice(extra);
    run_in(dir, &args)
}

/// Renders `scene` in two parts split by samples and in two split by tiles (the first part on
/// one thread, the second on two), merges each pair and asserts it equals `whole` (the single
/// render, in `dir`).
#[track_caller]
pub fn assert_splits_merge_exactly(dir: &Path, scene: &str, whole: &crate::common::Img) {
    for by in ["samples", "tiles"] {
        for i in 0..2 {
            let (split, out, threads) = (format!("{i}/2"), format!("{by}{i}.exr"), ["1", "2"][i]);
            ok(&render_scene(
                dir,
                scene,
                &[
                    "-o",
                    &out,
                    "--threads",
                    threads,
                    "--split",
                    &split,
                    "--split-by",
                    by,
                ],
            ));
        }
        let (a, b, m) = (
            format!("{by}0.exr"),
            format!("{by}1.exr"),
            format!("{by}.exr"),
        );
        ok(&run_in(dir, &["merge", &a, &b, "-o", &m]));
        assert_eq!(
            &crate::common::read_exr(&dir.join(&m)),
            whole,
            "split by {by}"
        );
    }
}

#[track_caller]
pub fn ok(o: &std::process::Output) -> String {
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(o.status.success(), "{e}");
    e
}

/// Renders `scene` into `dir`/`out` with the options `extra` and `--stats json`: it succeeds
/// without a warning; returns the stats.
#[track_caller]
pub fn render_stats(dir: &Path, scene: &str, out: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["-o", out, "--stats", "json"];
    args.extend_from_slice(extra);
    let o = render_scene(dir, scene, &args);
    let e = ok(&o);
    assert!(!e.contains("warning"), "{e}");
    serde_json::from_slice(&o.stdout).unwrap()
}

#[test]
fn sppm_splits_by_tiles_exactly_and_counts_photons() {
    let dir = ScratchDir::new("sppm-split");
    let stats = render_stats(&dir, SCENE, "whole.exr", &["--threads", "1"]);
    assert_eq!(stats["integrator"], "sppm");
    assert_eq!(stats["photons"], 4 * 4000);
    assert_eq!(stats["samples"], 16 * 40 * 4);
    for i in 0..2 {
        let split = format!("{i}/2");
        let out = format!("p{i}.exr");
        ok(&render(
            &dir,
            &["-o", &out, "--threads", "2", "--split", &split],
        ));
    }
    let o = run_in(&dir, &["merge", "p0.exr", "p1.exr", "-o", "m.exr"]);
    ok(&o);
    let (whole, merged) = (
        read_exr(&dir.join("whole.exr")),
        read_exr(&dir.join("m.exr")),
    );
    assert_eq!(whole, merged);
    assert!(whole.rgb.iter().any(|p| p[0] > 0.0));
}

#[test]
fn sppm_refuses_sample_ranges_checkpoint_intervals_and_denoising() {
    let dir = ScratchDir::new("sppm-refusals");
    for extra in [
        &["--split", "1/2", "--split-by", "samples"][..],
        &["--samples", "0..2"],
        &["--checkpoint-every", "1"],
        &["--denoise"],
    ] {
        let mut args = vec!["-o", "p.exr"];
        args.extend_from_slice(extra);
        let o = render(&dir, &args);
        let e = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "{extra:?}");
        assert!(
            e.contains("integrator \"sppm\" cannot render"),
            "{extra:?}: {e}"
        );
    }
    assert!(!dir.join("p.exr").exists());
}
