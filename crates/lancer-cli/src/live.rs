//! The image so far, shared between the render's workers and the live outputs (the PNG
//! preview, [`crate::preview`], and the tev stream, [`crate::tev`]).
//!
//! Workers hand each finished tile to [`LiveImage::update_tile`] (a copy under a lock, no I/O);
//! the outputs run on their own threads and read from it.

use lancer::film::{PixelBounds, PixelSum};
use lancer::math::Rgb;
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// The image as it converges, over the rendered pixel bounds (coordinates relative to them).
pub struct LiveImage {
    bounds: PixelBounds,
    scale: f32,
    state: Mutex<State>,
    changed: Condvar,
}

struct State {
    pixels: Vec<Rgb>,
    /// Rectangles updated since the stream last looked (local coordinates).
    dirty: Vec<PixelBounds>,
    /// Whether anyone takes `dirty` (the stream); otherwise it is not kept.
    tracking: bool,
    /// Bumped by every change.
    version: u64,
    /// The final image is in.
    done: bool,
}

impl LiveImage {
    /// A black image over `bounds`; pixel values are multiplied by `scale` (the film's).
    /// `track_dirty`: keep the list of updated rectangles for [`LiveImage::wait_dirty`].
    pub fn new(bounds: PixelBounds, scale: f32, track_dirty: bool) -> Arc<LiveImage> {
        Arc::new(LiveImage {
            bounds,
            scale,
            state: Mutex::new(State {
                pixels: vec![Rgb::ZERO; bounds.area() as usize],
                dirty: Vec::new(),
                tracking: track_dirty,
                version: 0,
                done: false,
            }),
            changed: Condvar::new(),
        })
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.bounds.width(), self.bounds.height())
    }

    /// Takes in a finished tile (full-image coordinates) and the film's sums over it.
    pub fn update_tile(&self, tile: &PixelBounds, sums: &[PixelSum]) {
        let local = PixelBounds {
            x0: tile.x0 - self.bounds.x0,
            x1: tile.x1 - self.bounds.x0,
            y0: tile.y0 - self.bounds.y0,
            y1: tile.y1 - self.bounds.y0,
        };
        let values: Vec<Rgb> = sums.iter().map(|s| s.value() * self.scale).collect();
        let w = self.bounds.width() as usize;
        let tw = local.width() as usize;
        let mut st = self.lock();
        for (row, y) in (local.y0..local.y1).enumerate() {
            let a = y as usize * w + local.x0 as usize;
            st.pixels[a..a + tw].copy_from_slice(&values[row * tw..(row + 1) * tw]);
        }
        if st.tracking {
            st.dirty.push(local);
        }
        st.version += 1;
        drop(st);
        self.changed.notify_all();
    }

    /// Replaces every pixel by the final image (row-major over the bounds) and wakes the
    /// outputs for their last write.
    pub fn finish(&self, pixels: &[Rgb]) {
        let mut st = self.lock();
        st.pixels.copy_from_slice(pixels);
        st.version += 1;
        st.done = true;
        drop(st);
        self.changed.notify_all();
    }

    /// Stops keeping the list of updated rectangles (the stream is gone).
    pub fn stop_tracking(&self) {
        let mut st = self.lock();
        st.tracking = false;
        st.dirty = Vec::new();
    }

    /// Waits up to `timeout` for updated rectangles; returns them (taken) and whether the final
    /// image is in.
    pub fn wait_dirty(&self, timeout: Duration) -> (Vec<PixelBounds>, bool) {
        let st = self.lock();
        let (mut st, _) = self
            .changed
            .wait_timeout_while(st, timeout, |s| s.dirty.is_empty() && !s.done)
            .unwrap_or_else(|e| e.into_inner());
        (std::mem::take(&mut st.dirty), st.done)
    }

    /// The pixels of `rect` (local coordinates) as interleaved RGB floats, row-major.
    pub fn floats(&self, rect: &PixelBounds) -> Vec<f32> {
        let w = self.bounds.width() as usize;
        let st = self.lock();
        let mut out = Vec::with_capacity(rect.area() as usize * 3);
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let p = st.pixels[y as usize * w + x as usize];
                out.extend_from_slice(&[p.x, p.y, p.z]);
            }
        }
        out
    }

    /// A copy of the image and its version.
    pub fn snapshot(&self) -> (Vec<Rgb>, u64) {
        let st = self.lock();
        (st.pixels.clone(), st.version)
    }

    /// Waits until the final image is in or `until` comes; returns whether it is in.
    pub fn wait_done(&self, until: Instant) -> bool {
        let mut st = self.lock();
        while !st.done {
            let now = Instant::now();
            if now >= until {
                break;
            }
            st = self
                .changed
                .wait_timeout(st, until - now)
                .unwrap_or_else(|e| e.into_inner())
                .0;
        }
        st.done
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sum(v: f32) -> PixelSum {
        let mut s = PixelSum::default();
        s.add(Rgb::new(v, 2.0 * v, 3.0 * v), 1.0);
        s
    }

    #[test]
    fn tiles_land_at_their_place_scaled_and_are_reported_once() {
        let bounds = PixelBounds {
            x0: 10,
            x1: 14,
            y0: 20,
            y1: 23,
        };
        let live = LiveImage::new(bounds, 2.0, true);
        let tile = PixelBounds {
            x0: 12,
            x1: 14,
            y0: 21,
            y1: 23,
        };
        live.update_tile(&tile, &[sum(1.0), sum(2.0), sum(3.0), sum(4.0)]);
        let (pixels, _) = live.snapshot();
        assert_eq!(pixels[4 + 2], Rgb::new(2.0, 4.0, 6.0));
        assert_eq!(pixels[4 + 3].x, 4.0);
        assert_eq!(pixels[2 * 4 + 3].z, 24.0);
        assert_eq!(pixels[0], Rgb::ZERO);
        let (dirty, done) = live.wait_dirty(Duration::from_millis(1));
        assert_eq!(
            dirty,
            vec![PixelBounds {
                x0: 2,
                x1: 4,
                y0: 1,
                y1: 3
            }]
        );
        assert!(!done);
        assert_eq!(live.floats(&dirty[0])[..3], [2.0, 4.0, 6.0]);
        assert!(live.wait_dirty(Duration::from_millis(1)).0.is_empty());
        live.finish(&[Rgb::splat(0.5); 12]);
        assert!(live.wait_dirty(Duration::from_millis(1)).1);
        assert_eq!(live.snapshot().0[5], Rgb::splat(0.5));
    }
}
