//! Per-pixel samplers whose values depend only on (seed, pixel, sample index, dimension).
//!
//! No sampler keeps state across pixel samples: a pixel's `i`-th sample is the same whichever
//! thread, tile order or machine computes it. That is what makes split renders merge exactly
//! and interrupted renders resume to the same pixels.

use super::halton::{self, DigitPermutations, HaltonTiling};
use super::hash::{hash_u64, mix_bits, permutation_element, u32_to_unit_f32};
use super::randomization::Randomization;
use super::sobol::{
    N_SOBOL_DIMENSIONS, fast_owen_scramble, interval_to_index, randomize, sobol_0, sobol_1,
    sobol_sample,
};
use crate::math::Vec2;
use std::sync::Arc;

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
    /// lancer's stand-in for pbrt-v4's `zsobol` (its default): the first two dimensions of
    /// the Sobol sequence for every pair of dimensions, the sample index shuffled by Owen
    /// scrambling and the values randomised independently for each pixel and pair of
    /// dimensions ("padded" Sobol with hash-based shuffling, Burley 2020). Every 2D
    /// projection is a (0, 2)-sequence: well stratified for any power-of-two prefix.
    ZSobol {
        /// How the values are randomised (`fastowen` by default).
        randomization: Randomization,
    },
    /// pbrt-v4's `paddedsobol`: for each pixel and dimension a random permutation of the
    /// pixel's sample indices picks a point of the first Sobol dimensions, randomised.
    PaddedSobol {
        /// How the values are randomised (`fastowen` by default).
        randomization: Randomization,
    },
    /// pbrt-v4's `sobol`: one Sobol sequence over the whole image, each pixel taking the
    /// points whose first two dimensions, scaled to the image, fall in it
    /// ([`super::sobol::interval_to_index`]).
    Sobol {
        /// How dimensions 2 and up are randomised (`fastowen` by default).
        randomization: Randomization,
        /// The film's full resolution.
        resolution: [u32; 2],
    },
    /// pbrt-v4's `halton`: the Halton sequence tiled over the image, so that each pixel's
    /// samples are a residue class of the index ([`halton::HaltonTiling`]).
    Halton {
        /// `permutedigits` (pbrt-v4's default), `owen` or `none`.
        randomization: Randomization,
        /// The film's full resolution, which sets the tiling.
        resolution: [u32; 2],
    },
}

impl SamplerKind {
    /// The pbrt-v4 name of this point set (`Sampler "…"`).
    pub fn pbrt_name(&self) -> &'static str {
        match self {
            SamplerKind::Independent => "independent",
            SamplerKind::Stratified { .. } => "stratified",
            SamplerKind::ZSobol { .. } => "zsobol",
            SamplerKind::PaddedSobol { .. } => "paddedsobol",
            SamplerKind::Halton { .. } => "halton",
            SamplerKind::Sobol { .. } => "sobol",
        }
    }

    /// The same point set for a film of `width × height` pixels (the samplers that tile the
    /// image with their first dimensions need the film's full resolution).
    pub fn for_film(self, width: u32, height: u32) -> SamplerKind {
        match self {
            SamplerKind::Halton { randomization, .. } => SamplerKind::Halton {
                randomization,
                resolution: [width, height],
            },
            SamplerKind::Sobol { randomization, .. } => SamplerKind::Sobol {
                randomization,
                resolution: [width, height],
            },
            k => k,
        }
    }
}

/// log₂ of the Sobol sampler's scale: the smallest power of two covering the resolution.
fn sobol_log2_scale(resolution: [u32; 2]) -> u32 {
    let r = resolution[0].max(resolution[1]).max(1);
    r.next_power_of_two().trailing_zeros().min(16)
}

/// What a Halton sampler keeps: its tiling and (for `permutedigits`) the digit permutations.
#[derive(Clone, Debug)]
struct HaltonState {
    tiling: HaltonTiling,
    perms: Option<Arc<DigitPermutations>>,
    /// The current sample's Halton index.
    index: u64,
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
    halton: Option<HaltonState>,
    /// The `sobol` sampler's index of the current sample in the whole image's sequence.
    sobol_index: u64,
}

