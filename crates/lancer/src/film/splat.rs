//! Splats: light an integrator puts on any pixel of the film, not only on the one it is
//! sampling (light tracing, bidirectional methods), as pbrt-v4's `Film::AddSplat`.
//!
//! A splat of colour c at film point p adds f(pᵢ − p)/∫f · c to every pixel i whose centre
//! pᵢ = i + ½ lies within the filter's radius of p (pbrt-v4's `RGBFilm::AddSplat`; pbrt-v4
//! divides by ∫f when it reads the pixel, lancer when it adds: the same sum). The sums are
//! the colour sums' fixed point ([`super::to_fixed`]), added with wrapping integer
//! arithmetic, which is associative: whatever the order in which threads, tiles, sample
//! ranges, split parts or checkpoints add them, a pixel's splat sum has the same bits. A
//! pixel's value is then Σw·L/Σw + S/n ([`super::Film::pixel_rgb`]), with S its splat sum
//! and n the film's camera samples per pixel (pbrt-v4's `splatScale` = 1/spp).
//!
//! A render whose integrator never splats has no splat plane at all: its films, parts and
//! checkpoints are the ones they were before splats existed.

use super::{PixelBounds, from_fixed, to_fixed};
use std::sync::atomic::{AtomicI64, Ordering};

/// A film's splat sums: `channels` fixed-point values per pixel of `bounds`, row-major: the
/// colour (R, G, B), then, for a `spectral` film, one value per wavelength bucket.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SplatPlane {
    /// The pixels splats may land on (the whole render's, even for a part of it).
    pub bounds: PixelBounds,
    /// Values per pixel.
    pub channels: usize,
    /// The sums, `channels` per pixel, row-major over `bounds`.
    pub sums: Vec<i64>,
}

impl SplatPlane {
    /// A plane of zeros.
    pub fn new(bounds: PixelBounds, channels: usize) -> SplatPlane {
        SplatPlane {
            bounds,
            channels,
            sums: vec![0; bounds.area() as usize * channels],
        }
    }

    /// The sums of pixel (`x`, `y`) (full-image coordinates), if the plane holds it.
    pub fn pixel(&self, x: i32, y: i32) -> Option<&[i64]> {
        let i = self.bounds.index(x, y)? * self.channels;
        self.sums.get(i..i + self.channels)
    }

    /// Channel `c` of pixel (`x`, `y`) as a float (0 outside the plane).
    pub fn value(&self, x: i32, y: i32, c: usize) -> f64 {
        self.pixel(x, y).map_or(0.0, |p| from_fixed(p[c]))
    }

    /// Adds another plane's sums over the pixels both hold (exact, in any order). Planes with
    /// different channel counts add their common channels.
    pub fn merge(&mut self, o: &SplatPlane) {
        let t = self.bounds.intersect(&o.bounds);
        let c = self.channels.min(o.channels);
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let (Some(d), Some(s)) = (self.bounds.index(x, y), o.bounds.index(x, y)) else {
                    continue;
                };
                let (d, s) = (d * self.channels, s * o.channels);
                for k in 0..c {
                    self.sums[d + k] = self.sums[d + k].wrapping_add(o.sums[s + k]);
                }
            }
        }
    }
}

/// A splat plane that the threads of a render add to at once: each value an atomic integer,
/// so concurrent splats neither lock nor lose anything, and the result does not depend on
/// their order.
#[derive(Debug)]
pub struct AtomicSplats {
    bounds: PixelBounds,
    channels: usize,
    sums: Vec<AtomicI64>,
}

impl AtomicSplats {
    /// A plane of zeros.
    pub fn new(bounds: PixelBounds, channels: usize) -> AtomicSplats {
        AtomicSplats {
            bounds,
            channels,
            sums: (0..bounds.area() as usize * channels)
                .map(|_| AtomicI64::new(0))
                .collect(),
        }
    }

    /// The pixels it holds.
    pub fn bounds(&self) -> PixelBounds {
        self.bounds
    }

    /// Adds `values[c]` (one per channel, fewer leave the rest alone) to pixel (`x`, `y`);
    /// nothing outside the plane.
    #[inline]
    pub fn add(&self, x: i32, y: i32, values: &[f32]) {
        let Some(i) = self.bounds.index(x, y).map(|i| i * self.channels) else {
            return;
        };
        for (s, &v) in self.sums[i..i + self.channels].iter().zip(values) {
            let v = to_fixed(v);
            if v != 0 {
                // Wrapping addition: associative, so the order of the threads does not matter.
                s.fetch_add(v, Ordering::Relaxed);
            }
        }
    }

    /// Adds the single value `v` to channel `c` of pixel (`x`, `y`) (nothing outside).
    #[inline]
    pub fn add_channel(&self, x: i32, y: i32, c: usize, v: f32) {
        let Some(i) = self.bounds.index(x, y).filter(|_| c < self.channels) else {
            return;
        };
        let i = i * self.channels;
        let v = to_fixed(v);
        if v != 0 {
            self.sums[i + c].fetch_add(v, Ordering::Relaxed);
        }
    }

    /// The sums as a plain plane.
    pub fn into_plane(self) -> SplatPlane {
        SplatPlane {
            bounds: self.bounds,
            channels: self.channels,
            sums: self.sums.into_iter().map(AtomicI64::into_inner).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planes_merge_exactly_over_their_common_pixels() {
        let a_b = PixelBounds {
            x0: 0,
            x1: 4,
            y0: 0,
            y1: 3,
        };
        let b_b = PixelBounds {
            x0: 2,
            x1: 6,
            y0: 1,
            y1: 2,
        };
        let acc = AtomicSplats::new(b_b, 3);
        acc.add(3, 1, &[1.0, 2.0, 3.0]);
        acc.add(5, 1, &[1.0, 1.0, 1.0]);
        acc.add(9, 9, &[1.0, 1.0, 1.0]);
        acc.add_channel(3, 1, 2, 0.5);
        let b = acc.into_plane();
        assert_eq!(b.value(3, 1, 2), 3.5);
        let mut a = SplatPlane::new(a_b, 3);
        a.merge(&b);
        assert_eq!(a.value(3, 1, 0), 1.0);
        assert_eq!(a.value(3, 1, 2), 3.5);
        // (5, 1) is outside `a`.
        assert_eq!(a.sums.iter().filter(|&&s| s != 0).count(), 3);
        // Merging in the other order gives the same sums.
        let mut c = SplatPlane::new(a_b, 3);
        let mut b2 = b.clone();
        b2.merge(&SplatPlane::new(b_b, 3));
        c.merge(&b2);
        assert_eq!(a, c);
    }
}
