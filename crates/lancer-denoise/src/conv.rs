//! The 3×3 convolution (stride 1, zero padding 1) with bias and ReLU, the network's only
//! heavy operation: out[o](p) = max(0, b[o] + Σ_i Σ_{dy,dx ∈ {-1,0,1}} w[o,i,dy,dx]·in[i](p + (dy, dx))).
//!
//! Direct convolution on padded planes ([`Tensor`]): in a plane of row stride S the
//! neighbour (dy, dx) of flat index p is p + dy·S + dx, so a run of consecutive flat indices
//! is convolved as one 1-D sequence (the padding columns in it are computed too, and zeroed
//! afterwards). The inner block keeps `OCB` output channels × `NV` vectors of 8 pixels in
//! registers; per input channel and tap it loads `NV` pixel vectors and broadcasts `OCB`
//! weights (AVX2 + FMA on x86-64-v3, a plain-array fallback elsewhere).

use crate::tensor::Tensor;
use rayon::prelude::*;

/// 8-lane vectors: AVX2 + FMA where the build has them (the intrinsics are compiled only
/// when the target has these features, so they never run on a CPU without them).
#[cfg(all(
    target_arch = "x86_64",
    target_feature = "avx2",
    target_feature = "fma"
))]
mod avx2 {
    use core::arch::x86_64::*;
    pub type V = __m256;
    /// Eight floats from `p` (unaligned). Safety: `p..p+8` readable.
    #[inline(always)]
    pub unsafe fn load(p: *const f32) -> V {
        unsafe { _mm256_loadu_ps(p) }
    }
    /// `*p` in every lane. Safety: `p` readable.
    #[inline(always)]
    pub unsafe fn splat(p: *const f32) -> V {
        unsafe { _mm256_broadcast_ss(&*p) }
    }
    /// The lanes to `p..p+8` (unaligned). Safety: `p..p+8` writable.
    #[inline(always)]
    pub unsafe fn store(p: *mut f32, v: V) {
        unsafe { _mm256_storeu_ps(p, v) }
    }
    /// a·b + c, one rounding.
    #[inline(always)]
    pub fn fma(a: V, b: V, c: V) -> V {
        unsafe { _mm256_fmadd_ps(a, b, c) }
    }
    /// max(a, 0).
    #[inline(always)]
    pub fn relu(a: V) -> V {
        unsafe { _mm256_max_ps(a, _mm256_setzero_ps()) }
    }
}

/// 8-lane vectors as plain arrays, the same arithmetic (fused multiply-adds): the fallback
/// where AVX2 + FMA are not enabled, also compiled in tests, which compare it with the
/// vectors the build uses.
#[cfg(any(
    test,
    not(all(
        target_arch = "x86_64",
        target_feature = "avx2",
        target_feature = "fma"
    ))
))]
mod portable {
    pub type V = [f32; 8];
    /// Eight floats from `p` (unaligned). Safety: `p..p+8` readable.
    #[inline(always)]
    pub unsafe fn load(p: *const f32) -> V {
        unsafe { std::ptr::read_unaligned(p as *const V) }
    }
    /// `*p` in every lane. Safety: `p` readable.
    #[inline(always)]
    pub unsafe fn splat(p: *const f32) -> V {
        unsafe { [*p; 8] }
    }
    /// The lanes to `p..p+8` (unaligned). Safety: `p..p+8` writable.
    #[inline(always)]
    pub unsafe fn store(p: *mut f32, v: V) {
        unsafe { std::ptr::write_unaligned(p as *mut V, v) }
    }
    /// a·b + c, one rounding.
    #[inline(always)]
    pub fn fma(a: V, b: V, c: V) -> V {
        std::array::from_fn(|i| a[i].mul_add(b[i], c[i]))
    }
    /// max(a, 0).
    #[inline(always)]
    pub fn relu(a: V) -> V {
        a.map(|x| x.max(0.0))
    }
}

