//! Sobol' points in base 2 and the ways pbrt-v4 randomises them.
//!
//! Dimension j of point a is C_j·a over GF(2): the generator matrix's columns XORed for each
//! set bit of a, read as a binary fraction. Dimension 0 is the van der Corput sequence (C = the
//! bit reversal), dimension 1 has Pascal's triangle mod 2 as its matrix; the two together form
//! a (0, 2)-sequence. Randomisations act on the 32-bit result: `permutedigits` XORs a random
//! word (a random permutation of each binary digit), `owen` flips each bit by a hash of the
//! bits above it (nested uniform scrambling), `fastowen` does the same with Laine and Karras's
//! multiplicative hash (Burley 2020).

use super::Randomization;
use super::hash::mix_bits;

/// Sobol dimension 0: the van der Corput sequence (bit reversal of the index).
#[inline]
pub fn sobol_0(a: u32) -> u32 {
    a.reverse_bits()
}

/// Sobol dimension 1: generator matrix = Pascal's triangle mod 2, produced by the recurrence
/// vᵢ₊₁ = vᵢ ⊕ (vᵢ >> 1) on the direction numbers.
#[inline]
pub fn sobol_1(mut a: u32) -> u32 {
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

/// Nested uniform (Owen) scrambling of a 32-bit fixed-point value, in the hash-based form of
/// Burley 2020 ("Practical Hash-based Owen Scrambling", §3): reverse the bits, apply the
/// Laine–Karras permutation, reverse back. Each bit is flipped by a function of the bits more
/// significant than it, as Owen scrambling asks, with a cheap hash.
#[inline]
pub fn fast_owen_scramble(v: u32, seed: u32) -> u32 {
    fast_owen_scramble_reversed(v.reverse_bits(), seed)
}

/// Owen scrambling bit by bit: bit 31 − b is flipped when a hash of (seed, the b bits above
/// it) says so; 32 hashes, each a full 64-bit mix.
#[inline]
pub fn owen_scramble(mut v: u32, seed: u32) -> u32 {
    for b in 0..32u32 {
        let mask = if b == 0 { 0 } else { !0u32 << (32 - b) };
        let h = mix_bits(mix_bits(((b as u64) << 32) | seed as u64) ^ (v & mask) as u64);
        if h & 1 != 0 {
            v ^= 1 << (31 - b);
        }
    }
    v
}

/// [`fast_owen_scramble`] of the value whose bit reversal is `v_reversed`: the scramble works
/// on reversed bits, so a caller holding them ([`sobol_sample_reversed`]) skips one reversal.
#[inline]
pub fn fast_owen_scramble_reversed(v_reversed: u32, seed: u32) -> u32 {
    let mut x = v_reversed.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x.reverse_bits()
}

/// `v` randomised by `randomization` with the 32-bit `seed`.
#[inline]
pub fn randomize(v: u32, randomization: Randomization, seed: u32) -> u32 {
    match randomization {
        Randomization::None => v,
        Randomization::PermuteDigits => v ^ seed,
        Randomization::FastOwen => fast_owen_scramble(v, seed),
        Randomization::Owen => owen_scramble(v, seed),
    }
}

/// Dimensions of the `sobol` sampler's generator matrices: dimension 0 (van der Corput) and
/// the 1023 of Joe and Kuo's `new-joe-kuo-6.21201` direction numbers (search criterion D(6))
/// listed in `joe_kuo.txt` (one line `d s a m₁ … m_s` per dimension), as pbrt-v4's 1024; past
/// the table, dimensions start again from 2, as in pbrt-v4.
pub const N_SOBOL_DIMENSIONS: usize = 1024;

/// The generator matrices, one 32-column matrix per dimension (column k = direction number
/// v_{k+1} as a 32-bit binary fraction), built from the direction numbers once.
///
/// From Joe–Kuo's (s, a, m₁…m_s) for a primitive polynomial of degree s with inner
/// coefficients a: v_k = m_k·2^(32−k) for k ≤ s, then
/// v_k = v_{k−s} ⊕ (v_{k−s} ≫ s) ⊕ ⨁_{j=1}^{s−1} a_j·v_{k−j} (a_j the j-th bit of a from the top).
pub fn sobol_matrices() -> &'static [[u32; 32]] {
    static M: std::sync::OnceLock<Vec<[u32; 32]>> = std::sync::OnceLock::new();
    M.get_or_init(|| {
        let mut out = Vec::with_capacity(N_SOBOL_DIMENSIONS);
        out.push(std::array::from_fn(|k| 1u32 << (31 - k)));
        for line in include_str!("joe_kuo.txt").lines() {
            let n: Vec<u32> = line
                .split_whitespace()
                .map(|t| t.parse().unwrap_or(0))
                .collect();
            let (s, a, m) = (n[1] as usize, n[2], &n[3..]);
            let mut v = [0u32; 32];
            for k in 0..32 {
                v[k] = if k < s {
                    m[k] << (31 - k)
                } else {
                    let mut x = v[k - s] ^ (v[k - s] >> s);
                    for j in 1..s {
                        if (a >> (s - 1 - j)) & 1 != 0 {
                            x ^= v[k - j];
                        }
                    }
                    x
                };
            }
            out.push(v);
        }
        out
    })
}

