//! pbrt-v4 users' reports on lancer's command line (issue 21): `info` prints each warning
//! once, `merge` names a missing part plainly, a one-row split says "row", a glTF model that
//! requires `KHR_texture_transform` renders.

mod common;

use common::{ScratchDir, data, run_in};
use std::path::Path;
use std::process::Output;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn info_prints_each_warning_once() {
    let dir = ScratchDir::new("pbrt-info-warn");
    std::fs::write(
        dir.join("w.pbrt"),
        "Camera \"perspective\"\nWorldBegin\nShape \"sphere\"\nShape \"bogus\"\n",
    )
    .unwrap();
    let o = run_in(&dir, &["info", "w.pbrt"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
    let warning = "w.pbrt:4:1: unknown shape \"bogus\"";
    assert_eq!(all.matches(warning).count(), 1, "{all}");
    assert!(all.contains("warnings      1\n"), "{all}");
}

#[test]
fn merge_names_a_missing_part_plainly() {
    let dir = ScratchDir::new("pbrt-merge-missing");
    let o = run_in(&dir, &["merge", "part-0.exr", "-o", "m.exr"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stderr(&o), "error: part-0.exr: no such part file\n");
    assert!(!dir.join("m.exr").exists());
}

#[test]
fn a_split_of_one_tile_row_says_row() {
    let dir = ScratchDir::new("pbrt-one-row");
    let scene = data("pt/cbox.pbrt");
    let o = run_in(
        &dir,
        &[
            "render",
            s(&scene),
            "-o",
            "p.exr",
            "--resolution",
            "32x16",
            "--split",
            "1/3",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("the image has only 1 row of 16-pixel tiles, too few for 3 parts"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_model_requiring_khr_texture_transform_renders() {
    let dir = ScratchDir::new("pbrt-khr-tt");
    let gltf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../lancer-scene/tests/data/gltf");
    let text = std::fs::read_to_string(gltf.join("Triangle/Triangle.gltf"))
        .unwrap()
        .replacen(
            '{',
            r#"{ "extensionsUsed": ["KHR_texture_transform"], "extensionsRequired": ["KHR_texture_transform"],"#,
            1,
        );
    std::fs::write(dir.join("t.gltf"), text).unwrap();
    std::fs::copy(
        gltf.join("Triangle/simpleTriangle.bin"),
        dir.join("simpleTriangle.bin"),
    )
    .unwrap();
    let o = run_in(
        &dir,
        &[
            "render",
            "t.gltf",
            "-o",
            "t.png",
            "--quiet",
            "--resolution",
            "16x16",
            "--spp",
            "1",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("t.png").is_file());
}
