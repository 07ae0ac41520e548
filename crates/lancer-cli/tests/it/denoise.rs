//! `lancer render --denoise [--denoise-inputs]`, `lancer img denoise` and `lancer merge
//! --denoise`: the auxiliary images on a hand-checkable scene (through a mirror too), the
//! same image from the three commands, an interrupted render resumed, and what `--denoise`
//! refuses.

use crate::common::{
    ScratchDir, data, lancer, read_exr, render_ok, resume_ok, run_in, signal_after_first_checkpoint,
};
use std::process::Stdio;

/// A diffuse plane (reflectance 0.25, 0.5, 0.75) at z = 3 facing a camera at the origin
/// looking down +z, and a grey one (0.9) at z = −1 behind the camera; with `mirror`, a
/// perfect silver mirror at z = 2 fills the left half of the view and shows the grey plane.
fn scene(mirror: bool) -> String {
    let m = if mirror {
        r#"AttributeBegin
Material "conductor" "float roughness" [0] "spectrum eta" "metal-Ag-eta" "spectrum k" "metal-Ag-k"
Shape "trianglemesh" "point3 P" [-10 -10 2  0 -10 2  0 10 2  -10 10 2]
  "integer indices" [0 1 2 0 2 3]
AttributeEnd
"#
    } else {
        ""
    };
    format!(
        r#"Camera "perspective" "float fov" [90]
Film "rgb" "integer xresolution" [16] "integer yresolution" [16]
Sampler "stratified" "integer xsamples" [2] "integer ysamples" [2]
WorldBegin
LightSource "infinite" "rgb L" [1 1 1]
{m}Material "diffuse" "rgb reflectance" [0.25 0.5 0.75]
Shape "trianglemesh" "point3 P" [-10 -10 3  10 -10 3  10 10 3  -10 10 3]
  "integer indices" [0 1 2 0 2 3]
Material "diffuse" "rgb reflectance" [0.9 0.9 0.9]
Shape "trianglemesh" "point3 P" [-10 -10 -1  10 -10 -1  10 10 -1  -10 10 -1]
  "integer indices" [0 1 2 0 2 3]
"#
    )
}

