//! Helpers shared by the command-line tests: running `lancer`, reading EXR images, comparing
//! them the way the team's acceptance scripts do, scratch folders that go away.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[allow(unused_imports)] // as dead_code above: not every test writes files
pub use lancer_testing::ScratchDir;

/// The `lancer` binary built for these tests.
pub fn lancer() -> Command {
    Command::new(env!("CARGO_BIN_EXE_lancer"))
}

/// Runs `lancer` with `args` in `dir`.
pub fn run_in(dir: &Path, args: &[&str]) -> Output {
    lancer()
        .current_dir(dir)
        .args(args)
        .output()
        .expect("lancer runs")
}

/// Resumes, in `dir`, the render to `out` from the checkpoint `out.ckpt` with nothing but
/// those two (quietly), and panics with lancer's message if it fails.
pub fn resume_ok(dir: &Path, out: &str) {
    let ckpt = format!("{out}.ckpt");
    let o = run_in(dir, &["render", "-o", out, "--resume", &ckpt, "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// Renders `scene` to `out` quietly with `extra` flags, in `dir`; panics with lancer's
/// message if it fails.
pub fn render_ok(dir: &Path, scene: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec![
        "render",
        scene.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let o = run_in(dir, &args);
    assert!(
        o.status.success(),
        "{}: {}",
        scene.display(),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Test data shipped with the crate.
pub fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

/// The team's shared folder, when present (`../shared` next to the repository).
pub fn shared() -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared");
    p.is_dir().then(|| p.canonicalize().unwrap())
}

/// An RGB float image.
#[derive(Clone, Debug, PartialEq)]
pub struct Img {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<[f64; 3]>,
}

/// Reads an EXR's R, G, B channels.
pub fn read_exr(path: &Path) -> Img {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |res, _| Img {
            width: res.width(),
            height: res.height(),
            rgb: vec![[0.0; 3]; res.width() * res.height()],
        },
        |img: &mut Img, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            let w = img.width;
            img.rgb[pos.y() * w + pos.x()] = [r as f64, g as f64, b as f64];
        },
    )
    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    image.layer_data.channel_data.pixels
}

impl Img {
    /// Box-filters the image down by an integer factor.
    pub fn shrink(&self, k: usize) -> Img {
        let (w, h) = (self.width / k, self.height / k);
        let mut rgb = vec![[0.0; 3]; w * h];
        for y in 0..h * k {
            for x in 0..w * k {
                let p = self.rgb[y * self.width + x];
                let q = &mut rgb[(y / k) * w + x / k];
                for c in 0..3 {
                    q[c] += p[c] / (k * k) as f64;
                }
            }
        }
        Img {
            width: w,
            height: h,
            rgb,
        }
    }

    /// Mean of each channel.
    pub fn means(&self) -> [f64; 3] {
        let mut m = [0.0; 3];
        for p in &self.rgb {
            for c in 0..3 {
                m[c] += p[c];
            }
        }
        m.map(|v| v / self.rgb.len() as f64)
    }

    /// The largest relative error of a channel mean against `reference`'s (the acceptance
    /// scripts' "mre"); the images may differ in size.
    pub fn mean_rel_error(&self, reference: &Img) -> f64 {
        let (mt, mr) = (self.means(), reference.means());
        (0..3)
            .map(|c| (mt[c] - mr[c]).abs() / mr[c].max(1e-4))
            .fold(0.0, f64::max)
    }
}

/// The acceptance scripts' comparison: per-channel relative error of the means, and the RMSE
/// over the reference's mean. Panics with both figures when a bound is exceeded.
pub fn compare(name: &str, test: &Img, reference: &Img, max_mre: f64, max_nrmse: f64) {
    assert_eq!(
        (test.width, test.height),
        (reference.width, reference.height),
        "{name}: sizes differ"
    );
    assert!(
        test.rgb.iter().all(|p| p.iter().all(|v| v.is_finite())),
        "{name}: non-finite pixels"
    );
    let (mt, mr) = (test.means(), reference.means());
    let mre = test.mean_rel_error(reference);
    let m = (mr.iter().sum::<f64>() / 3.0).max(1e-6);
    let se: f64 = test
        .rgb
        .iter()
        .zip(&reference.rgb)
        .map(|(a, b)| (0..3).map(|c| (a[c] - b[c]).powi(2)).sum::<f64>())
        .sum::<f64>()
        / (3 * test.rgb.len()) as f64;
    let nrmse = se.sqrt() / m;
    println!("{name}: means {mt:.5?} vs {mr:.5?}, mre {mre:.4}, nrmse {nrmse:.4}");
    assert!(
        mre <= max_mre,
        "{name}: channel means differ by {mre:.4} (> {max_mre})"
    );
    assert!(
        nrmse <= max_nrmse,
        "{name}: nrmse {nrmse:.4} (> {max_nrmse})"
    );
}

/// Waits until the render `child` has written its first checkpoint `ckpt` (failing if the
/// render ends first or none comes within five minutes), then sends it `signal` (`"INT"`,
/// `"HUP"`, …) and returns its output once it has stopped.
pub fn signal_after_first_checkpoint(
    mut child: std::process::Child,
    ckpt: &Path,
    signal: &str,
) -> Output {
    let t0 = std::time::Instant::now();
    while !ckpt.exists() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the render ended before its first checkpoint"
        );
        assert!(
            t0.elapsed() < std::time::Duration::from_secs(300),
            "no checkpoint"
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    let kill = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    child.wait_with_output().unwrap()
}