#[cfg(all(
    target_arch = "x86_64",
    target_feature = "avx2",
    target_feature = "fma"
))]
use avx2 as simd;
#[cfg(not(all(
    target_arch = "x86_64",
    target_feature = "avx2",
    target_feature = "fma"
)))]
use portable as simd;
use simd::V;

/// A convolution layer's weights, packed for the inner block.
#[derive(Clone, Debug)]
pub struct Conv {
    /// Input channels.
    pub cin: usize,
    /// Output channels.
    pub cout: usize,
    /// Output channels per register block.
    ocb: usize,
    /// Per block of `ocb` output channels: [input channel][tap 0..9][ocb] (zero-padded
    /// channels past `cout`).
    packed: Vec<f32>,
    /// Biases, zero-padded to a whole number of blocks.
    bias: Vec<f32>,
}

/// Pixel vectors per block for a register block of `ocb` output channels.
fn vectors_for(ocb: usize) -> usize {
    if ocb == 4 { 3 } else { 4 }
}

impl Conv {
    /// A layer from OIDN's `oihw` weights (cout × cin × 3 × 3) and biases.
    pub fn new(cout: usize, cin: usize, weight: &[f32], bias: &[f32]) -> Self {
        assert_eq!(weight.len(), cout * cin * 9);
        assert_eq!(bias.len(), cout);
        let ocb = if cout.is_multiple_of(4) { 4 } else { 3 };
        let blocks = cout.div_ceil(ocb);
        let mut packed = vec![0.0; blocks * cin * 9 * ocb];
        for o in 0..cout {
            let (b, j) = (o / ocb, o % ocb);
            for i in 0..cin {
                for k in 0..9 {
                    packed[((b * cin + i) * 9 + k) * ocb + j] = weight[(o * cin + i) * 9 + k];
                }
            }
        }
        let mut b = bias.to_vec();
        b.resize(blocks * ocb, 0.0);
        Self {
            cin,
            cout,
            ocb,
            packed,
            bias: b,
        }
    }

    /// Convolves channels `c0..c0+cin` of `src`, then ReLU (every layer of OIDN's U-Net has
    /// it), into `dst`, which becomes a tensor of `cout` channels of `src`'s size (its storage
    /// reused: [`Tensor::reshape_for_conv`]).
    pub fn run_into(&self, src: &Tensor, c0: usize, dst: &mut Tensor) {
        assert!(c0 + self.cin <= src.c);
        dst.reshape_for_conv(self.cout, src.h, src.w);
        match self.ocb {
            4 => self.run_blocks::<4, 3>(src, c0, dst),
            3 => self.run_blocks::<3, 4>(src, c0, dst),
            _ => unreachable!(),
        }
        debug_assert_eq!(vectors_for(self.ocb) * 8, chunk_px(self.ocb));
        dst.clear_side_padding();
    }

    fn run_blocks<const OCB: usize, const NV: usize>(
        &self,
        src: &Tensor,
        c0: usize,
        dst: &mut Tensor,
    ) {
        let stride = src.stride();
        let (begin, end) = (stride + 1, (src.h + 1) * stride - 1);
        let cw = 8 * NV;
        // A task: a run of `TASK` blocks of pixels, for every output channel (its input rows
        // stay in the core's cache while the output channels go by).
        const TASK: usize = 8;
        let chunks = (end - begin).div_ceil(cw);
        let tasks = chunks.div_ceil(TASK);
        let splane = src.plane();
        let dplane = dst.plane();
        let src_ptr = SendPtr(src.data[c0 * splane..].as_ptr() as *mut f32);
        let dst_ptr = SendPtr(dst.data.as_mut_ptr());
        let blocks = self.cout.div_ceil(OCB);
        (0..tasks).into_par_iter().for_each(|t| {
            let (sp, dp) = (src_ptr, dst_ptr);
            let p0 = begin + t * TASK * cw;
            let p1 = (p0 + TASK * cw).min(end);
            for b in 0..blocks {
                let w = &self.packed[b * self.cin * 9 * OCB..][..self.cin * 9 * OCB];
                let bias = &self.bias[b * OCB..][..OCB];
                let nout = (self.cout - b * OCB).min(OCB);
                let mut p = p0;
                while p < p1 {
                    let valid = (p1 - p).min(cw);
                    // SAFETY: reads stay within src's planes plus SLACK (p ± stride ± 1,
                    // + cw - 1 < SLACK past the last plane's end; a tensor's storage is at
                    // least its planes + SLACK); writes go to flat indices p..p+valid of
                    // planes b·OCB..b·OCB+nout of dst, which no other task writes (tasks own
                    // disjoint pixel runs).
                    unsafe {
                        block::<OCB, NV>(
                            sp.0.add(p),
                            splane,
                            self.cin,
                            stride,
                            w,
                            bias,
                            dp.0.add(b * OCB * dplane + p),
                            dplane,
                            nout,
                            valid,
                        );
                    }
                    p += cw;
                }
            }
        });
    }
}

