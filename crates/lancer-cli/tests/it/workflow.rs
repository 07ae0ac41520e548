//! The long-render workflow: a render split into parts in separate processes and merged gives
//! the single render's exact bytes; an interrupted render resumed from its checkpoint gives the
//! uninterrupted render's exact bytes, and so does one command line run again with
//! `--resume-if-exists` (a requeued batch job); `lancer merge` refuses parts that do not belong
//! together.

use crate::common::{
    ScratchDir, data, read_exr, render_ok, resume_ok, run_in, signal_after_first_checkpoint,
};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Options shared by the split tests: 40 × 72 pixels is 5 rows of 16-pixel tiles.
const OPTS: [&str; 6] = ["--spp", "8", "--seed", "5", "--resolution", "40x72"];

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Renders part `i` of `n` of the Cornell box, split `by`, to `dir/by-i.exr`.
fn part(dir: &Path, by: &str, i: usize, n: usize, extra: &[&str]) -> PathBuf {
    let out = dir.join(format!("{by}-{i}.exr"));
    let split = format!("{i}/{n}");
    let mut args = OPTS.to_vec();
    args.extend_from_slice(&["--split", &split, "--split-by", by]);
    args.extend_from_slice(extra);
    render_ok(dir, &data("pt/cbox.pbrt"), &out, &args);
    out
}