impl Sampler {
    /// A sampler of `kind` for `spp` samples per pixel, seeded by `seed`.
    pub fn new(kind: SamplerKind, spp: u32, seed: u64) -> Sampler {
        let halton = match kind {
            SamplerKind::Halton {
                randomization,
                resolution,
            } => Some(HaltonState {
                tiling: HaltonTiling::new(resolution),
                perms: (randomization == Randomization::PermuteDigits)
                    .then(|| DigitPermutations::for_seed(seed)),
                index: 0,
            }),
            _ => None,
        };
        Sampler {
            kind,
            seed,
            spp: spp.max(1),
            pixel: (0, 0),
            pixel_hash: hash_u64(&[0, 0, seed]),
            sample_hash: 0,
            index: 0,
            dim: 0,
            halton,
            sobol_index: 0,
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
        if let Some(h) = &mut self.halton {
            h.index = h.tiling.index(x, y, index);
        }
        if let SamplerKind::Sobol { resolution, .. } = self.kind {
            let m = sobol_log2_scale(resolution);
            self.sobol_index = interval_to_index(m, index, x as u32, y as u32);
        }
    }

    /// The pixel's sample index permuted by a hash `h` of (pixel, dimension): pbrt-v4's
    /// padded samplers take the points of one pixel in a different order in each dimension.
    #[inline]
    fn permuted_index(&self, h: u64) -> u32 {
        let spp = self.spp as u64;
        let (round, i) = (self.index / spp, self.index % spp);
        (round * spp) as u32 + permutation_element(i as u32, self.spp, h as u32)
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
            SamplerKind::ZSobol { randomization } => {
                let i = fast_owen_scramble(self.index as u32, h as u32);
                u32_to_unit_f32(randomize(sobol_0(i), randomization, (h >> 32) as u32))
            }
            SamplerKind::PaddedSobol { randomization } => {
                let i = self.permuted_index(h);
                u32_to_unit_f32(randomize(sobol_0(i), randomization, (h >> 32) as u32))
            }
            SamplerKind::Halton { randomization, .. } => self.halton_dimension(d, randomization),
            SamplerKind::Sobol { randomization, .. } => self.sobol_dimension(d, randomization),
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
            SamplerKind::ZSobol { randomization } => {
                let i = fast_owen_scramble(self.index as u32, h as u32);
                let h2 = mix_bits(h);
                Vec2::new(
                    u32_to_unit_f32(randomize(sobol_0(i), randomization, (h >> 32) as u32)),
                    u32_to_unit_f32(randomize(sobol_1(i), randomization, h2 as u32)),
                )
            }
            SamplerKind::PaddedSobol { randomization } => {
                let i = self.permuted_index(h);
                Vec2::new(
                    u32_to_unit_f32(randomize(sobol_0(i), randomization, h as u32)),
                    u32_to_unit_f32(randomize(sobol_1(i), randomization, (h >> 32) as u32)),
                )
            }
            SamplerKind::Halton { randomization, .. } => Vec2::new(
                self.halton_dimension(d, randomization),
                self.halton_dimension(d + 1, randomization),
            ),
            SamplerKind::Sobol { randomization, .. } => Vec2::new(
                self.sobol_dimension(d, randomization),
                self.sobol_dimension(d + 1, randomization),
            ),
        }
    }

    /// The 2D sample that positions the sample on the film (the first two dimensions).
    #[inline]
    pub fn get_pixel_2d(&mut self) -> Vec2 {
        match &self.halton {
            // The Halton tiling's own first two dimensions, past the digits that chose the
            // pixel; the other dimensions start at 2.
            Some(h) => {
                self.dim = 2;
                let (x, y) = h.tiling.pixel_2d(h.index);
                Vec2::new(x, y)
            }
            None => match self.kind {
                // The first two dimensions below the bits that chose the pixel, unscrambled.
                SamplerKind::Sobol { resolution, .. } => {
                    self.dim = 2;
                    let m = sobol_log2_scale(resolution);
                    let a = self.sobol_index;
                    Vec2::new(
                        u32_to_unit_f32(sobol_0(a as u32) << m),
                        u32_to_unit_f32(sobol_1(a as u32) << m),
                    )
                }
                _ => self.get_2d(),
            },
        }
    }

    /// Dimension `d` of the current `sobol` sample, randomised by a hash of (dimension,
    /// seed); past the table, dimensions start again from 2 (as pbrt-v4 does past its 1024).
    fn sobol_dimension(&self, d: u32, randomization: Randomization) -> f32 {
        let n = N_SOBOL_DIMENSIONS as u32;
        let d = if d < n {
            d.max(2)
        } else {
            2 + (d - 2) % (n - 2)
        };
        let h = mix_bits(hash_u64(&[d as u64, self.seed]));
        u32_to_unit_f32(randomize(
            sobol_sample(self.sobol_index, d as usize),
            randomization,
            h as u32,
        ))
    }

