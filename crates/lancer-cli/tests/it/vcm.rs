//! lancer's `vcm` through `lancer render`: read without a warning, `--stats json` counts its
//! light paths, light vertices and merges, and a split by samples and a split by tiles each
//! merge to the single render's exact pixels.

use crate::common::{ScratchDir, read_exr, run_in};
use crate::sppm::{SCENE, ok, render_scene};
use std::path::Path;

/// sppm's test scene (a glass sphere on a grey floor under a distant light, 16 × 40 pixels,
/// three tile rows) rendered by vcm: a caustic that merging renders.
fn render(dir: &Path, extra: &[&str]) -> std::process::Output {
    let scene = SCENE.replace(
        r#"Integrator "sppm" "integer maxdepth" [6] "integer photonsperiteration" [4000] "float radius" [0.1]"#,
        r#"Integrator "vcm" "integer maxdepth" [6] "float radius" [0.05]"#,
    );
    assert!(scene.contains("\"vcm\""));
    render_scene(dir, &scene, extra)
}

#[test]
fn vcm_counts_its_paths_and_splits_by_samples_and_tiles_exactly() {
    let dir = ScratchDir::new("vcm-split");
    let o = render(
        &dir,
        &["-o", "whole.exr", "--threads", "2", "--stats", "json"],
    );
    let e = ok(&o);
    assert!(!e.contains("warning"), "{e}");
    let stats: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(stats["integrator"], "vcm");
    assert_eq!(stats["samples"], 16 * 40 * 4);
    assert_eq!(stats["light_paths"], 16 * 40 * 4);
    assert!(stats["photons"].as_u64().unwrap() > 0, "{stats}");
    assert!(stats["merges"].as_u64().unwrap() > 0, "{stats}");
    assert!(stats["connections"].as_u64().unwrap() > 0, "{stats}");
    let whole = read_exr(&dir.join("whole.exr"));
    assert!(whole.rgb.iter().any(|p| p[0] > 0.0));
    for by in ["samples", "tiles"] {
        for i in 0..2 {
            let (split, out, threads) = (format!("{i}/2"), format!("{by}{i}.exr"), ["1", "2"][i]);
            ok(&render(
                &dir,
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
        ok(&run_in(&dir, &["merge", &a, &b, "-o", &m]));
        assert_eq!(read_exr(&dir.join(&m)), whole, "split by {by}");
    }
}
