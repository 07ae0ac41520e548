//! Per-pixel samplers whose values depend only on (seed, pixel, sample index, dimension).
//!
//! No sampler keeps state across pixel samples: a pixel's `i`-th sample is the same whichever
//! thread, tile order or machine computes it. That is what makes split renders merge exactly
//! and interrupted renders resume to the same pixels.

use super::hash::{hash_u64, mix_bits, permutation_element, u32_to_unit_f32};
use crate::math::Vec2;

/// Which point set a [`Sampler`] draws from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// Independent uniform random numbers (pbrt's `independent`).
    Independent,
    /// Jittered strata in each 2D pair of dimensions, randomly matched across dimensions
    /// (pbrt's `stratified`); `xsamples × ysamples` strata.
    Stratified {
        /// Strata along x.
        xsamples: u32,
        /// Strata along y.
        ysamples: u32,
        /// Jitter within each stratum (otherwise its centre).
        jitter: bool,
    },
    /// The first two dimensions of the Sobol sequence, Owen-scrambled and shuffled
    /// independently for each pair of dimensions ("padded" Sobol, Burley 2020). Every 2D
    /// projection is a (0, 2)-sequence: well stratified for any power-of-two prefix.
    Sobol,
}

impl SamplerKind {
    /// The pbrt-v4 name of this point set (`Sampler "…"`): `independent`, `stratified`,
    /// `paddedsobol` (pbrt's `sobol` and `zsobol` are read as it too).
    pub fn pbrt_name(&self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Stratified { .. } => "stratified",
            SamplerKind::Sobol => "paddedsobol",
        }
    }
}

/// A sampler positioned at one pixel sample; hands out the sample's dimensions in turn.
#[derive(Clone, Debug)]
pub struct Sampler {
    kind: SamplerKind,
    seed: u64,
    spp: u32,
    pixel: (i32, i32),
    pixel_hash: u64,
    /// Hash of (pixel, sample index): the seed of the sample's independent dimensions.
    sample_hash: u64,
    index: u64,
    dim: u32,
}

/// Reverses the bits of a 32-bit word.
#[inline]
fn reverse_bits(v: u32) -> u32 {
    v.reverse_bits()
}

/// Nested uniform (Owen) scrambling of a 32-bit fixed-point value, in the hash-based form of
/// Burley 2020 ("Practical Hash-based Owen Scrambling", §3): reverse the bits, apply the
/// Laine–Karras permutation, reverse back.
#[inline]
fn owen_scramble(v: u32, seed: u32) -> u32 {
    let mut x = reverse_bits(v);
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    reverse_bits(x)
}

/// Sobol dimension 0: the van der Corput sequence (bit reversal of the index).
#[inline]
fn sobol_0(a: u32) -> u32 {
    reverse_bits(a)
}

/// Sobol dimension 1: generator matrix = Pascal's triangle mod 2, produced by the recurrence
/// vᵢ₊₁ = vᵢ ⊕ (vᵢ >> 1) on the direction numbers.
#[inline]
fn sobol_1(mut a: u32) -> u32 {
    let mut v = 1u32 << 31;
    let mut r = 0u32;
    while a != 0 {
        if a & 1 != 0 {
            r ^= v;
        }
        a >>= 1;
        v ^= v >> 1;
    }
    r
}

impl Sampler {
    /// A sampler of `kind` for `spp` samples per pixel, seeded by `seed`.
    pub fn new(kind: SamplerKind, spp: u32, seed: u64) -> Sampler {
        Sampler {
            kind,
            seed,
            spp: spp.max(1),
            pixel: (0, 0),
            pixel_hash: hash_u64(&[0, 0, seed]),
            sample_hash: 0,
            index: 0,
            dim: 0,
        }
    }

    /// The point set.
    pub fn kind(&self) -> SamplerKind {
        self.kind
    }

    /// Samples per pixel.
    pub fn samples_per_pixel(&self) -> u32 {
        self.spp
    }

    /// Positions the sampler at sample `index` of pixel `(x, y)`, dimension 0.
    #[inline]
    pub fn start_pixel_sample(&mut self, x: i32, y: i32, index: u64) {
        // A pixel's samples are taken in a row: its hash is reused between them.
        if self.pixel != (x, y) {
            self.pixel = (x, y);
            self.pixel_hash = hash_u64(&[x as u32 as u64, y as u32 as u64, self.seed]);
        }
        self.sample_hash = mix_bits(self.pixel_hash ^ index.wrapping_mul(0xd6e8_feb8_6659_fd93));
        self.index = index;
        self.dim = 0;
    }

    /// The sample's next dimension.
    #[inline(always)]
    pub fn get_1d(&mut self) -> f32 {
        let d = self.dim;
        self.dim += 1;
        // The independent case inline (a few instructions), the point sets out of line.
        match self.kind {
            SamplerKind::Independent => self.independent(d),
            _ => self.get_1d_at(d),
        }
    }

