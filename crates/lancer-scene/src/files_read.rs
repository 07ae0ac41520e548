//! The record of every file a load reads (scene, includes, meshes, textures, spectra), for
//! `lancer info --files`: scenes may name files anywhere (absolute paths, `..`), and users
//! want to know exactly what a render depends on.
//!
//! Readers call [`record`] wherever they open a file. The record is per thread: [`recording`]
//! collects what the closure it runs reads. A loader that reads files on other threads carries
//! the record there with [`current`] and [`with`].

use std::cell::RefCell;
use std::collections::HashSet;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A shared list of the files read so far, in first-read order, without repeats (the set
/// keeps the repeat test constant-time for scenes naming thousands of files).
#[derive(Clone, Debug, Default)]
pub struct Recorder(Arc<Mutex<(Vec<PathBuf>, HashSet<PathBuf>)>>);

impl Recorder {
    /// Adds `path`, made absolute, unless it is already listed.
    pub fn add(&self, path: &Path) {
        let abs = absolute(path);
        let mut files = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if files.1.insert(abs.clone()) {
            files.0.push(abs);
        }
    }

    /// The files listed so far.
    pub fn files(&self) -> Vec<PathBuf> {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).0.clone()
    }
}

thread_local! {
    static CURRENT: RefCell<Option<Recorder>> = const { RefCell::new(None) };
}

/// `path` as an absolute path: canonical when it exists (symbolic links and `..` resolved),
/// else joined to the current folder.
pub fn absolute(path: &Path) -> PathBuf {
    std::fs::canonicalize(path).unwrap_or_else(|_| {
        std::env::current_dir()
            .map(|d| d.join(path))
            .unwrap_or_else(|_| path.to_path_buf())
    })
}

/// Notes that `path` was read, if this thread is recording.
pub fn record(path: &Path) {
    CURRENT.with(|c| {
        if let Some(r) = &*c.borrow() {
            r.add(path);
        }
    });
}

/// The two bytes every gzip stream starts with (RFC 1952, ID1 ID2).
pub const GZIP_MAGIC: [u8; 2] = [0x1f, 0x8b];

/// Reads `path` whole, recording it, and gunzips it when it starts with [`GZIP_MAGIC`] (whatever
/// its name: pbrt-v4 decides by the `.gz` ending, the bytes are the surer sign). Concatenated
/// gzip members are read one after another, as `gunzip` does.
pub fn read_maybe_gzipped(path: &Path) -> std::io::Result<Vec<u8>> {
    record(path);
    let raw = std::fs::read(path)?;
    gunzip_if_compressed(raw)
}

/// `bytes` gunzipped when they start with [`GZIP_MAGIC`], else unchanged.
pub fn gunzip_if_compressed(bytes: Vec<u8>) -> std::io::Result<Vec<u8>> {
    if !bytes.starts_with(&GZIP_MAGIC) {
        return Ok(bytes);
    }
    let mut out = Vec::new();
    std::io::Read::read_to_end(
        &mut flate2::read::MultiGzDecoder::new(bytes.as_slice()),
        &mut out,
    )
    .map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("cannot decompress its gzip data: {e}"),
        )
    })?;
    Ok(out)
}

/// This thread's recorder, to hand to worker threads.
pub fn current() -> Option<Recorder> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Runs `f` with `recorder` (or none) as this thread's recorder, then restores the previous one.
pub fn with<T>(recorder: Option<Recorder>, f: impl FnOnce() -> T) -> T {
    let previous = CURRENT.with(|c| c.replace(recorder));
    struct Restore(Option<Recorder>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let prev = self.0.take();
            CURRENT.with(|c| *c.borrow_mut() = prev);
        }
    }
    let _restore = Restore(previous);
    f()
}

/// Runs `f` and returns its result with the files read meanwhile on this thread (and on threads
/// it handed the recorder to). Nested recordings also report to the outer one.
pub fn recording<T>(f: impl FnOnce() -> T) -> (T, Vec<PathBuf>) {
    let outer = current();
    let recorder = Recorder::default();
    let out = with(Some(recorder.clone()), f);
    let files = recorder.files();
    if let Some(o) = outer {
        for p in &files {
            o.add(p);
        }
    }
    (out, files)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_only_inside_a_recording_and_without_repeats() {
        record(Path::new("outside.txt"));
        let dir = std::env::temp_dir();
        let a = dir.join("lancer-files-read-a");
        let ((), files) = recording(|| {
            record(&a);
            record(Path::new("relative/b.ply"));
            record(&a);
        });
        assert_eq!(files.len(), 2);
        assert_eq!(files[0], absolute(&a));
        assert!(files[1].is_absolute());
        assert!(files[1].ends_with("relative/b.ply"));
        assert!(current().is_none());
    }

    #[test]
    fn gzip_data_is_recognised_by_its_magic_bytes() {
        use std::io::Write;
        let text = b"WorldBegin\nShape \"sphere\"\n";
        let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
        enc.write_all(text).unwrap();
        let gz = enc.finish().unwrap();
        assert_eq!(gz[..2], GZIP_MAGIC);
        assert_eq!(gunzip_if_compressed(gz.clone()).unwrap(), text);
        // Plain text passes unchanged, even if its name said .gz.
        assert_eq!(gunzip_if_compressed(text.to_vec()).unwrap(), text);
        // Two members, as `cat a.gz b.gz` makes, read as one text.
        let mut two = gz.clone();
        two.extend_from_slice(&gz);
        assert_eq!(gunzip_if_compressed(two).unwrap().len(), 2 * text.len());
        // A truncated stream is an error, not a short text.
        let e = gunzip_if_compressed(gz[..gz.len() - 6].to_vec()).unwrap_err();
        assert!(e.to_string().contains("cannot decompress"), "{e}");
    }

    #[test]
    fn worker_threads_report_through_the_handed_recorder() {
        let ((), files) = recording(|| {
            let r = current();
            std::thread::spawn(move || with(r, || record(Path::new("/tmp/from-worker"))))
                .join()
                .unwrap();
        });
        assert_eq!(files, vec![absolute(Path::new("/tmp/from-worker"))]);
    }
}