    /// Dimension `d` of the current Halton sample (dimensions 0 and 1 belong to the pixel).
    fn halton_dimension(&self, d: u32, randomization: Randomization) -> f32 {
        let Some(h) = &self.halton else { return 0.5 };
        halton::sample_dimension(
            d.max(2),
            h.index,
            randomization,
            h.perms.as_deref(),
            self.seed,
        )
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

    /// Every point set, with several randomisations.
    fn all_kinds() -> Vec<SamplerKind> {
        let mut v = vec![
            SamplerKind::Independent,
            SamplerKind::Stratified {
                xsamples: 4,
                ysamples: 4,
                jitter: true,
            },
        ];
        for r in [
            Randomization::None,
            Randomization::PermuteDigits,
            Randomization::FastOwen,
            Randomization::Owen,
        ] {
            v.push(SamplerKind::ZSobol { randomization: r });
            v.push(SamplerKind::PaddedSobol { randomization: r });
            v.push(SamplerKind::Sobol {
                randomization: r,
                resolution: [16, 16],
            });
            if r != Randomization::FastOwen {
                v.push(SamplerKind::Halton {
                    randomization: r,
                    resolution: [16, 16],
                });
            }
        }
        v
    }

    #[test]
    fn every_sampler_is_a_pure_function_of_pixel_index_and_dimension() {
        for kind in all_kinds() {
            let mut a = Sampler::new(kind, 16, 7);
            let mut b = Sampler::new(kind, 16, 7);
            b.start_pixel_sample(9, 9, 3);
            let _ = (b.get_pixel_2d(), b.get_1d(), b.get_2d());
            a.start_pixel_sample(5, 6, 11);
            b.start_pixel_sample(5, 6, 11);
            assert_eq!(a.get_pixel_2d(), b.get_pixel_2d());
            for _ in 0..40 {
                assert_eq!(a.get_2d(), b.get_2d(), "{kind:?}");
                assert_eq!(a.get_1d(), b.get_1d(), "{kind:?}");
            }
        }
    }

    #[test]
    fn first_dimensions_are_uniform_by_chi_square() {
        // 16 × 16 pixels × 16 samples = 4096 values of the pixel sample and of the next two
        // dimensions, in 16 bins each (expected 256 per bin). χ² with 15 degrees of freedom
        // stays below 37.7 with probability 0.999 for uniform values; stratified ones do far
        // better.
        for kind in all_kinds() {
            let mut s = Sampler::new(kind, 16, 1);
            let mut bins = [[0u32; 16]; 5];
            for y in 0..16 {
                for x in 0..16 {
                    for i in 0..16 {
                        s.start_pixel_sample(x, y, i);
                        let p = s.get_pixel_2d();
                        let u = s.get_1d();
                        let q = s.get_2d();
                        for (k, v) in [p.x, p.y, u, q.x, q.y].into_iter().enumerate() {
                            assert!((0.0..1.0).contains(&v), "{kind:?}");
                            bins[k][(v * 16.0) as usize] += 1;
                        }
                    }
                }
            }
            for (k, b) in bins.iter().enumerate() {
                let chi2: f64 = b.iter().map(|&o| (o as f64 - 256.0).powi(2) / 256.0).sum();
                assert!(chi2 < 37.7, "{kind:?} dimension {k}: chi2 {chi2} {b:?}");
            }
        }
    }

    #[test]
    fn sobol_and_halton_pixel_samples_are_stratified() {
        // The first 16 samples of a pixel put one point in each 4 × 4 cell (Sobol, a
        // (0, 2)-sequence); Halton's first 6 samples one in each of 2 × 3 cells (bases 2, 3).
        let mut s = Sampler::new(
            SamplerKind::Sobol {
                randomization: Randomization::FastOwen,
                resolution: [32, 20],
            },
            16,
            2,
        );
        let mut grid = [0u32; 16];
        for i in 0..16 {
            s.start_pixel_sample(7, 13, i);
            let p = s.get_pixel_2d();
            grid[(p.x * 4.0) as usize + 4 * (p.y * 4.0) as usize] += 1;
        }
        assert_eq!(grid, [1; 16]);
        let mut s = Sampler::new(
            SamplerKind::Halton {
                randomization: Randomization::PermuteDigits,
                resolution: [32, 20],
            },
            6,
            2,
        );
        let mut cells = [0u32; 6];
        for i in 0..6 {
            s.start_pixel_sample(3, 4, i);
            let p = s.get_pixel_2d();
            cells[(p.x * 2.0) as usize + 2 * (p.y * 3.0) as usize] += 1;
        }
        assert_eq!(cells, [1; 6]);
    }

    #[test]
    fn samples_depend_only_on_pixel_index_and_dimension() {
        for kind in [
            SamplerKind::Independent,
            SamplerKind::ZSobol {
                randomization: Randomization::FastOwen,
            },
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
        let mut s = Sampler::new(
            SamplerKind::ZSobol {
                randomization: Randomization::FastOwen,
            },
            16,
            3,
        );
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
