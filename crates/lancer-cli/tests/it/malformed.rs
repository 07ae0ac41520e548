//! Malformed scenes: each gives one clear error line naming `file:line:column`, an excerpt,
//! exit status 2, no panic, and leaves an existing output image untouched. What lancer merely
//! does not support is a warning, and the scene still renders.

use crate::common::*;
use std::path::Path;

/// (file in `tests/data/bad`, line:column the error must point at, words the message must hold)
const CASES: &[(&str, &str, &str)] = &[
    ("truncated-array.pbrt", "6:31", "never closed"),
    ("truncated-string.pbrt", "6:16", "string is never closed"),
    ("truncated-parameter.pbrt", "6:16", "has no value"),
    (
        "truncated-block.pbrt",
        "6:1",
        "AttributeBegin is never closed",
    ),
    (
        "truncated-arguments.pbrt",
        "7:1",
        "LookAt expects 9 numbers",
    ),
    ("truncated-before-world.pbrt", "4:1", "before WorldBegin"),
    (
        "unknown-directive.pbrt",
        "6:1",
        "unknown directive 'Sphere'",
    ),
    (
        "misspelled-directive.pbrt",
        "6:1",
        "did you mean AttributeBegin",
    ),
    (
        "float-for-integer.pbrt",
        "6:34",
        "expects integers, found 1.5",
    ),
    (
        "string-for-float.pbrt",
        "6:16",
        "must be of type float, not string",
    ),
    (
        "rgb-with-two-values.pbrt",
        "6:20",
        "needs triples of numbers",
    ),
    (
        "unknown-parameter-type.pbrt",
        "6:16",
        "unknown parameter type 'flaot'",
    ),
    (
        "extra-attribute-end.pbrt",
        "8:1",
        "AttributeEnd without a matching AttributeBegin",
    ),
    ("mismatched-end.pbrt", "7:1", "closes the TransformBegin"),
    (
        "missing-include.pbrt",
        "6:1",
        "missing/geometry.pbrt: no such file",
    ),
    (
        "negative-resolution.pbrt",
        "1:12",
        "xresolution\" must be between 1 and 65536, not -64",
    ),
    (
        "zero-resolution.pbrt",
        "1:39",
        "yresolution\" must be between 1 and 65536, not 0",
    ),
    ("nan-argument.pbrt", "6:13", "'nan' is not a finite number"),
    ("nan-parameter.pbrt", "6:32", "'NaN' is not a finite number"),
    ("huge-number.pbrt", "6:32", "'1e999' is not a finite number"),
    (
        "negative-radius.pbrt",
        "6:16",
        "radius must be positive, got -1",
    ),
    (
        "shape-before-world.pbrt",
        "5:1",
        "only allowed after WorldBegin",
    ),
    ("camera-in-world.pbrt", "6:1", "must come before WorldBegin"),
    (
        "unknown-named-material.pbrt",
        "6:1",
        "no material named \"nowhere\"",
    ),
    ("include-self.pbrt", "6:1", "cycle"),
    ("stray-number.pbrt", "6:33", "found the number 2"),
    ("degenerate-spot.pbrt", "6:1", "\"from\" equal to \"to\""),
];

const OLD_IMAGE: &[u8] = b"an existing image that must survive";

