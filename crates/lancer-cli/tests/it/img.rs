//! `lancer img diff / convert / info` and `lancer completions`, on tiny synthetic images
//! written by the tests, against values worked out by hand.

use crate::common::{ScratchDir, read_exr, run_in};
use std::path::{Path, PathBuf};
use std::process::Output;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Writes a float EXR of `w × h` pixels given row by row.
fn write_exr(path: &Path, w: usize, h: usize, pixels: &[[f32; 3]]) -> PathBuf {
    assert_eq!(pixels.len(), w * h);
    exr::prelude::write_rgb_file(path, w, h, |x, y| {
        let p = pixels[y * w + x];
        (p[0], p[1], p[2])
    })
    .unwrap();
    path.to_path_buf()
}

/// Runs `lancer ARGS` in `dir`.
fn lancer(dir: &Path, args: &[&str]) -> Output {
    run_in(dir, args)
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `lancer ARGS --json` and parses its output; panics unless it succeeds.
fn json(dir: &Path, args: &[&str]) -> serde_json::Value {
    let mut a = args.to_vec();
    a.push("--json");
    let o = lancer(dir, &a);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap_or_else(|e| panic!("{e}: {}", stdout(&o)))
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// A = (1, 0.5, 0), (3, 0.5, 0.25); B = (1, 1, 0), (2, 0.5, 0.5), as 2 × 1 images.
fn pair(dir: &Path) -> (PathBuf, PathBuf) {
    let a = write_exr(
        &dir.join("a.exr"),
        2,
        1,
        &[[1.0, 0.5, 0.0], [3.0, 0.5, 0.25]],
    );
    let b = write_exr(
        &dir.join("b.exr"),
        2,
        1,
        &[[1.0, 1.0, 0.0], [2.0, 0.5, 0.5]],
    );
    (a, b)
}

#[test]
fn diff_of_an_image_with_itself_is_zero_and_passes_any_threshold() {
    let dir = ScratchDir::new("img-diff-self");
    let (a, _) = pair(&dir);
    let o = lancer(&dir, &["img", "diff", s(&a), s(&a), "--threshold", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("relmse    0.000000"), "{out}");
    assert!(out.contains("R 2.000000  G 0.500000  B 0.125000"), "{out}");
    let v = json(&dir, &["img", "diff", s(&a), s(&a)]);
    for k in ["relmse", "mrse", "mse", "rmse", "mae", "mre"] {
        assert_eq!(v[k], 0.0, "{k}: {v}");
    }
    assert_eq!(v["samples_compared"], 6);
}

#[test]
fn diff_metrics_of_a_known_modified_copy() {
    let dir = ScratchDir::new("img-diff-known");
    let (a, b) = pair(&dir);
    let v = json(&dir, &["img", "diff", s(&a), s(&b)]);
    // Differences 0, −0.5, 0 | 1, 0, −0.25: squares 0.25, 1, 0.0625 over 6 samples.
    let relmse = (0.25 / (1.0 + 0.01) + 1.0 / (4.0 + 0.01) + 0.0625 / (0.25 + 0.01)) / 6.0;
    let mrse = (0.25 / 1.01f64.powi(2) + 1.0 / 2.01f64.powi(2) + 0.0625 / 0.51f64.powi(2)) / 6.0;
    let f = |k: &str| v[k].as_f64().unwrap();
    assert!(close(f("relmse"), relmse, 1e-12), "{v}");
    assert!(close(f("mrse"), mrse, 1e-12), "{v}");
    assert_eq!(f("mse"), 1.3125 / 6.0);
    assert!(close(f("rmse"), (1.3125f64 / 6.0).sqrt(), 1e-15));
    assert_eq!(f("mae"), 1.75 / 6.0);
    // Means A (2, 0.5, 0.125), B (1.5, 0.75, 0.25): relative errors 1/3, 1/3, 1/2.
    assert_eq!(v["means_a"], serde_json::json!([2.0, 0.5, 0.125]));
    assert_eq!(v["means_b"], serde_json::json!([1.5, 0.75, 0.25]));
    assert_eq!(f("mre"), 0.5);

    // The difference image is |A − B|.
    let d = dir.join("d.exr");
    let o = lancer(&dir, &["img", "diff", s(&a), s(&b), "-o", s(&d)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_exr(&d).rgb, vec![[0.0, 0.5, 0.0], [1.0, 0.0, 0.25]]);
}

#[test]
fn threshold_sets_the_exit_status() {
    let dir = ScratchDir::new("img-diff-threshold");
    let (a, b) = pair(&dir);
    let code = |extra: &[&str]| {
        let mut args = vec!["img", "diff", s(&a), s(&b)];
        args.extend_from_slice(extra);
        let o = lancer(&dir, &args);
        (o.status.code().unwrap(), stderr(&o))
    };
    // relmse ≈ 0.12291: above 0.1, below 0.2.
    let (c, err) = code(&["--threshold", "0.1"]);
    assert_eq!(c, 1, "{err}");
    assert!(
        err.contains("relmse 0.122") && err.contains("exceeds --threshold 0.1"),
        "{err}"
    );
    assert_eq!(code(&["--threshold", "0.2"]).0, 0);
    // The relative error of the means is 0.5.
    assert_eq!(code(&["--metric", "mre", "--threshold", "0.49"]).0, 1);
    assert_eq!(code(&["--metric", "mre", "--threshold", "0.5"]).0, 0);
    // MSE 0.21875.
    assert_eq!(code(&["--metric", "mse", "--threshold", "0.2"]).0, 1);
    assert_eq!(code(&["--metric", "mse", "--threshold", "0.25"]).0, 0);
    let (c, err) = code(&["--threshold", "-1"]);
    assert_eq!(c, 2, "{err}");
}

#[test]
fn a_value_not_finite_in_one_image_only_fails_the_threshold() {
    let dir = ScratchDir::new("img-diff-nan");
    let a = write_exr(&dir.join("a.exr"), 1, 1, &[[f32::NAN, 1.0, 1.0]]);
    let b = write_exr(&dir.join("b.exr"), 1, 1, &[[1.0, 1.0, 1.0]]);
    let o = lancer(&dir, &["img", "diff", s(&a), s(&a), "--threshold", "0"]);
    assert!(
        o.status.success(),
        "NaN in both at the same place: {}",
        stderr(&o)
    );
    let o = lancer(&dir, &["img", "diff", s(&a), s(&b), "--threshold", "1"]);
    assert_eq!(o.status.code(), Some(1));
    assert!(
        stderr(&o).contains("1 samples are not finite"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn convert_exposure_doubles_per_stop() {
    let dir = ScratchDir::new("img-convert-exposure");
    let a = write_exr(
        &dir.join("a.exr"),
        2,
        1,
        &[[0.3, 1.0, 0.0], [2.0, 0.25, 7.0]],
    );
    let up = dir.join("up.exr");
    let o = lancer(&dir, &["img", "convert", s(&a), s(&up), "--exposure", "1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let got = read_exr(&up).rgb;
    assert_eq!(got, vec![[0.6f32 as f64, 2.0, 0.0], [4.0, 0.5, 14.0]]);
    let down = dir.join("down.exr");
    let o = lancer(
        &dir,
        &["img", "convert", s(&a), s(&down), "--exposure", "-2"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_exr(&down).rgb[1], [0.5, 0.0625, 1.75]);
}

#[test]
fn tonemaps_on_known_values() {
    let dir = ScratchDir::new("img-convert-tonemap");
    let a = write_exr(&dir.join("a.exr"), 1, 1, &[[1.0, 3.0, 0.0]]);
    let r = dir.join("r.exr");
    let o = lancer(
        &dir,
        &["img", "convert", s(&a), s(&r), "--tonemap", "reinhard"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // x / (1 + x): 1 → 1/2, 3 → 3/4, 0 → 0.
    assert_eq!(read_exr(&r).rgb, vec![[0.5, 0.75, 0.0]]);
    let c = dir.join("c.exr");
    let o = lancer(&dir, &["img", "convert", s(&a), s(&c), "--tonemap", "aces"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // Narkowicz: x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14).
    // 1 → 2.54 / 3.16; 3 → 3·7.56 / (3·7.88 + 0.14) = 22.68 / 23.78.
    let p = read_exr(&c).rgb[0];
    assert!(close(p[0], 2.54 / 3.16, 1e-6), "{p:?}");
    assert!(close(p[1], 22.68 / 23.78, 1e-6), "{p:?}");
    assert_eq!(p[2], 0.0);
    // Exposure comes before the tone mapping: 0.5 · 2¹ = 1 → 1/2.
    let h = write_exr(&dir.join("h.exr"), 1, 1, &[[0.5, 0.5, 0.5]]);
    let o = lancer(
        &dir,
        &[
            "img",
            "convert",
            s(&h),
            s(&r),
            "--exposure",
            "1",
            "--tonemap",
            "reinhard",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(read_exr(&r).rgb, vec![[0.5, 0.5, 0.5]]);
}

/// A 4 × 2 image whose red is `x + 4y`, green twice that, blue 1.
fn ramp(dir: &Path) -> PathBuf {
    let px: Vec<[f32; 3]> = (0..8).map(|i| [i as f32, 2.0 * i as f32, 1.0]).collect();
    write_exr(&dir.join("ramp.exr"), 4, 2, &px)
}

#[test]
fn crop_and_box_resize_by_hand() {
    let dir = ScratchDir::new("img-convert-crop-resize");
    let src = ramp(&dir);
    let out = dir.join("out.exr");
    let convert = |extra: &[&str]| {
        let mut args = vec!["img", "convert", s(&src), s(&out)];
        args.extend_from_slice(extra);
        let o = lancer(&dir, &args);
        assert!(o.status.success(), "{extra:?}: {}", stderr(&o));
        let img = read_exr(&out);
        (
            img.width,
            img.height,
            img.rgb.iter().map(|p| p[0]).collect::<Vec<_>>(),
        )
    };
    // Columns 1..3 of both rows: 1 2 / 5 6.
    assert_eq!(
        convert(&["--crop", "1,3,0,2"]),
        (2, 2, vec![1.0, 2.0, 5.0, 6.0])
    );
    // 4 × 2 → 2 × 1: the 2 × 2 blocks' means, (0+1+4+5)/4 and (2+3+6+7)/4.
    assert_eq!(convert(&["--resize", "2x1"]), (2, 1, vec![2.5, 4.5]));
    // 3 columns (0 1 2 / 4 5 6) → 2 × 1: new pixel 0 covers column 0 and half of column 1,
    // weights 2/3 and 1/3: (2/3)·(0+4)/2 + (1/3)·(1+5)/2 = 7/3; pixel 1 likewise 11/3.
    let (w, h, r) = convert(&["--crop", "0,3,0,2", "--resize", "2x1"]);
    assert_eq!((w, h), (2, 1));
    assert!(
        close(r[0], 7.0 / 3.0, 1e-6) && close(r[1], 11.0 / 3.0, 1e-6),
        "{r:?}"
    );
    // Enlarging repeats pixels: 4 × 2 → 8 × 2.
    let (_, _, r) = convert(&["--resize", "8x2"]);
    assert_eq!(&r[..8], &[0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 3.0, 3.0]);

    let o = lancer(
        &dir,
        &["img", "convert", s(&src), s(&out), "--crop", "2,5,0,1"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("goes past the image's 4x2 pixels"),
        "{}",
        stderr(&o)
    );
    let o = lancer(
        &dir,
        &["img", "convert", s(&src), s(&out), "--crop", "1,2,3"],
    );
    assert_eq!(o.status.code(), Some(2));
    let o = lancer(
        &dir,
        &["img", "convert", s(&src), s(&out), "--resize", "0x4"],
    );
    assert_eq!(o.status.code(), Some(2));
    let big = [
        "img",
        "convert",
        s(&src),
        s(&out),
        "--resize",
        "65536x65536",
    ];
    let o = lancer(&dir, &big);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("at most 268435456 pixels"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn convert_between_exr_and_png() {
    let dir = ScratchDir::new("img-convert-png");
    let a = write_exr(
        &dir.join("a.exr"),
        2,
        1,
        &[[1.0, 0.5, 0.0], [4.0, -1.0, 0.25]],
    );
    let png = dir.join("a.png");
    let o = lancer(&dir, &["img", "convert", s(&a), s(&png)]);
    assert!(o.status.success(), "{}", stderr(&o));
    // 8-bit sRGB, clamped: 1 → 255, 0.5 → 0.7354 → 188, 0 → 0, 4 → 255, −1 → 0, 0.25 → 137.
    let mut dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()))
        .read_info()
        .unwrap();
    let mut buf = vec![0; dec.output_buffer_size().unwrap()];
    dec.next_frame(&mut buf).unwrap();
    assert_eq!(&buf[..6], &[255, 188, 0, 255, 0, 137]);
    // And back: the PNG decoded to linear.
    let back = dir.join("back.exr");
    let o = lancer(&dir, &["img", "convert", s(&png), s(&back)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let p = read_exr(&back).rgb;
    assert_eq!(p[0][0], 1.0);
    assert!(close(p[0][1], 0.5, 0.004), "{p:?}");
}

#[test]
fn info_counts_nan_and_infinity() {
    let dir = ScratchDir::new("img-info");
    let a = write_exr(
        &dir.join("a.exr"),
        2,
        2,
        &[
            [1.0, 2.0, 0.5],
            [f32::NAN, 4.0, 0.5],
            [3.0, f32::INFINITY, 0.5],
            [5.0, f32::NEG_INFINITY, 0.5],
        ],
    );
    let v = json(&dir, &["img", "info", s(&a)]);
    assert_eq!(
        (v["width"].as_u64(), v["height"].as_u64()),
        (Some(2), Some(2))
    );
    assert_eq!(v["channels"], serde_json::json!(["R", "G", "B"]));
    // R: NaN left out, mean (1+3+5)/3 = 3; G: two infinities left out, mean (2+4)/2 = 3.
    let r = &v["stats"]["R"];
    assert_eq!(
        (r["mean"].as_f64(), r["min"].as_f64(), r["max"].as_f64()),
        (Some(3.0), Some(1.0), Some(5.0))
    );
    assert_eq!((r["nan"].as_u64(), r["inf"].as_u64()), (Some(1), Some(0)));
    let g = &v["stats"]["G"];
    assert_eq!(
        (g["mean"].as_f64(), g["nan"].as_u64(), g["inf"].as_u64()),
        (Some(3.0), Some(0), Some(2))
    );
    assert_eq!(v["stats"]["B"]["mean"].as_f64(), Some(0.5));

    let o = lancer(&dir, &["img", "info", s(&a)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("2x2 pixels, EXR, channels R, G, B (linear)"),
        "{out}"
    );
    assert!(
        out.lines()
            .any(|l| l.starts_with('R')
                && l.split_whitespace().collect::<Vec<_>>()[4..] == ["1", "0"]),
        "{out}"
    );
}

#[test]
fn errors_name_the_file_and_exit_2() {
    let dir = ScratchDir::new("img-errors");
    let (a, _) = pair(&dir);
    let missing = dir.join("missing.exr");
    let o = lancer(&dir, &["img", "info", s(&missing)]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.starts_with(&format!("error: cannot read {}: ", missing.display())),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");

    let o = lancer(&dir, &["img", "diff", s(&a), s(&missing)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot read"), "{}", stderr(&o));

    let big = write_exr(&dir.join("big.exr"), 1, 2, &[[0.0; 3], [0.0; 3]]);
    let o = lancer(&dir, &["img", "diff", s(&a), s(&big), "--threshold", "1"]);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains(&format!(
            "cannot compare {} (2x1) with {} (1x2): the sizes differ",
            a.display(),
            big.display()
        )),
        "{err}"
    );

    let o = lancer(&dir, &["img", "convert", s(&a), s(&dir.join("out.tiff"))]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("out.tiff: unknown image format"),
        "{}",
        stderr(&o)
    );

    let o = lancer(
        &dir,
        &[
            "img",
            "convert",
            s(&a),
            s(&dir.join("no/such/folder/out.exr")),
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("cannot write"), "{}", stderr(&o));

    let text = dir.join("text.exr");
    std::fs::write(&text, "not an image").unwrap();
    let o = lancer(&dir, &["img", "info", s(&text)]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).starts_with(&format!("error: cannot read {}: ", text.display())),
        "{}",
        stderr(&o)
    );
}

#[test]
fn completions_for_bash_zsh_and_fish() {
    let dir = ScratchDir::new("img-completions");
    for shell in ["bash", "zsh", "fish"] {
        let o = lancer(&dir, &["completions", shell]);
        assert!(o.status.success(), "{shell}: {}", stderr(&o));
        let out = stdout(&o);
        assert!(
            out.contains("lancer") && out.contains("img") && out.contains("threshold"),
            "{shell}"
        );
    }
    assert_eq!(
        lancer(&dir, &["completions", "tcsh"]).status.code(),
        Some(2)
    );
}