/// Renders `scene(mirror)` with `--denoise --denoise-inputs` into `out.exr` of a new scratch
/// folder `name`, and returns the folder.
fn render_denoised(name: &str, mirror: bool) -> ScratchDir {
    let dir = ScratchDir::new(name);
    std::fs::write(dir.join("s.pbrt"), scene(mirror)).unwrap();
    let o = run_in(
        &dir,
        &[
            "render",
            "s.pbrt",
            "-o",
            "out.exr",
            "--quiet",
            "--denoise",
            "--denoise-inputs",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    dir
}

#[test]
fn render_denoise_writes_its_inputs_and_img_denoise_gives_the_same_image() {
    let dir = render_denoised("denoise-render", false);
    let albedo = read_exr(&dir.join("out.albedo.exr"));
    let normal = read_exr(&dir.join("out.normal.exr"));
    for (a, n) in albedo.rgb.iter().zip(&normal.rgb) {
        // a diffuse surface's albedo is its reflectance; its normal faces the camera (−z
        // in camera space)
        for (c, want) in [0.25, 0.5, 0.75].iter().enumerate() {
            assert!((a[c] - want).abs() < 2e-3, "albedo {a:?}");
        }
        assert!(
            (n[2] + 1.0).abs() < 1e-4 && n[0].abs() < 1e-4,
            "normal {n:?}"
        );
    }
    let o = run_in(
        &dir,
        &[
            "img",
            "denoise",
            "out.noisy.exr",
            "--albedo",
            "out.albedo.exr",
            "--normal",
            "out.normal.exr",
            "-o",
            "img.exr",
            "--quiet",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (a, b) = (
        read_exr(&dir.join("out.exr")),
        read_exr(&dir.join("img.exr")),
    );
    assert_eq!(a, b, "img denoise differs from render --denoise");
    // the denoised image is the noisy one's brightness
    let (m, n) = (a.means(), read_exr(&dir.join("out.noisy.exr")).means());
    for c in 0..3 {
        assert!((m[c] / n[c] - 1.0).abs() < 0.05, "means {m:?} vs {n:?}");
    }
}

#[test]
fn the_albedo_is_the_one_seen_through_a_mirror() {
    let dir = render_denoised("denoise-mirror", true);
    let albedo = read_exr(&dir.join("out.albedo.exr"));
    // left column: the mirror shows the grey plane behind the camera (0.9 times silver's
    // reflectance, above 0.8); right column: the coloured plane itself
    let (left, right) = (albedo.rgb[8 * 16], albedo.rgb[8 * 16 + 15]);
    assert!(
        left.iter().all(|&v| v > 0.75 && v < 0.9),
        "through the mirror {left:?}"
    );
    assert!(
        (right[0] - 0.25).abs() < 2e-3 && (right[2] - 0.75).abs() < 2e-3,
        "{right:?}"
    );
}

/// The parts of a split render keep the denoiser's sums, and `lancer merge --denoise` gives
/// `render --denoise`'s image and inputs: bit for bit split by tiles (each pixel's sums come
/// from one part), up to float rounding split by samples; a part without the sums is
/// refused.
#[test]
fn merge_denoise_gives_the_single_renders_image() {
    let dir = ScratchDir::new("denoise-merge");
    std::fs::write(dir.join("s.pbrt"), scene(true)).unwrap();
    // two rows of 16-pixel tiles, one per part
    let render = |args: &[&str]| {
        let mut all = vec!["render", "s.pbrt", "--quiet", "--resolution", "16x32"];
        all.extend(args);
        let o = run_in(&dir, &all);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    render(&["-o", "whole.exr", "--denoise", "--denoise-inputs"]);
    render(&["-o", "p0.exr", "--denoise", "--split", "0/2"]);
    render(&["-o", "p1.exr", "--denoise", "--split", "1/2"]);
    render(&["-o", "plain1.exr", "--split", "1/2"]);
    let merge = |args: &[&str]| {
        let mut all = vec!["merge", "p0.exr"];
        all.extend(args);
        run_in(&dir, &all)
    };
    let o = merge(&["p1.exr", "-o", "m.exr", "--denoise", "--denoise-inputs"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for name in ["", ".noisy", ".albedo", ".normal"] {
        let (m, w) = (format!("m{name}.exr"), format!("whole{name}.exr"));
        assert_eq!(read_exr(&dir.join(&m)), read_exr(&dir.join(&w)), "{m}");
    }
    // the denoised image is not the noisy one
    assert_ne!(
        read_exr(&dir.join("m.exr")),
        read_exr(&dir.join("m.noisy.exr"))
    );
    // Split by samples (1 + 3 of the 4): the colour sums are exact, the auxiliary ones add
    // in another order (last bits of an f64), so the denoised image agrees to float rounding.
    render(&["-o", "s0.exr", "--denoise", "--samples", "0..1"]);
    render(&["-o", "s1.exr", "--denoise", "--samples", "1..4"]);
    let o = run_in(
        &dir,
        &[
            "merge",
            "s0.exr",
            "s1.exr",
            "-o",
            "s.exr",
            "--denoise",
            "--denoise-inputs",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let noisy = read_exr(&dir.join("s.noisy.exr"));
    assert_eq!(noisy, read_exr(&dir.join("whole.noisy.exr")));
    for (name, tol) in [(".albedo", 1e-6), (".normal", 1e-6), ("", 1e-4)] {
        let (s, w) = (format!("s{name}.exr"), format!("whole{name}.exr"));
        let (s, w) = (read_exr(&dir.join(&s)), read_exr(&dir.join(&w)));
        let worst = s
            .rgb
            .iter()
            .flatten()
            .zip(w.rgb.iter().flatten())
            .map(|(a, b)| (a - b).abs() / b.abs().max(1e-2))
            .fold(0.0, f64::max);
        assert!(
            worst <= tol,
            "s{name}.exr: worst relative difference {worst}"
        );
    }
    let o = merge(&["plain1.exr", "-o", "x.exr", "--denoise"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("plain1.exr has no denoiser's albedo and normal sums"),
        "{err}"
    );
    assert!(!dir.join("x.exr").exists());
}

#[test]
fn denoise_refuses_what_it_cannot_do_yet() {
    let dir = ScratchDir::new("denoise-refuse");
    std::fs::write(dir.join("s.pbrt"), scene(false)).unwrap();
    let o = run_in(
        &dir,
        &[
            "render",
            "s.pbrt",
            "-o",
            "p.exr",
            "--quiet",
            "--denoise",
            "--denoise-inputs",
            "--samples",
            "0..2",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("--denoise-inputs with a part"), "{err}");
    let o = run_in(
        &dir,
        &["render", "s.pbrt", "-o", "p.exr", "--denoise-inputs"],
    );
    assert_eq!(o.status.code(), Some(2), "--denoise-inputs needs --denoise");
}

/// A `--denoise` render interrupted (SIGINT after its first checkpoint; `--checkpoint-every`
/// keeps writing them) and continued, by `--resume` and by the same command line run again
/// with `--resume-if-exists` (a requeued job), ends with the uninterrupted render's bytes,
/// denoised image and denoiser's inputs alike: the checkpoint keeps the albedo and normal sums
/// of its finished work bit for bit, and the work left adds to them in the same order.
#[test]
fn an_interrupted_denoise_render_resumes_to_the_uninterrupted_bytes() {
    let dir = ScratchDir::new("denoise-resume");
    let scene = data("pt/cbox.pbrt");
    let opts = ["--spp", "1024", "--seed", "9", "--resolution", "48x48"];
    let denoise = ["--denoise", "--denoise-inputs"];
    let full = dir.join("full.exr");
    render_ok(&dir, &scene, &full, &[&opts[..], &denoise].concat());
    let outputs = |stem: &str| -> Vec<Vec<u8>> {
        ["exr", "noisy.exr", "albedo.exr", "normal.exr"]
            .iter()
            .map(|e| std::fs::read(dir.join(format!("{stem}.{e}"))).unwrap())
            .collect()
    };
    let expected = outputs("full");

    // The job's command line: continues its checkpoint if there is one, else starts afresh.
    let job = |out: &str, extra: &[&str]| {
        let mut c = lancer();
        c.current_dir(&dir)
            .args(["render", scene.to_str().unwrap(), "-o", out])
            .args(["--resume-if-exists", "--checkpoint-every", "0.001"])
            .args(opts)
            .args(extra)
            .stdout(Stdio::null())
            .stderr(Stdio::piped());
        c
    };
    let ckpt = dir.join("int.exr.ckpt");
    let job_denoise = [&denoise[..], &["--quiet"]].concat();
    let o =
        signal_after_first_checkpoint(job("int.exr", &job_denoise).spawn().unwrap(), &ckpt, "INT");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("--resume"), "{err}");
    let saved = std::fs::read(&ckpt).unwrap();
    let has = |b: &[u8], s: &[u8]| b.windows(s.len()).any(|w| w == s);
    assert!(
        has(&saved, b"\naux=aux.W,"),
        "the checkpoint keeps the sums"
    );
    // The image so far (the noisy film, not denoised) is short of the finished one's.
    assert!(
        std::fs::read(dir.join("int.exr")).unwrap() != expected[1],
        "the render was not interrupted mid-way"
    );

    // --resume with nothing but the output and the checkpoint.
    resume_ok(&dir, "int.exr");
    assert!(outputs("int") == expected, "resumed render differs");
    assert!(!ckpt.exists(), "the checkpoint was not removed");

    // The job run again unchanged finds the checkpoint and continues it.
    std::fs::write(&ckpt, &saved).unwrap();
    let o = job("int.exr", &denoise).output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("continuing the render saved there"), "{err}");
    assert!(outputs("int") == expected, "requeued render differs");
    assert!(!ckpt.exists(), "the checkpoint was not removed");

    // A checkpoint of a render without --denoise has no sums for its finished work: going
    // on with --denoise is refused either way, naming the file, and the checkpoint is kept.
    let plain = dir.join("plain.exr.ckpt");
    let o = signal_after_first_checkpoint(
        job("plain.exr", &["--quiet"]).spawn().unwrap(),
        &plain,
        "INT",
    );
    assert_eq!(o.status.code(), Some(130));
    assert!(!has(&std::fs::read(&plain).unwrap(), b"\naux="));
    for o in [
        run_in(
            &dir,
            &[
                "render",
                "-o",
                "p2.exr",
                "--resume",
                "plain.exr.ckpt",
                "--denoise",
            ],
        ),
        job("plain.exr", &denoise).output().unwrap(),
    ] {
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains(
                "plain.exr.ckpt: this checkpoint was written by a render without --denoise"
            ),
            "{err}"
        );
        assert!(plain.exists() && !dir.join("p2.exr").exists());
    }
}