/// [`sobol_matrices`] with every column bit-reversed: XORing them gives the bit reversal of
/// a Sobol value directly (reversal commutes with XOR), which is what Owen scrambling wants.
fn sobol_matrices_reversed() -> &'static [[u32; 32]] {
    static M: std::sync::OnceLock<Vec<[u32; 32]>> = std::sync::OnceLock::new();
    M.get_or_init(|| {
        sobol_matrices()
            .iter()
            .map(|c| c.map(u32::reverse_bits))
            .collect()
    })
}

/// The bit reversal of [`sobol_sample`]`(a, dim)`, from the reversed columns.
#[inline]
pub fn sobol_sample_reversed(a: u64, dim: usize) -> u32 {
    let c = &sobol_matrices_reversed()[dim];
    let mut a = a as u32;
    let mut v = 0;
    while a != 0 {
        v ^= c[(a.trailing_zeros() & 31) as usize];
        a &= a - 1;
    }
    v
}

/// Dimension `dim` of Sobol point `a` (its low 32 bits) as a 32-bit binary fraction: the
/// columns of C_dim for the set bits of a, XORed. The loop visits only the set bits (lowest
/// first, `a & (a − 1)` clearing it), so it runs popcount(a) times and its one data-dependent
/// branch is the exit: testing every bit instead mispredicted about half of them.
#[inline]
pub fn sobol_sample(a: u64, dim: usize) -> u32 {
    let c = &sobol_matrices()[dim];
    let mut a = a as u32;
    let mut v = 0;
    while a != 0 {
        v ^= c[(a.trailing_zeros() & 31) as usize];
        a &= a - 1;
    }
    v
}

/// The largest `m` [`interval_to_index`] accepts (an image of 2¹⁶ pixels a side).
pub const MAX_INTERVAL_LOG2: u32 = 16;

/// For each `m`, the inverse of the m × m system [`interval_to_index`] solves, as the
/// solutions for the unit right-hand sides: entry `b` is the x with Σ x_j c_j = 2^b, where
/// c_j is the top m bits of dimension 1's column m + j. The system depends on m alone, so
/// each is solved once (Gaussian elimination over GF(2)) and a pixel sample's index then
/// costs a few XORs: x(rhs) = ⨁_{b set in rhs} x(2^b), by linearity.
fn dim1_inverse(m: u32) -> &'static [u32; MAX_INTERVAL_LOG2 as usize] {
    static INV: [std::sync::OnceLock<[u32; MAX_INTERVAL_LOG2 as usize]>;
        MAX_INTERVAL_LOG2 as usize + 1] = [const { std::sync::OnceLock::new() }; 17];
    INV[m as usize].get_or_init(|| {
        let top = |v: u32| v >> (32 - m);
        std::array::from_fn(|b| {
            if b as u32 >= m {
                return 0;
            }
            // (column image, which unknowns make it), eliminated towards the target 2^b.
            let mut rows: Vec<(u32, u32)> = (0..m)
                .map(|j| (top(sobol_1(1u32 << (m + j))), 1u32 << j))
                .collect();
            let mut x = 0u32;
            let mut target = 1u32 << b;
            for bit in (0..m).rev() {
                let Some(p) = rows.iter().position(|r| r.0 >> bit & 1 != 0) else {
                    continue;
                };
                let pivot = rows.swap_remove(p);
                for r in rows.iter_mut() {
                    if r.0 >> bit & 1 != 0 {
                        r.0 ^= pivot.0;
                        r.1 ^= pivot.1;
                    }
                }
                if target >> bit & 1 != 0 {
                    target ^= pivot.0;
                    x ^= pivot.1;
                }
            }
            x
        })
    })
}