/// Pixels per inner block for a register block of `ocb` channels.
fn chunk_px(ocb: usize) -> usize {
    8 * vectors_for(ocb)
}

/// A raw pointer shared by the tasks of one convolution (they touch disjoint outputs).
#[derive(Clone, Copy)]
struct SendPtr(*mut f32);
unsafe impl Send for SendPtr {}
unsafe impl Sync for SendPtr {}

/// One register block: `OCB` output channels × `8·NV` pixels from flat index `src`/`dst`,
/// after ReLU. Stores `nout` channels and the first `valid` pixels.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
unsafe fn block<const OCB: usize, const NV: usize>(
    src: *const f32,
    splane: usize,
    cin: usize,
    stride: usize,
    w: &[f32],
    bias: &[f32],
    dst: *mut f32,
    dplane: usize,
    nout: usize,
    valid: usize,
) {
    unsafe {
        let mut acc: [[V; NV]; OCB] = [[simd::splat(&0.0); NV]; OCB];
        for (o, a) in acc.iter_mut().enumerate() {
            *a = [simd::splat(&bias[o]); NV];
        }
        let mut wp = w.as_ptr();
        for i in 0..cin {
            let base = src.add(i * splane).sub(stride + 1);
            for dy in 0..3 {
                let row = base.add(dy * stride);
                for dx in 0..3 {
                    let mut x: [V; NV] = [simd::splat(&0.0); NV];
                    for (v, xv) in x.iter_mut().enumerate() {
                        *xv = simd::load(row.add(dx + 8 * v));
                    }
                    for (o, a) in acc.iter_mut().enumerate() {
                        let wv = simd::splat(wp.add(o));
                        for v in 0..NV {
                            a[v] = simd::fma(x[v], wv, a[v]);
                        }
                    }
                    wp = wp.add(OCB);
                }
            }
        }
        for (o, a) in acc.iter().enumerate().take(nout) {
            let out = dst.add(o * dplane);
            for (v, &av) in a.iter().enumerate() {
                let av = simd::relu(av);
                if valid >= 8 * (v + 1) {
                    simd::store(out.add(8 * v), av);
                } else if valid > 8 * v {
                    let mut tmp = [0.0f32; 8];
                    simd::store(tmp.as_mut_ptr(), av);
                    std::ptr::copy_nonoverlapping(tmp.as_ptr(), out.add(8 * v), valid - 8 * v);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition, looped directly over an unpadded image (zero outside).
    fn direct(
        cin: usize,
        cout: usize,
        h: usize,
        w: usize,
        img: &[f32],
        wt: &[f32],
        b: &[f32],
    ) -> Vec<f32> {
        let mut out = vec![0.0f64; cout * h * w];
        for o in 0..cout {
            for y in 0..h {
                for x in 0..w {
                    let mut s = b[o] as f64;
                    for i in 0..cin {
                        for dy in 0..3 {
                            for dx in 0..3 {
                                let (yy, xx) =
                                    (y as isize + dy as isize - 1, x as isize + dx as isize - 1);
                                if yy < 0 || xx < 0 || yy >= h as isize || xx >= w as isize {
                                    continue;
                                }
                                let v = img[(i * h + yy as usize) * w + xx as usize] as f64;
                                s += v * wt[((o * cin + i) * 3 + dy) * 3 + dx] as f64;
                            }
                        }
                    }
                    out[(o * h + y) * w + x] = s.max(0.0);
                }
            }
        }
        out.into_iter().map(|v| v as f32).collect()
    }

    /// A deterministic pseudo-random sequence in [-1, 1).
    fn noise(n: usize, seed: u64) -> Vec<f32> {
        lancer_testing::uniform(n, seed)
            .into_iter()
            .map(|u| 2.0 * u - 1.0)
            .collect()
    }

    /// The portable vectors give the build's vectors' bits (the AVX2 ones on x86-64-v3),
    /// through each of their operations, at an unaligned address.
    #[test]
    fn portable_vectors_equal_the_builds() {
        let x = noise(17, 5);
        let (a, b, c) = (&x[1..9], &x[9..17], &x[5..13]);
        let (mut got, mut want) = ([0.0f32; 9], [0.0f32; 9]);
        // SAFETY: every pointer is to 8 floats inside `x`, `got` or `want`.
        unsafe {
            let (pa, pb, pc) = (a.as_ptr(), b.as_ptr(), c.as_ptr());
            let v = simd::relu(simd::fma(simd::load(pa), simd::splat(pb), simd::load(pc)));
            simd::store(want.as_mut_ptr().add(1), v);
            let p = portable::relu(portable::fma(
                portable::load(pa),
                portable::splat(pb),
                portable::load(pc),
            ));
            portable::store(got.as_mut_ptr().add(1), p);
        }
        assert_eq!(got.map(f32::to_bits), want.map(f32::to_bits));
        assert_eq!(got[0], 0.0);
        assert!(got[1..].iter().any(|&v| v > 0.0) && got[1..].contains(&0.0));
    }

    #[test]
    fn convolution_equals_the_direct_loop() {
        // shapes that exercise both register blocks, a partial last block of pixels and a
        // channel offset into the source
        for &(cin, cout, h, w, c0) in &[
            (3, 32, 5, 7, 0),
            (9, 3, 16, 16, 2),
            (13, 8, 11, 40, 1),
            (2, 4, 1, 1, 0),
        ] {
            let img = noise(cin * h * w, 1 + cin as u64);
            let wt = noise(cout * cin * 9, 2 + cout as u64);
            let b = noise(cout, 3);
            let mut t = Tensor::zeros(c0 + cin, h, w);
            for i in 0..cin {
                for y in 0..h {
                    for x in 0..w {
                        let k = t.idx(c0 + i, y, x);
                        t.data[k] = img[(i * h + y) * w + x];
                    }
                }
            }
            let conv = Conv::new(cout, cin, &wt, &b);
            // into a reused buffer of another shape, full of stale values
            let mut out = Tensor::zeros(cout + 2, h + 3, w + 1);
            out.data.fill(f32::NAN);
            conv.run_into(&t, c0, &mut out);
            assert_eq!((out.c, out.h, out.w), (cout, h, w));
            let want = direct(cin, cout, h, w, &img, &wt, &b);
            for o in 0..cout {
                for y in 0..h {
                    for x in 0..w {
                        let (g, e) = (out.at(o, y, x), want[(o * h + y) * w + x]);
                        assert!(
                            (g - e).abs() <= 1e-5 * (1.0 + e.abs()),
                            "{cin}→{cout} {h}x{w} o{o} ({y},{x}): {g} vs {e}"
                        );
                    }
                }
                // the padding ring is zero
                for y in 0..h + 2 {
                    assert_eq!(out.data[o * out.plane() + y * out.stride()], 0.0);
                    assert_eq!(out.data[o * out.plane() + y * out.stride() + w + 1], 0.0);
                }
            }
        }
    }
}
