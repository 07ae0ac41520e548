//! `path` with lancer's `caustics` through `lancer render`: read without a warning, its light
//! paths and connections counted, a split by samples and a split by tiles each merged to the
//! single render's exact pixels, and `lancer info` naming it.

use crate::common::{ScratchDir, read_exr, run_in};
use crate::sppm::{SCENE, assert_splits_merge_exactly, render_stats};

/// sppm's test scene (a glass sphere on a grey floor under a distant light) with `path` and
/// its caustics by light tracing.
fn scene() -> String {
    let s = SCENE.replace(
        r#"Integrator "sppm" "integer maxdepth" [6] "integer photonsperiteration" [4000] "float radius" [0.1]"#,
        r#"Integrator "path" "integer maxdepth" [6] "bool caustics" true "float causticpaths" [0.5]"#,
    );
    assert!(s.contains("bool caustics"));
    s
}

#[test]
fn caustics_count_their_paths_and_split_exactly() {
    let dir = ScratchDir::new("caustics-split");
    let s = scene();
    let stats = render_stats(&dir, &s, "whole.exr", &["--threads", "2"]);
    assert_eq!(stats["integrator"], "path");
    assert!(stats["light_paths"].as_u64().unwrap() > 0, "{stats}");
    assert!(stats["connections"].as_u64().unwrap() > 0, "{stats}");
    let whole = read_exr(&dir.join("whole.exr"));
    assert_splits_merge_exactly(&dir, &s, &whole);
    std::fs::write(dir.join("s.pbrt"), &s).unwrap();
    let o = run_in(&dir, &["info", "s.pbrt", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["integrator"]["name"], "path");
    assert_eq!(v["integrator"]["caustics"], true);
    assert_eq!(v["integrator"]["causticpaths"].as_f64(), Some(0.5));
}