/// Renders `scene` (a file name inside `dir`) over an existing output and checks the failure.
fn check_failure(dir: &Path, scene: &str, at: &str, words: &str) {
    let out = dir.join(format!("{scene}.png"));
    std::fs::write(&out, OLD_IMAGE).unwrap();
    let o = run_in(
        dir,
        &["render", scene, "-o", out.to_str().unwrap(), "--quiet"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{scene}: exit status {:?}: {err}",
        o.status
    );
    assert!(!err.contains("panicked"), "{scene}: panic: {err}");
    let first = err.lines().next().unwrap_or_default();
    let prefix = format!("error: {scene}:{at}: ");
    assert!(
        first.starts_with(&prefix),
        "{scene}: expected '{prefix}…', got '{first}'"
    );
    assert!(
        first.contains(words),
        "{scene}: '{first}' does not say '{words}'"
    );
    // The excerpt: the offending line, numbered, then a caret.
    let line = at.split(':').next().unwrap();
    assert!(
        err.lines().any(|l| l.starts_with(&format!("{line} | "))),
        "{scene}: no excerpt of line {line} in:\n{err}"
    );
    assert_eq!(
        std::fs::read(&out).unwrap(),
        OLD_IMAGE,
        "{scene}: the existing output changed"
    );
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(
        leftovers.is_empty(),
        "{scene}: temporary files left: {leftovers:?}"
    );
}

#[test]
fn every_malformed_scene_is_reported_at_its_place() {
    let dir = ScratchDir::new("malformed");
    for (scene, _, _) in CASES {
        std::fs::copy(data(&format!("bad/{scene}")), dir.join(scene)).unwrap();
    }
    for (scene, at, words) in CASES {
        check_failure(&dir, scene, at, words);
    }
    // Every file of the corpus is in the table.
    let files = std::fs::read_dir(data("bad")).unwrap().count();
    assert_eq!(files, CASES.len(), "tests/data/bad and CASES disagree");
}

#[test]
fn non_utf8_bytes_are_located() {
    let dir = ScratchDir::new("utf8");
    let mut bytes = b"LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n".to_vec();
    bytes.extend_from_slice(b"Shape \"sph\xe9re\"\n");
    std::fs::write(dir.join("latin1.pbrt"), bytes).unwrap();
    check_failure(&dir, "latin1.pbrt", "4:11", "not valid UTF-8");
}

#[test]
fn a_missing_scene_or_unknown_format_fails_cleanly() {
    let dir = ScratchDir::new("missing");
    std::fs::write(dir.join("keep.png"), OLD_IMAGE).unwrap();
    for scene in ["nowhere.pbrt", "model.xyz", "nowhere.obj", "nowhere.ply"] {
        let o = run_in(&dir, &["render", scene, "-o", "keep.png", "--quiet"]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{scene}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(scene),
            "{scene}: {err}"
        );
    }
    assert_eq!(std::fs::read(dir.join("keep.png")).unwrap(), OLD_IMAGE);
}

#[test]
fn absurd_command_line_values_are_refused() {
    let dir = ScratchDir::new("absurd");
    let scene = data("course/01-sphere.pbrt");
    let scene = scene.to_str().unwrap();
    for args in [
        &["--resolution", "0x10"][..],
        &["--resolution", "-5x10"],
        &["--resolution", "65536x65536"],
        &["--spp", "0"],
        &["-o", "image.bmp"],
        &["-o", "no/such/folder/image.png"],
    ] {
        let mut all = vec!["render", scene, "--quiet"];
        all.extend_from_slice(args);
        let o = run_in(&dir, &all);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[test]
fn unsupported_features_warn_with_their_line_and_still_render() {
    let dir = ScratchDir::new("warnings");
    std::fs::write(
        dir.join("warn.pbrt"),
        "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n\
         Sampler \"independent\" \"integer pixelsamples\" [1]\n\
         WorldBegin\n\
         MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"float density\" [1]\n\
         Shape \"sphere\" \"float radius\" [1] \"float wobble\" [2]\n\
         Shape \"nurbs\" \"point3 P\" [0 0 0 1 0 0 1 1 0 0 1 0]\n",
    )
    .unwrap();
    let o = run_in(&dir, &["render", "warn.pbrt", "-o", "w.png", "--quiet"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    for (at, words) in [
        ("warn.pbrt:4:51", "\"float density\" of MakeNamedMedium"),
        ("warn.pbrt:5:35", "\"float wobble\""),
        ("warn.pbrt:6:1", "unknown shape \"nurbs\"; skipped"),
    ] {
        assert!(
            err.lines()
                .any(|l| l.starts_with(&format!("warning: {at}: ")) && l.contains(words)),
            "no warning at {at} saying {words} in:\n{err}"
        );
    }
    // A shape skipped whole has one warning, not one more per parameter.
    assert!(
        !err.contains("\"point3 P\" of Shape \"nurbs\""),
        "a skipped shape's parameters were warned about:\n{err}"
    );
    assert!(dir.join("w.png").exists());
}