    /// Dimension `d` of a stratified or Sobol sample.
    #[inline(never)]
    fn get_1d_at(&self, d: u32) -> f32 {
        let h = mix_bits(self.pixel_hash ^ (d as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        match self.kind {
            SamplerKind::Independent => self.independent(d),
            SamplerKind::Stratified {
                xsamples,
                ysamples,
                jitter,
            } => {
                let n = xsamples * ysamples;
                let stratum = permutation_element((self.index % n as u64) as u32, n, h as u32);
                let delta = if jitter { self.independent(d) } else { 0.5 };
                (stratum as f32 + delta) / n as f32
            }
            SamplerKind::Sobol => {
                let i = owen_scramble(self.index as u32, h as u32);
                u32_to_unit_f32(owen_scramble(sobol_0(i), (h >> 32) as u32))
            }
        }
    }

    /// The sample's next two dimensions.
    #[inline(always)]
    pub fn get_2d(&mut self) -> Vec2 {
        let d = self.dim;
        self.dim += 2;
        match self.kind {
            SamplerKind::Independent => self.independent_2d(d),
            _ => self.get_2d_at(d),
        }
    }

    /// Dimensions `d`, `d + 1` of a stratified or Sobol sample.
    #[inline(never)]
    fn get_2d_at(&self, d: u32) -> Vec2 {
        let h = mix_bits(self.pixel_hash ^ (d as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        match self.kind {
            SamplerKind::Independent => self.independent_2d(d),
            SamplerKind::Stratified {
                xsamples,
                ysamples,
                jitter,
            } => {
                let n = xsamples * ysamples;
                let stratum = permutation_element((self.index % n as u64) as u32, n, h as u32);
                let (sx, sy) = (stratum % xsamples, stratum / xsamples);
                let (dx, dy) = if jitter {
                    (self.independent(d), self.independent(d + 1))
                } else {
                    (0.5, 0.5)
                };
                Vec2::new(
                    (sx as f32 + dx) / xsamples as f32,
                    (sy as f32 + dy) / ysamples as f32,
                )
            }
            SamplerKind::Sobol => {
                let i = owen_scramble(self.index as u32, h as u32);
                let h2 = mix_bits(h);
                Vec2::new(
                    u32_to_unit_f32(owen_scramble(sobol_0(i), (h >> 32) as u32)),
                    u32_to_unit_f32(owen_scramble(sobol_1(i), h2 as u32)),
                )
            }
        }
    }

    /// The 2D sample that positions the sample on the film (the first two dimensions).
    #[inline]
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        self.get_2d()
    }

    /// 64 random bits for dimension `d`: the `d`-th output of a SplitMix64 stream seeded by the
    /// sample's hash (one mixing round per dimension).
    #[inline]
    fn independent_bits(&self, d: u32) -> u64 {
        mix_bits(
            self.sample_hash
                .wrapping_add((d as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15)),
        )
    }

    #[inline]
    fn independent(&self, d: u32) -> f32 {
        u32_to_unit_f32(self.independent_bits(d) as u32)
    }

    /// Dimensions `d`, `d + 1` of an independent sample: the two halves of one 64-bit hash.
    #[inline(always)]
    fn independent_2d(&self, d: u32) -> Vec2 {
        let h = self.independent_bits(d);
        Vec2::new(u32_to_unit_f32(h as u32), u32_to_unit_f32((h >> 32) as u32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_depend_only_on_pixel_index_and_dimension() {
        for kind in [
            SamplerKind::Independent,
            SamplerKind::Sobol,
            SamplerKind::Stratified {
                xsamples: 4,
                ysamples: 4,
                jitter: true,
            },
        ] {
            let mut a = Sampler::new(kind, 16, 7);
            let mut b = Sampler::new(kind, 16, 7);
            b.start_pixel_sample(9, 9, 3);
            let _ = (b.get_2d(), b.get_1d());
            a.start_pixel_sample(5, 6, 11);
            b.start_pixel_sample(5, 6, 11);
            for _ in 0..5 {
                assert_eq!(a.get_2d(), b.get_2d());
                assert_eq!(a.get_1d(), b.get_1d());
            }
        }
    }

    #[test]
    fn sobol_2d_prefix_is_stratified() {
        // A (0, 2)-sequence: the first 16 points put exactly one point in each 4 × 4 cell, and
        // one in each 1 × 16 and 16 × 1 elementary interval.
        let mut s = Sampler::new(SamplerKind::Sobol, 16, 3);
        let mut grid = [0u32; 16];
        let mut cols = [0u32; 16];
        let mut rows = [0u32; 16];
        for i in 0..16 {
            s.start_pixel_sample(2, 3, i);
            s.get_1d();
            let p = s.get_2d();
            grid[(p.x * 4.0) as usize + 4 * (p.y * 4.0) as usize] += 1;
            cols[(p.x * 16.0) as usize] += 1;
            rows[(p.y * 16.0) as usize] += 1;
        }
        assert!(grid.iter().all(|&c| c == 1), "{grid:?}");
        assert!(cols.iter().all(|&c| c == 1) && rows.iter().all(|&c| c == 1));
    }

    #[test]
    fn stratified_covers_every_stratum() {
        let mut s = Sampler::new(
            SamplerKind::Stratified {
                xsamples: 3,
                ysamples: 2,
                jitter: true,
            },
            6,
            1,
        );
        let mut cells = [0; 6];
        for i in 0..6 {
            s.start_pixel_sample(0, 0, i);
            let p = s.get_2d();
            cells[(p.x * 3.0) as usize + 3 * (p.y * 2.0) as usize] += 1;
        }
        assert_eq!(cells, [1; 6]);
    }
}
