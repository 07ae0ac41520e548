//! Helpers for lancer's own tests, shared by every crate of the workspace as a
//! dev-dependency: scratch folders removed when the test is done, and a deterministic
//! sequence of pseudo-random numbers ([`uniform`]).

use std::ops::Deref;
use std::path::{Path, PathBuf};

/// Set this environment variable (to anything) to keep the tests' scratch folders, to look at
/// what a failing test wrote: `LANCER_KEEP_TEST_FILES=1 cargo test …`.
pub const KEEP_TEST_FILES: &str = "LANCER_KEEP_TEST_FILES";

/// A fresh, empty folder in the system's temporary directory for one test, removed with
/// everything in it when the guard is dropped, also when the test panics. (Each run of the
/// tests used to leave dozens of folders behind; they piled up to gigabytes.)
///
/// The folder is `lancer-test-<test binary>-<process id>-<name>`; `name` must be unique among
/// the tests of one test binary, or two tests running at once would share (and remove) it.
/// When [`KEEP_TEST_FILES`] is set, the folder is kept and its path printed (shown with a
/// failing test's output).
///
/// The guard dereferences to the folder's [`Path`], so `dir.join("file")` and `&dir` work where
/// a path is expected. Bind it to a variable that lives as long as the files are used:
/// `let f = ScratchDir::new("x").join("f")` removes the folder at the end of the statement.
#[derive(Debug)]
#[must_use = "the folder is removed when the ScratchDir is dropped"]
pub struct ScratchDir {
    path: PathBuf,
}

impl ScratchDir {
    /// Creates the folder for the test `name`, emptying what an earlier process with the same
    /// id may have left there.
    pub fn new(name: &str) -> ScratchDir {
        // The test binary's name (e.g. `gltf-0123abcd`) says which suite left a kept folder.
        let exe = std::env::current_exe().ok();
        let suite = exe
            .as_deref()
            .and_then(|p| p.file_stem())
            .and_then(|s| s.to_str())
            .unwrap_or("tests");
        let path =
            std::env::temp_dir().join(format!("lancer-test-{suite}-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&path);
        std::fs::create_dir_all(&path)
            .unwrap_or_else(|e| panic!("cannot create {}: {e}", path.display()));
        ScratchDir { path }
    }
}

impl Deref for ScratchDir {
    type Target = Path;

    fn deref(&self) -> &Path {
        &self.path
    }
}

impl AsRef<Path> for ScratchDir {
    fn as_ref(&self) -> &Path {
        &self.path
    }
}

impl Drop for ScratchDir {
    fn drop(&mut self) {
        if std::env::var_os(KEEP_TEST_FILES).is_some() {
            eprintln!("{KEEP_TEST_FILES} is set: keeping {}", self.path.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.path);
        }
    }
}

/// `n` pseudo-random numbers in [0, 1), a pure function of `seed`: xorshift64 (shifts 13, 7,
/// 17) from the state `seed`·0x9E3779B97F4A7C15 | 1, each number the state's top 24 bits
/// / 2²⁴ (exact in f32). `tools/oidn_golden.py` makes the same sequence, so keep it.
pub fn uniform(n: usize, seed: u64) -> Vec<f32> {
    let mut s = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..n)
        .map(|_| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 40) as f32 / (1u64 << 24) as f32
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scratch_dir_is_fresh_and_removed_when_dropped() {
        let dir = ScratchDir::new("scratch-self-test");
        std::fs::create_dir(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/f"), b"x").unwrap();
        let path = dir.to_path_buf();
        drop(dir);
        if std::env::var_os(KEEP_TEST_FILES).is_none() {
            assert!(!path.exists(), "{} is left", path.display());
        }
        // What an earlier process left under the same name is cleared.
        std::fs::create_dir_all(&path).unwrap();
        std::fs::write(path.join("stale"), b"x").unwrap();
        let dir = ScratchDir::new("scratch-self-test");
        assert!(std::fs::read_dir(&dir).unwrap().next().is_none());
    }
}
