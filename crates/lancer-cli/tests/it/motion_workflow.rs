//! Motion blur keeps the long-render workflow exact: a render of a scene with a moving sphere
//! and a turning box (a small copy of `shared/scenes/cameras/motion.pbrt`), split by tiles or
//! by samples and merged, or interrupted and resumed, gives the whole render's bytes, in
//! spectral and in RGB mode. Each camera sample's time is a pure function of (seed, pixel,
//! sample index), like its other dimensions.

use crate::common::{
    ScratchDir, data, render_ok, resume_ok, run_in, signal_after_first_checkpoint,
};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Renders the scene with `args`, then part `i` of `n` split `by` for each i, merges the
/// parts, and checks the merge equals the whole render byte for byte.
fn split_merge_is_exact(dir: &Path, mode: &[&str], by: &str, n: usize) {
    let scene = data("motion/motion.pbrt");
    let mut args = vec!["--seed", "3"];
    args.extend_from_slice(mode);
    let tag = format!("{by}{}", mode.join(""));
    let whole = dir.join(format!("whole{tag}.exr"));
    render_ok(dir, &scene, &whole, &args);
    let parts: Vec<PathBuf> = (0..n)
        .map(|i| {
            let out = dir.join(format!("{tag}-{i}.exr"));
            let split = format!("{i}/{n}");
            let mut a = args.clone();
            a.extend_from_slice(&["--split", &split, "--split-by", by]);
            render_ok(dir, &scene, &out, &a);
            out
        })
        .collect();
    let merged = dir.join(format!("merged{tag}.exr"));
    let mut m = vec!["merge"];
    m.extend(parts.iter().map(|p| p.to_str().unwrap()));
    m.extend_from_slice(&["-o", merged.to_str().unwrap()]);
    let o = run_in(dir, &m);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        bytes(&merged) == bytes(&whole),
        "{by} split of the motion-blurred scene ({mode:?}) merges to other bytes"
    );
}

#[test]
fn motion_blurred_splits_merge_to_the_whole_render() {
    let dir = ScratchDir::new("motion-splits");
    split_merge_is_exact(&dir, &[], "tiles", 2);
    split_merge_is_exact(&dir, &[], "samples", 3);
    split_merge_is_exact(&dir, &["--rgb"], "samples", 2);
}

#[test]
fn the_motion_scene_reads_without_warnings_and_blurs() {
    let dir = ScratchDir::new("motion-info");
    let scene = data("motion/motion.pbrt");
    let o = run_in(&dir, &["info", scene.to_str().unwrap(), "--strict"]);
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    // With the shutter closed at its opening nothing moves, and the image differs.
    let still = dir.join("still.pbrt");
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(
        &still,
        text.replace("\"float shutterclose\" [1]", "\"float shutterclose\" [0]"),
    )
    .unwrap();
    let (a, b) = (dir.join("blur.exr"), dir.join("still.exr"));
    render_ok(&dir, &scene, &a, &["--rgb"]);
    render_ok(&dir, &still, &b, &["--rgb"]);
    assert!(bytes(&a) != bytes(&b));
}

#[test]
fn an_interrupted_motion_blurred_render_resumes_to_the_same_bytes() {
    let dir = ScratchDir::new("motion-resume");
    let scene = dir.join("motion.pbrt");
    std::fs::copy(data("motion/motion.pbrt"), &scene).unwrap();
    let opts = ["--spp", "1024", "--seed", "4"];
    let full = dir.join("full.exr");
    render_ok(&dir, &scene, &full, &opts);

    // Interrupted after its first checkpoint (every 60 ms), as in the workflow tests.
    let ckpt = dir.join("int.exr.ckpt");
    let child = Command::new(env!("CARGO_BIN_EXE_lancer"))
        .current_dir(&dir)
        .args(["render", "motion.pbrt", "-o", "int.exr", "--quiet"])
        .args(opts)
        .args(["--checkpoint-every", "0.001"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let o = signal_after_first_checkpoint(child, &ckpt, "INT");
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let out = dir.join("int.exr");
    assert!(
        bytes(&out) != bytes(&full),
        "the render was not interrupted"
    );

    resume_ok(&dir, "int.exr");
    assert!(
        bytes(&out) == bytes(&full),
        "the resumed motion-blurred render differs from the uninterrupted one"
    );
}
