//! Records what `lancer --version` reports besides the version: the commit the binary was
//! built from (`git rev-parse`, or "unknown" outside a git checkout) and the target it was
//! built for (triple and CPU level, since the CPU level decides which machines can run it).

use std::process::Command;

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
        .filter(|s| !s.is_empty())
}

fn main() {
    let commit = git(&["rev-parse", "--short=12", "HEAD"]).unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=LANCER_COMMIT={commit}");
    // Rebuild the version when HEAD moves: HEAD itself and the branch it points to.
    for name in ["HEAD", "refs/heads"] {
        if let Some(p) = git(&["rev-parse", "--git-path", name]) {
            let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(p);
            println!("cargo:rerun-if-changed={}", p.display());
        }
    }
    if let Some(r) =
        git(&["symbolic-ref", "-q", "HEAD"]).and_then(|r| git(&["rev-parse", "--git-path", &r]))
    {
        let p = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(r);
        println!("cargo:rerun-if-changed={}", p.display());
    }
    println!("cargo:rerun-if-changed=build.rs");
    let target = std::env::var("TARGET").unwrap_or_default();
    // The CPU features the compiler was told it may use (from .cargo/config.toml).
    let features = std::env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    let level = if features.split(',').any(|f| f == "avx2") {
        "x86-64-v3"
    } else {
        "baseline CPU"
    };
    println!("cargo:rustc-env=LANCER_TARGET={target}, {level}");
}