/// Runs `lancer merge PARTS -o OUT`.
fn merge(dir: &Path, parts: &[&Path], out: &Path) -> std::process::Output {
    let mut args = vec!["merge"];
    args.extend(parts.iter().map(|p| s(p)));
    args.extend_from_slice(&["-o", s(out)]);
    run_in(dir, &args)
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn tile_and_sample_splits_merge_to_the_whole_render_byte_for_byte() {
    let dir = ScratchDir::new("wf-splits");
    let scene = data("pt/cbox.pbrt");
    let whole = dir.join("whole.exr");
    let whole_png = dir.join("whole.png");
    render_ok(&dir, &scene, &whole, &OPTS);
    render_ok(&dir, &scene, &whole_png, &OPTS);

    let tiles: Vec<PathBuf> = (0..4).map(|i| part(&dir, "tiles", i, 4, &[])).collect();
    let samples: Vec<PathBuf> = (0..3).map(|i| part(&dir, "samples", i, 3, &[])).collect();
    for (name, parts) in [("tiles", &tiles), ("samples", &samples)] {
        // The order of the parts on the command line does not matter.
        let mut refs: Vec<&Path> = parts.iter().map(|p| p.as_path()).collect();
        refs.reverse();
        let out = dir.join(format!("m-{name}.exr"));
        let o = merge(&dir, &refs, &out);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert!(bytes(&out) == bytes(&whole), "merged {name} EXR differs");
        let out_png = dir.join(format!("m-{name}.png"));
        assert!(merge(&dir, &refs, &out_png).status.success());
        assert!(
            bytes(&out_png) == bytes(&whole_png),
            "merged {name} PNG differs"
        );
    }

    // A part is also an ordinary EXR image: tile part 1 of 4 holds tile row 1 (rows 16..32),
    // whose pixels have all their samples, so they equal the whole render's.
    let w = read_exr(&whole);
    let p1 = read_exr(&tiles[1]);
    assert_eq!((p1.width, p1.height), (40, 16));
    assert_eq!(p1.rgb[..], w.rgb[16 * 40..32 * 40]);
    let mean = p1.means();
    assert!(mean.iter().all(|&m| m > 0.01 && m.is_finite()), "{mean:?}");
}

#[test]
fn merge_refuses_parts_that_do_not_belong_together() {
    let dir = ScratchDir::new("wf-refuse");
    let tiles: Vec<PathBuf> = (0..2).map(|i| part(&dir, "tiles", i, 2, &[])).collect();
    let other_seed = dir.join("seed.exr");
    let mut args = vec!["--spp", "8", "--seed", "6", "--resolution", "40x72"];
    args.extend_from_slice(&["--split", "1/2", "--split-by", "tiles"]);
    render_ok(&dir, &data("pt/cbox.pbrt"), &other_seed, &args);
    let other_scene = dir.join("scene.exr");
    let mut args = OPTS.to_vec();
    args.extend_from_slice(&["--split", "1/2", "--split-by", "tiles"]);
    render_ok(&dir, &data("course/01-sphere.pbrt"), &other_scene, &args);
    let samples0 = part(&dir, "samples", 0, 2, &[]);

    let cases: [(&str, Vec<&Path>, &str); 5] = [
        ("another seed", vec![&tiles[0], &other_seed], "seed 6"),
        (
            "another scene",
            vec![&tiles[0], &other_scene],
            "another scene",
        ),
        (
            "an overlap",
            vec![&tiles[0], &tiles[1], &samples0],
            "overlap",
        ),
        ("the same part twice", vec![&tiles[0], &tiles[0]], "overlap"),
        ("a hole", vec![&tiles[1]], "holes"),
    ];
    for (what, parts, says) in cases {
        let out = dir.join("bad.exr");
        let o = merge(&dir, &parts, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success(), "merge accepted {what}");
        assert!(
            err.contains(says),
            "{what}: the message does not say '{says}': {err}"
        );
        assert!(!out.exists(), "merge wrote an image despite {what}");
    }
    // A file that is not a part is named in the refusal.
    let plain = dir.join("plain.exr");
    render_ok(&dir, &data("pt/cbox.pbrt"), &plain, &OPTS);
    let out = dir.join("bad.exr");
    let o = merge(&dir, &[&tiles[0], &plain], &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("plain.exr"), "{err}");
    assert!(!out.exists());
    // Sanity: the two tile halves alone do merge.
    assert!(merge(&dir, &[&tiles[0], &tiles[1]], &out).status.success());
}

/// Spectral mode changes pixels, so it is part of what a part records: a spectral half does
/// not merge with an RGB half, and spectral halves merge to the whole spectral render byte for
/// byte (the wavelengths, like every other sample dimension, depend on seed, pixel and index
/// only).
#[test]
fn spectral_parts_merge_with_each_other_and_not_with_rgb_parts() {
    let dir = ScratchDir::new("wf-spectral");
    let rgb0 = part(&dir, "tiles", 0, 2, &["--rgb"]);
    let spectral: Vec<PathBuf> = (0..2)
        .map(|i| {
            let out = dir.join(format!("spectral-{i}.exr"));
            let split = format!("{i}/2");
            let mut args = OPTS.to_vec();
            args.extend_from_slice(&["--split", &split, "--split-by", "tiles", "--spectral"]);
            render_ok(&dir, &data("pt/cbox.pbrt"), &out, &args);
            out
        })
        .collect();
    let out = dir.join("mixed.exr");
    let o = merge(&dir, &[&rgb0, &spectral[1]], &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "merge accepted RGB and spectral parts");
    assert!(err.contains("another scene"), "{err}");
    assert!(!out.exists());
    let whole = dir.join("whole.exr");
    let mut args = OPTS.to_vec();
    args.push("--spectral");
    render_ok(&dir, &data("pt/cbox.pbrt"), &whole, &args);
    let out = dir.join("merged.exr");
    let o = merge(&dir, &[&spectral[1], &spectral[0]], &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(bytes(&out) == bytes(&whole), "merged spectral EXR differs");
    // Spectral is the default: without a flag the same bytes; and the spectral image is not
    // the RGB one.
    let default = dir.join("default.exr");
    render_ok(&dir, &data("pt/cbox.pbrt"), &default, &OPTS);
    assert!(
        bytes(&default) == bytes(&whole),
        "the default mode is not spectral"
    );
    let plain = dir.join("plain.exr");
    let mut args = OPTS.to_vec();
    args.push("--rgb");
    render_ok(&dir, &data("pt/cbox.pbrt"), &plain, &args);
    assert!(bytes(&plain) != bytes(&whole));
}

#[test]
fn an_interrupted_render_resumes_to_the_uninterrupted_pixels() {
    let dir = ScratchDir::new("wf-resume");
    // The scene is a copy, so that the test can change it afterwards.
    let scene = dir.join("cbox.pbrt");
    std::fs::copy(data("pt/cbox.pbrt"), &scene).unwrap();
    let opts = ["--spp", "1024", "--seed", "9", "--resolution", "48x48"];
    let full = dir.join("full.exr");
    render_ok(&dir, &scene, &full, &opts);

    // Checkpoints every 60 ms show that the render is under way; the interrupt is sent after
    // the first one, whatever the machine's load, and the render is far from done by then.
    let out = dir.join("int.exr");
    let ckpt = dir.join("int.exr.ckpt");
    let child = Command::new(env!("CARGO_BIN_EXE_lancer"))
        .current_dir(&dir)
        .args(["render", "cbox.pbrt", "-o", "int.exr", "--quiet"])
        .args(opts)
        .args(["--checkpoint-every", "0.001"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let o = signal_after_first_checkpoint(child, &ckpt, "INT");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("--resume"), "{err}");

    // The image so far is a valid, finite image of the right size with light in it (a
    // spectral render's pixels may dip below zero: a few wavelengths can fall outside sRGB).
    let partial = read_exr(&out);
    assert_eq!((partial.width, partial.height), (48, 48));
    assert!(partial.rgb.iter().flatten().all(|v| v.is_finite()));
    assert!(
        partial.means().iter().all(|&m| m > 0.01),
        "{:?}",
        partial.means()
    );
    assert!(
        bytes(&out) != bytes(&full),
        "the render was not interrupted mid-way"
    );
    let saved = dir.join("saved.ckpt");
    std::fs::copy(&ckpt, &saved).unwrap();

    // Resume with nothing but the output and the checkpoint.
    resume_ok(&dir, "int.exr");
    assert!(
        bytes(&out) == bytes(&full),
        "resumed render differs from uninterrupted"
    );
    assert!(
        !ckpt.exists(),
        "the checkpoint was not removed after the render"
    );

    // Options that change pixels cannot be changed on resume.
    let o = run_in(
        &dir,
        &[
            "render",
            "-o",
            "x.exr",
            "--resume",
            "saved.ckpt",
            "--spp",
            "4",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--resume") && err.contains("--spp"),
        "the refusal names the clash: {err}"
    );
    assert!(!dir.join("x.exr").exists(), "nothing written");
    // A checkpoint whose scene changed is refused, and nothing is written.
    let text = std::fs::read_to_string(&scene).unwrap();
    std::fs::write(&scene, text.replace("maxdepth\" [7]", "maxdepth\" [3]")).unwrap();
    let o = run_in(
        &dir,
        &["render", "-o", "y.exr", "--resume", "saved.ckpt", "--quiet"],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("changed"), "{err}");
    assert!(!dir.join("y.exr").exists());
}

#[test]
fn resume_if_exists_starts_afresh_then_continues_its_own_checkpoint_only() {
    let dir = ScratchDir::new("wf-resume-if-exists");
    let scene = data("pt/cbox.pbrt");
    // A part of a split render, as a job array's task renders it.
    let opts = [
        "--spp",
        "1024",
        "--seed",
        "9",
        "--resolution",
        "48x48",
        "--split",
        "1/2",
        "--split-by",
        "samples",
    ];
    let reference = dir.join("ref.exr");
    render_ok(&dir, &scene, &reference, &opts);

    // No checkpoint: the same command line starts afresh (and says nothing about resuming).
    let fresh = dir.join("fresh.exr");
    render_ok(
        &dir,
        &scene,
        &fresh,
        &[&opts[..], &["--resume-if-exists"]].concat(),
    );
    assert!(bytes(&fresh) == bytes(&reference));

    // The job script's command line, interrupted after its first checkpoint…
    let job = |opts: &[&str], extra: &[&str]| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_lancer"));
        c.current_dir(&dir)
            .args(["render", s(&scene), "-o", "part.exr", "--resume-if-exists"])
            .args(opts)
            .args(["--checkpoint-every", "0.001"])
            .args(extra)
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        c
    };
    let ckpt = dir.join("part.exr.ckpt");
    let o = signal_after_first_checkpoint(job(&opts, &["--quiet"]).spawn().unwrap(), &ckpt, "INT");
    assert_eq!(
        o.status.code(),
        Some(130),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(ckpt.exists() && !dir.join("part.exr").exists());
    let saved = std::fs::read(&ckpt).unwrap();

    // …and run again unchanged (a requeued job): it continues, ends bit-exact, and removes
    // its checkpoint.
    let o = job(&opts, &[]).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("continuing the render saved there"), "{err}");
    assert!(
        bytes(&dir.join("part.exr")) == bytes(&reference),
        "resumed part differs"
    );
    assert!(!ckpt.exists(), "the checkpoint was not removed");

    // A checkpoint of another render at that path is refused, naming the option, and nothing
    // is written: the seed differs here.
    std::fs::write(&ckpt, &saved).unwrap();
    std::fs::remove_file(dir.join("part.exr")).unwrap();
    let other_seed = opts.map(|o| if o == "9" { "10" } else { o });
    let o = job(&other_seed, &["--quiet"]).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--seed") && err.contains("part.exr.ckpt"),
        "{err}"
    );
    assert!(ckpt.exists(), "the refused checkpoint is kept");
    assert!(!dir.join("part.exr").exists(), "nothing written");

    // The same part with --denoise cannot continue it: the checkpoint has no denoiser's sums
    // for its finished work (the part would carry zero albedo and normal there).
    let o = run_in(
        &dir,
        &[
            &["render", s(&scene), "-o", "part.exr", "--resume-if-exists"],
            &opts[..],
            &["--denoise", "--quiet"],
        ]
        .concat(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("written by a render without --denoise"),
        "{err}"
    );
    assert!(ckpt.exists(), "the refused checkpoint is kept");
    assert!(!dir.join("part.exr").exists(), "nothing written");

    // Without an output or a checkpoint path there is nothing to look for.
    let o = run_in(
        &dir,
        &["render", s(&scene), "--resume-if-exists", "--quiet"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--resume-if-exists"));
}
