//! Activations: C planes of H×W floats, each with a one-pixel ring of zeros (a 3×3
//! convolution's zero padding), so the convolution reads its neighbours without bounds tests.
//!
//! Plane c, row y, column x (y in -1..=H, x in -1..=W) is at `c·plane + (y+1)·(W+2) + x+1`.
//! `SLACK` floats after the last plane let a convolution's last vector of pixels read past
//! the last pixel it needs.

use rayon::prelude::*;

/// Floats after the last plane, read (never used) by a vector that overhangs the last plane.
pub const SLACK: usize = 64;

/// A padded planar activation tensor.
#[derive(Clone, Debug)]
pub struct Tensor {
    /// Channels.
    pub c: usize,
    /// Rows (without padding).
    pub h: usize,
    /// Columns (without padding).
    pub w: usize,
    /// The planes, then at least `SLACK` floats (zeros, or old values of a reused buffer).
    pub data: Vec<f32>,
}

impl Tensor {
    /// A tensor of zeros.
    pub fn zeros(c: usize, h: usize, w: usize) -> Self {
        let plane = (h + 2) * (w + 2);
        Self {
            c,
            h,
            w,
            data: vec![0.0; c * plane + SLACK],
        }
    }

    /// Makes this buffer a `c`×`h`×`w` tensor for a convolution to fill, keeping its storage
    /// (grown only if too small), so that a network's layers reuse a few buffers rather than
    /// fault in fresh pages for each output. The top and bottom padding rows of each plane are
    /// zeroed; every other element of the planes is written by the convolution, which zeroes
    /// the side columns itself ([`Tensor::clear_side_padding`]). Storage past the planes may
    /// hold old values: only vectors that overhang the last plane read it, and what they
    /// compute from it is never stored.
    pub fn reshape_for_conv(&mut self, c: usize, h: usize, w: usize) {
        (self.c, self.h, self.w) = (c, h, w);
        let (plane, stride) = (self.plane(), self.stride());
        let need = c * plane + SLACK;
        if self.data.len() < need {
            self.data.resize(need, 0.0);
        }
        for p in self.data[..c * plane].chunks_exact_mut(plane) {
            p[..stride].fill(0.0);
            p[plane - stride..].fill(0.0);
        }
    }

    /// The row stride W+2.
    #[inline]
    pub fn stride(&self) -> usize {
        self.w + 2
    }

    /// The plane size (H+2)·(W+2).
    #[inline]
    pub fn plane(&self) -> usize {
        (self.h + 2) * (self.w + 2)
    }

    /// The index of channel c, pixel (y, x).
    #[inline]
    pub fn idx(&self, c: usize, y: usize, x: usize) -> usize {
        c * self.plane() + (y + 1) * self.stride() + x + 1
    }

    /// The value at channel c, pixel (y, x).
    #[inline]
    pub fn at(&self, c: usize, y: usize, x: usize) -> f32 {
        self.data[self.idx(c, y, x)]
    }

    /// Zeroes the left and right padding columns of every plane (a convolution computes them
    /// as if they were pixels).
    pub fn clear_side_padding(&mut self) {
        let (stride, plane, h) = (self.stride(), self.plane(), self.h);
        self.data[..self.c * plane]
            .par_chunks_mut(plane)
            .for_each(|p| {
                for y in 1..=h {
                    p[y * stride] = 0.0;
                    p[y * stride + stride - 1] = 0.0;
                }
            });
    }
}

/// 2×2 max pooling of `src` into channels `dst_c0..` of `dst` (H/2 × W/2).
pub fn pool_into(src: &Tensor, dst: &mut Tensor, dst_c0: usize) {
    assert!(dst.h == src.h / 2 && dst.w == src.w / 2 && dst_c0 + src.c <= dst.c);
    let (dplane, dstride, sstride) = (dst.plane(), dst.stride(), src.stride());
    let (sw, sh) = (dst.w, dst.h);
    dst.data[dst_c0 * dplane..(dst_c0 + src.c) * dplane]
        .par_chunks_mut(dplane)
        .enumerate()
        .for_each(|(c, d)| {
            let s = &src.data[c * src.plane()..(c + 1) * src.plane()];
            for y in 0..sh {
                let r0 = &s[(2 * y + 1) * sstride + 1..][..2 * sw];
                let r1 = &s[(2 * y + 2) * sstride + 1..][..2 * sw];
                let out = &mut d[(y + 1) * dstride + 1..][..sw];
                for (x, o) in out.iter_mut().enumerate() {
                    *o = r0[2 * x]
                        .max(r0[2 * x + 1])
                        .max(r1[2 * x].max(r1[2 * x + 1]));
                }
            }
        });
}

/// Nearest-neighbour 2× upsampling of `src` into channels `0..src.c` of `dst` (2H × 2W).
pub fn upsample_into(src: &Tensor, dst: &mut Tensor) {
    assert!(dst.h == src.h * 2 && dst.w == src.w * 2 && src.c <= dst.c);
    let (dplane, dstride, sstride) = (dst.plane(), dst.stride(), src.stride());
    let (sw, sh) = (src.w, src.h);
    dst.data[..src.c * dplane]
        .par_chunks_mut(dplane)
        .enumerate()
        .for_each(|(c, d)| {
            let s = &src.data[c * src.plane()..(c + 1) * src.plane()];
            for y in 0..2 * sh {
                let row = &s[(y / 2 + 1) * sstride + 1..][..sw];
                let out = &mut d[(y + 1) * dstride + 1..][..2 * sw];
                for (x, o) in out.iter_mut().enumerate() {
                    *o = row[x / 2];
                }
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_reshaped_buffer_has_a_zero_top_and_bottom_ring_and_keeps_its_storage() {
        let mut t = Tensor::zeros(2, 6, 6);
        t.data.fill(7.0);
        let len = t.data.len();
        t.reshape_for_conv(3, 2, 4);
        assert_eq!((t.c, t.h, t.w, t.data.len()), (3, 2, 4, len));
        for c in 0..3 {
            let p = &t.data[c * t.plane()..(c + 1) * t.plane()];
            assert!(
                p[..6].iter().chain(&p[18..]).all(|&v| v == 0.0),
                "plane {c}"
            );
            assert_eq!(p[7], 7.0, "the interior is the convolution's to write");
        }
        t.reshape_for_conv(4, 8, 8);
        assert_eq!(t.data.len(), 4 * 100 + SLACK);
    }

    #[test]
    fn pool_and_upsample() {
        let mut t = Tensor::zeros(2, 4, 6);
        for c in 0..2 {
            for y in 0..4 {
                for x in 0..6 {
                    let i = t.idx(c, y, x);
                    t.data[i] = (c * 100 + y * 10 + x) as f32;
                }
            }
        }
        let mut p = Tensor::zeros(3, 2, 3);
        pool_into(&t, &mut p, 1);
        assert_eq!(p.at(0, 1, 1), 0.0);
        assert_eq!(p.at(1, 0, 0), 11.0);
        assert_eq!(p.at(2, 1, 2), 135.0);
        let mut u = Tensor::zeros(3, 4, 6);
        upsample_into(&p, &mut u);
        assert_eq!(u.at(1, 3, 5), 35.0);
        assert_eq!(u.at(1, 2, 4), 35.0);
        assert_eq!(u.at(1, 1, 1), 11.0);
        // the padding ring stays zero
        assert_eq!(u.data[u.idx(1, 0, 0) - 1], 0.0);
        assert_eq!(u.data[u.idx(1, 3, 5) + 1], 0.0);
    }
}
