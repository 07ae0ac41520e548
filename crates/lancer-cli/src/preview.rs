//! The live outputs of a render: the PNG rewritten every few seconds (`--preview FILE.png`)
//! and the tev stream ([`crate::tev`]), both fed from the [`LiveImage`] the workers update.

use crate::live::LiveImage;
use lancer::film::{PixelBounds, PixelSum};
use lancer::image_io::{encode_png, write_atomic};
use lancer::math::Rgb;
use std::path::PathBuf;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Writes `live` as a PNG to `path` atomically (temporary file, then rename).
pub fn write_png(path: &std::path::Path, live: &LiveImage) -> Result<u64, String> {
    let (pixels, version) = live.snapshot();
    let (w, h) = live.size();
    let bytes = encode_png(w, h, &pixels)?;
    write_atomic(path, &bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(version)
}

/// Starts rewriting the PNG `path` from `live` every `every` (when it changed), and once more
/// with the final image, on a new thread that ends after that last write. A failing write is
/// a warning: the render goes on.
pub fn spawn(path: PathBuf, every: Duration, live: Arc<LiveImage>) -> JoinHandle<()> {
    std::thread::spawn(move || {
        let mut written = None;
        loop {
            let done = live.wait_done(Instant::now() + every);
            let version = live.snapshot().1;
            if done || written != Some(version) {
                match write_png(&path, &live) {
                    Ok(v) => written = Some(v),
                    Err(e) => eprintln!("warning: preview {e}"),
                }
            }
            if done {
                break;
            }
        }
    })
}

/// The live outputs of one render: the PNG preview and the tev stream, either or both.
pub struct LiveOutputs {
    live: Option<Arc<LiveImage>>,
    threads: Vec<JoinHandle<()>>,
}

impl LiveOutputs {
    /// Starts the outputs asked for: `preview` rewritten every `every`, the stream to
    /// `display_server` under the image name `name`. With neither, does nothing.
    pub fn start(
        bounds: PixelBounds,
        scale: f32,
        preview: Option<(PathBuf, Duration)>,
        display_server: Option<(String, String)>,
    ) -> LiveOutputs {
        if preview.is_none() && display_server.is_none() {
            return LiveOutputs {
                live: None,
                threads: Vec::new(),
            };
        }
        let live = LiveImage::new(bounds, scale, display_server.is_some());
        let mut threads = Vec::new();
        if let Some((path, every)) = preview {
            threads.push(spawn(path, every, live.clone()));
        }
        if let Some((address, name)) = display_server {
            threads.push(crate::tev::spawn(address, name, live.clone()));
        }
        LiveOutputs {
            live: Some(live),
            threads,
        }
    }

    /// Takes in a finished tile (see [`LiveImage::update_tile`]).
    pub fn tile(&self, tile: &PixelBounds, sums: &[PixelSum]) {
        if let Some(l) = &self.live {
            l.update_tile(tile, sums);
        }
    }

    /// Hands over the final image (made by `pixels` only when some output is live) and waits
    /// for the outputs' last writes.
    pub fn finish(self, pixels: impl FnOnce() -> Vec<Rgb>) {
        if let Some(l) = &self.live {
            l.finish(&pixels());
        }
        for t in self.threads {
            let _ = t.join();
        }
    }
}
