//! Fits the RGB → spectrum coefficient table of `src/spectrum/table.rs` at compile time, so
//! that no process pays for it.
//!
//! The fit is `src/spectrum/fit.rs` itself, included here with the CIE tables it reads: plain
//! IEEE arithmetic in a fixed order, so any build of it gives the table the library would fit,
//! bit for bit (the library's tests check it). The tables go to `$OUT_DIR/uplift_table.bin`
//! (sRGB) and `$OUT_DIR/uplift_table_rec2020.bin` (Rec. 2020, for colours outside the sRGB
//! gamut) as little-endian `f32`, 2.3 MB each; they are fitted at each clean build rather than
//! committed, as they do not compress (deflate keeps 94 % of one, xz 58 % after byte-plane
//! shuffling and deltas).
//!
//! Build scripts are compiled without optimisation (unless the workspace's profile says
//! otherwise, which a crate's own manifest cannot), and unoptimised the fit takes 18 s of
//! processor time (40–60 s on a busy two-core machine). So this script compiles itself once
//! more, optimised for the build machine (`rustc -C opt-level=2 -C target-cpu=native`, about
//! 1 s), into `$OUT_DIR` and runs that copy with `--fit DIR THREADS` to write the tables (0.5 s
//! of processor time each). Should that fail, it fits the table itself, slowly (the same table, bit
//! for bit), and says so in a cargo warning.

#[allow(dead_code)]
#[path = "src/spectrum/cie.rs"]
mod cie;
#[allow(dead_code)]
#[path = "src/spectrum/fit.rs"]
mod fit;

use std::path::{Path, PathBuf};
use std::process::Command;

/// The tables fitted: file name in `$OUT_DIR` and the rows of their XYZ → RGB matrix.
const TABLES: [(&str, &[[f64; 3]; 3]); 2] = [
    ("uplift_table.bin", &cie::XYZ_TO_SRGB),
    ("uplift_table_rec2020.bin", &cie::XYZ_TO_REC2020),
];

/// Fits every table of [`TABLES`] on `threads` threads and writes them into `dir`.
fn fit_to(dir: &Path, threads: usize) {
    for (name, matrix) in TABLES {
        fit_one(&dir.join(name), threads, matrix);
    }
}

/// Fits one table on `threads` threads and writes it to `path`: each coefficient an `f32`,
/// little-endian, in the table's index order (`fit::table_index`).
fn fit_one(path: &Path, threads: usize, matrix: &[[f64; 3]; 3]) {
    let coeffs = fit::fit_table(threads, matrix);
    let bytes: Vec<u8> = coeffs
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    std::fs::write(path, bytes)
        .unwrap_or_else(|e| panic!("cannot write the coefficient table {}: {e}", path.display()));
}

/// Compiles this file with optimisation into `out_dir` and runs it to fit the tables into
/// `path` (a directory); an error says which step failed.
fn fit_optimised(out_dir: &Path, path: &Path, threads: usize) -> Result<(), String> {
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let dir = std::env::var_os("CARGO_MANIFEST_DIR").ok_or("CARGO_MANIFEST_DIR is not set")?;
    let source = Path::new(&dir).join("build.rs");
    let exe = out_dir.join(format!("fit_uplift_table{}", std::env::consts::EXE_SUFFIX));
    let status = Command::new(&rustc)
        .args([
            "--edition=2024",
            "--crate-type=bin",
            "--crate-name=fit_uplift_table",
        ])
        .args([
            "-C",
            "opt-level=2",
            "-C",
            "debuginfo=0",
            "-C",
            "target-cpu=native",
        ])
        .arg("--cap-lints=allow")
        .arg("-o")
        .arg(&exe)
        .arg(&source)
        .status()
        .map_err(|e| format!("cannot run {}: {e}", rustc.to_string_lossy()))?;
    if !status.success() {
        return Err(format!(
            "{} failed on {}: {status}",
            rustc.to_string_lossy(),
            source.display()
        ));
    }
    let status = Command::new(&exe)
        .arg("--fit")
        .arg(path)
        .arg(threads.to_string())
        .status()
        .map_err(|e| format!("cannot run {}: {e}", exe.display()));
    // The helper (4 MB) has done its work either way.
    let _ = std::fs::remove_file(&exe);
    let status = status?;
    if !status.success() {
        return Err(format!("{} failed: {status}", exe.display()));
    }
    Ok(())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() == 4 && args[1] == "--fit" {
        // The optimised copy, run by the build script below.
        fit_to(
            Path::new(&args[2]),
            args[3].parse().expect("a thread count"),
        );
        return;
    }
    for input in ["build.rs", "src/spectrum/cie.rs", "src/spectrum/fit.rs"] {
        println!("cargo::rerun-if-changed={input}");
    }
    // Cargo's job count, else the machine's parallelism: the table does not depend on it.
    let threads = std::env::var("NUM_JOBS")
        .ok()
        .and_then(|n| n.parse().ok())
        .or_else(|| std::thread::available_parallelism().ok().map(|n| n.get()))
        .unwrap_or(1);
    let out_dir = PathBuf::from(std::env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    if let Err(e) = fit_optimised(&out_dir, &out_dir, threads) {
        println!("cargo::warning=fitting the RGB → spectrum tables unoptimised ({e})");
        fit_to(&out_dir, threads);
    }
}
