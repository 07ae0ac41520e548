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
    let mut x = v.reverse_bits();
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x.reverse_bits()
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
        // And they do change the points.
        assert_ne!(owen_scramble(0, 5), 0);
        assert_eq!(
            randomize(0b1010, Randomization::PermuteDigits, 0b0110),
            0b1100
        );
    }
}