/// The index of the `frame`-th Sobol point whose first two dimensions, scaled by 2^m, fall in
/// pixel (`px`, `py`) (pbrt-v4's `SobolIntervalToIndex`, solved here directly): the index is
/// `frame` followed by 2m low bits. The top m bits of dimension 0 are the low m bits of the
/// index reversed, which `px` fixes; the top m bits of dimension 1 are then linear in the
/// remaining m bits, a system over GF(2) that the (0, 2) property makes invertible (its
/// inverse is computed once per m, [`dim1_inverse`]). `m` is at most [`MAX_INTERVAL_LOG2`].
pub fn interval_to_index(m: u32, frame: u64, px: u32, py: u32) -> u64 {
    if m == 0 {
        return frame;
    }
    let m = m.min(MAX_INTERVAL_LOG2);
    // Bits 0..m: px mirrored.
    let low = (px.reverse_bits() >> (32 - m)) as u64;
    let known = (frame << (2 * m)) | low;
    let mut rhs = (py ^ (sobol_sample(known, 1) >> (32 - m))) & ((1u32 << m) - 1);
    let inv = dim1_inverse(m);
    let mut x = 0u32;
    while rhs != 0 {
        x ^= inv[(rhs.trailing_zeros() & 15) as usize];
        rhs &= rhs - 1;
    }
    known | ((x as u64) << m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_sobol_points_by_hand() {
        // Dimension 0: 1 → 0.1₂, 2 → 0.01₂, 3 → 0.11₂; dimension 1: 1 → 0.1₂, 2 → 0.11₂,
        // 3 → 0.01₂ (columns 10…, 110…).
        let f = |v: u32| v as f64 / 2f64.powi(32);
        assert_eq!([1, 2, 3].map(|a| f(sobol_0(a))), [0.5, 0.25, 0.75]);
        assert_eq!([1, 2, 3].map(|a| f(sobol_1(a))), [0.5, 0.75, 0.25]);
    }

    #[test]
    fn joe_kuo_matrices_match_the_closed_forms() {
        // Dimension 1 from the table (s = 1, a = 0, m = 1) is Pascal's matrix mod 2.
        for a in [1u64, 2, 3, 77, 12345, 0xffff_ffff] {
            assert_eq!(sobol_sample(a, 0), sobol_0(a as u32));
            assert_eq!(sobol_sample(a, 1), sobol_1(a as u32));
        }
        // Dimension 2 (s = 2, a = 1, m = 1 3): v₁ = 0.1, v₂ = 0.11, then
        // v₃ = v₁ ⊕ v₁≫2 ⊕ v₂ = 0.100 ⊕ 0.001 ⊕ 0.110 = 0.011.
        let c = &sobol_matrices()[2];
        assert_eq!([c[0] >> 29, c[1] >> 29, c[2] >> 29], [0b100, 0b110, 0b011]);
        assert_eq!(sobol_matrices().len(), N_SOBOL_DIMENSIONS);
    }

    #[test]
    fn matrices_equal_pbrt_v4s() {
        // Columns 0..4 and 31 of pbrt-v4's SobolMatrices32 for these dimensions (copied from
        // its src/pbrt/util/sobolmatrices.cpp by hand).
        let pbrt: [(usize, [u32; 5]); 7] = [
            (
                0,
                [
                    0x8000_0000,
                    0x4000_0000,
                    0x2000_0000,
                    0x1000_0000,
                    0x0000_0001,
                ],
            ),
            (
                1,
                [
                    0x8000_0000,
                    0xc000_0000,
                    0xa000_0000,
                    0xf000_0000,
                    0xffff_ffff,
                ],
            ),
            (
                2,
                [
                    0x8000_0000,
                    0xc000_0000,
                    0x6000_0000,
                    0x9000_0000,
                    0xc500_5555,
                ],
            ),
            (
                127,
                [
                    0x8000_0000,
                    0xc000_0000,
                    0x6000_0000,
                    0x7000_0000,
                    0xa0e5_41bf,
                ],
            ),
            (
                128,
                [
                    0x8000_0000,
                    0xc000_0000,
                    0xe000_0000,
                    0x7000_0000,
                    0xcd72_9c6f,
                ],
            ),
            (
                500,
                [
                    0x8000_0000,
                    0xc000_0000,
                    0xa000_0000,
                    0x1000_0000,
                    0x2c95_1429,
                ],
            ),
            (
                1023,
                [
                    0x8000_0000,
                    0x4000_0000,
                    0xa000_0000,
                    0xb000_0000,
                    0x651d_e84d,
                ],
            ),
        ];
        for (d, want) in pbrt {
            let c = &sobol_matrices()[d];
            assert_eq!([c[0], c[1], c[2], c[3], c[31]], want, "dimension {d}");
        }
    }

    #[test]
    fn every_pair_of_dimensions_is_stratified() {
        // The first 2^k points of any two of the first dimensions: one per elementary
        // interval of area 1/16 for the pairs the (t, s) property guarantees — checked on the
        // 4 × 4 grid for (0, 1) and 1 × 16 slabs for each dimension alone.
        for d in 0..N_SOBOL_DIMENSIONS {
            let mut seen = [0; 16];
            for a in 0..16u64 {
                seen[(sobol_sample(a, d) >> 28) as usize] += 1;
            }
            assert!(seen.iter().all(|&c| c == 1), "dimension {d}");
        }
    }

    #[test]
    fn interval_to_index_finds_the_pixels_points() {
        // A 16 × 16 image (m = 4): the k-th point of pixel (x, y) lands in it.
        for (x, y) in [(0u32, 0u32), (3, 9), (15, 15), (7, 2)] {
            for frame in 0..5u64 {
                let a = interval_to_index(4, frame, x, y);
                assert_eq!(a >> 8, frame);
                assert_eq!((sobol_sample(a, 0) >> 28, sobol_sample(a, 1) >> 28), (x, y));
            }
        }
        // Other scales, up to the largest: the point's top m bits are the pixel's.
        for m in [1u32, 8, 11, MAX_INTERVAL_LOG2] {
            let n = 1u32 << m;
            for (x, y) in [(0, 0), (n - 1, 0), (n / 3, n - 1), (n / 2, n / 5)] {
                for frame in [0u64, 1, 63] {
                    let a = interval_to_index(m, frame, x, y);
                    assert_eq!(a >> (2 * m), frame);
                    let top = |v: u32| v >> (32 - m);
                    let p = (top(sobol_sample(a, 0)), top(sobol_sample(a, 1)));
                    assert_eq!(p, (x, y), "m = {m}");
                }
            }
        }
    }

    #[test]
    fn scramblings_keep_elementary_intervals() {
        // Owen-type scramblings (and XOR) map each dyadic interval of length 2^-k onto another
        // one: the first 2^k points of dimension 0 still fill every interval.
        for r in [
            Randomization::None,
            Randomization::PermuteDigits,
            Randomization::FastOwen,
            Randomization::Owen,
        ] {
            for seed in [1u32, 0xdead_beef] {
                let mut seen = [0; 64];
                for a in 0..64 {
                    seen[(randomize(sobol_1(a), r, seed) >> 26) as usize] += 1;
                }
                assert!(seen.iter().all(|&c| c == 1), "{r:?}");
            }
        }
        // The scramble from reversed Sobol values is the scramble of the values.
        for (a, d, seed) in [
            (5u64, 2usize, 9u32),
            (0x2f_1234, 17, 0xdead_beef),
            (0, 3, 1),
        ] {
            assert_eq!(
                sobol_sample_reversed(a, d),
                sobol_sample(a, d).reverse_bits()
            );
            assert_eq!(
                fast_owen_scramble_reversed(sobol_sample_reversed(a, d), seed),
                fast_owen_scramble(sobol_sample(a, d), seed)
            );
        }
        // And they do change the points.
        assert_ne!(owen_scramble(0, 5), 0);
        assert_eq!(
            randomize(0b1010, Randomization::PermuteDigits, 0b0110),
            0b1100
        );
    }
}
