//! `--stats json` of the integrators that trace light subpaths: how many they started and how
//! many connections they tried (and none for a camera-path integrator).

use crate::common::ScratchDir;
use crate::sppm::{SCENE, render_stats};

/// The stats of the sppm test scene rendered with `integrator` (a pbrt `Integrator` line).
fn stats(integrator: &str) -> serde_json::Value {
    let dir = ScratchDir::new("light-stats");
    let scene = SCENE
        .lines()
        .map(|l| {
            if l.starts_with("Integrator") {
                integrator
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n");
    render_stats(&dir, &scene, "s.exr", &[])
}

#[test]
fn stats_count_light_paths_and_connections() {
    let samples = 16 * 40 * 4;
    // One light subpath per camera sample (a distant light always emits one); bdpt tries
    // several connections per sample (its strategies with s ≥ 1: light sampling from every
    // camera vertex at least), light tracing one per light vertex on a surface (none from a
    // distant light's first, and many of its paths miss the floor).
    for name in ["bdpt", "lightpath"] {
        let s = stats(&format!("Integrator \"{name}\" \"integer maxdepth\" [4]"));
        assert_eq!(s["integrator"], name);
        assert_eq!(s["samples"], samples, "{name}");
        assert_eq!(s["light_paths"], samples, "{name}");
        let c = s["connections"].as_u64().unwrap();
        let least = if name == "bdpt" { samples } else { samples / 4 };
        assert!(c > least && c < 20 * samples, "{name}: {c} connections");
    }
    // mlt: one light subpath per vector with s ≥ 1 (bootstrap and mutations).
    let s =
        stats("Integrator \"mlt\" \"integer maxdepth\" [4] \"integer bootstrapsamples\" [1000]");
    let (l, c) = (
        s["light_paths"].as_u64().unwrap(),
        s["connections"].as_u64().unwrap(),
    );
    assert!(l > 0 && c > 0, "mlt: {l} light paths, {c} connections");
    let s = stats("Integrator \"path\"");
    assert_eq!(
        (s["light_paths"].as_u64(), s["connections"].as_u64()),
        (Some(0), Some(0))
    );
}
