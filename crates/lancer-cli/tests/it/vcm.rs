//! lancer's `vcm` through `lancer render`: read without a warning, `--stats json` counts its
//! light paths, light vertices and merges, and a split by samples and a split by tiles each
//! merge to the single render's exact pixels; `lancer info` gives the merge radius the render
//! uses, the default one too.

use crate::common::{ScratchDir, read_exr, run_in};
use crate::sppm::{SCENE, assert_splits_merge_exactly, render_stats};

/// sppm's test scene (a glass sphere on a grey floor under a distant light, 16 × 40 pixels,
/// three tile rows) rendered by vcm: a caustic that merging renders.
fn scene() -> String {
    let scene = SCENE.replace(
        r#"Integrator "sppm" "integer maxdepth" [6] "integer photonsperiteration" [4000] "float radius" [0.1]"#,
        r#"Integrator "vcm" "integer maxdepth" [6] "float radius" [0.05]"#,
    );
    assert!(scene.contains("\"vcm\""));
    scene
}

#[test]
fn vcm_counts_its_paths_and_splits_by_samples_and_tiles_exactly() {
    let dir = ScratchDir::new("vcm-split");
    let stats = render_stats(&dir, &scene(), "whole.exr", &["--threads", "2"]);
    assert_eq!(stats["integrator"], "vcm");
    assert_eq!(stats["samples"], 16 * 40 * 4);
    assert_eq!(stats["light_paths"], 16 * 40 * 4);
    assert!(stats["photons"].as_u64().unwrap() > 0, "{stats}");
    assert!(stats["merges"].as_u64().unwrap() > 0, "{stats}");
    assert!(stats["connections"].as_u64().unwrap() > 0, "{stats}");
    let whole = read_exr(&dir.join("whole.exr"));
    assert!(whole.rgb.iter().any(|p| p[0] > 0.0));
    assert_splits_merge_exactly(&dir, &scene(), &whole);
}

#[test]
fn info_reports_the_radius_the_render_uses() {
    let dir = ScratchDir::new("vcm-info");
    let written = SCENE.replace(
        r#"Integrator "sppm" "integer maxdepth" [6] "integer photonsperiteration" [4000] "float radius" [0.1]"#,
        r#"Integrator "vcm" "float radius" [0.05]"#,
    );
    let default = written.replace(r#" "float radius" [0.05]"#, "");
    assert!(written.contains("\"vcm\"") && !default.contains("[0.05]"));
    let info = |scene: &str, json: bool| {
        std::fs::write(dir.join("s.pbrt"), scene).unwrap();
        let args: &[&str] = if json {
            &["info", "s.pbrt", "--json"]
        } else {
            &["info", "s.pbrt"]
        };
        let o = run_in(&dir, args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    // The floor spans [−4, 4] × {0} × [−4, 4] and the sphere reaches y = 0.8: the bounding
    // sphere's radius is |(4, 0.4, 4)| = √32.16, and the default radius 0.003 of it.
    let expected = 0.003 * 32.16f64.sqrt();
    let v: serde_json::Value = serde_json::from_str(&info(&default, true)).unwrap();
    let r = v["integrator"]["radius"].as_f64().unwrap();
    assert!((r - expected).abs() < 1e-4 * expected, "{r} vs {expected}");
    assert_eq!(v["integrator"]["defaults"], serde_json::json!(["radius"]));
    let text = info(&default, false);
    assert!(
        text.contains(&format!("radius {} (default)", v["integrator"]["radius"])),
        "{text}"
    );
    assert!(!text.contains("null"), "{text}");
    // A written radius is given as written, not called a default.
    let v: serde_json::Value = serde_json::from_str(&info(&written, true)).unwrap();
    assert_eq!(v["integrator"]["radius"].as_f64(), Some(0.05));
    assert!(v["integrator"].get("defaults").is_none(), "{v}");
    let text = info(&written, false);
    assert!(
        text.contains("radius 0.05)") && !text.contains("(default)"),
        "{text}"
    );
}
