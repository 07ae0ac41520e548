//! The Halton sequence as pbrt-v4's `halton` sampler uses it: dimension `d` is the radical
//! inverse of the sample's index in the `d`-th prime base, and the first two dimensions tile
//! the image so that each pixel's samples are a fixed residue class of the index.
//!
//! Radical inverse in base b of a = Σ dᵢ bⁱ: Φ_b(a) = Σ dᵢ b^−(i+1) (the digits mirrored about
//! the radix point). Randomised by a random permutation of the digit values at each digit
//! position (`permutedigits`, pbrt-v4's default) or by Owen scrambling (`owen`: the permutation
//! of a digit also depends on the digits before it).

use super::ONE_MINUS_EPSILON;
use super::Randomization;
use super::hash::{hash_u64, mix_bits, permutation_element};
use std::sync::{Arc, Mutex, OnceLock};

/// How many prime bases (dimensions) the sampler has, as pbrt-v4's `PrimeTableSize`: past it,
/// dimensions start again from 2.
pub const PRIME_TABLE_SIZE: usize = 1000;

/// The first [`PRIME_TABLE_SIZE`] primes (2, 3, 5, …, 7919), by trial division at compile time.
pub const PRIMES: [u32; PRIME_TABLE_SIZE] = primes();

const fn primes() -> [u32; PRIME_TABLE_SIZE] {
    let mut out = [0u32; PRIME_TABLE_SIZE];
    let mut n = 0;
    let mut c = 2u32;
    while n < PRIME_TABLE_SIZE {
        let mut prime = true;
        let mut k = 0;
        while k < n && out[k] * out[k] <= c {
            if c.is_multiple_of(out[k]) {
                prime = false;
                break;
            }
            k += 1;
        }
        if prime {
            out[n] = c;
            n += 1;
        }
        c += 1;
    }
    out
}

/// Radical inverse Φ_b(a) of `a` in base `PRIMES[base_index]`.
pub fn radical_inverse(base_index: usize, mut a: u64) -> f32 {
    let base = PRIMES[base_index] as u64;
    // Stop before the mirrored digits could overflow 64 bits.
    let limit = u64::MAX / base - base;
    let inv_base = 1.0 / base as f32;
    let mut inv_base_m = 1.0f32;
    let mut reversed = 0u64;
    while a != 0 && reversed < limit {
        let next = a / base;
        let digit = a - next * base;
        reversed = reversed * base + digit;
        inv_base_m *= inv_base;
        a = next;
    }
    (reversed as f32 * inv_base_m).min(ONE_MINUS_EPSILON)
}

/// The index whose radical inverse in `base` has the `n_digits` digits of `inverse` (read as
/// an integer, most significant digit first): the mirror of [`radical_inverse`] on integers.
pub fn inverse_radical_inverse(mut inverse: u64, base: u64, n_digits: u32) -> u64 {
    let mut index = 0;
    for _ in 0..n_digits {
        let digit = inverse % base;
        inverse /= base;
        index = index * base + digit;
    }
    index
}

/// How many base-b digits a float in [0, 1) can tell apart: the number of steps until
/// 1 − (b − 1)·b^−k rounds to 1 (the loop bound of pbrt-v4's digit permutations).
fn digit_count(base: u32) -> usize {
    let inv_base = 1.0 / base as f32;
    let mut inv_base_m = 1.0f32;
    let mut n = 0;
    while 1.0 - (base - 1) as f32 * inv_base_m < 1.0 {
        n += 1;
        inv_base_m *= inv_base;
    }
    n
}

/// The random permutation of digit values at digit position `digit` of base `base`, applied
/// to `value`: a pure function of (base, position, seed).
#[inline]
fn permute_digit(base: u32, digit: usize, value: u32, seed: u64) -> u32 {
    let dseed = hash_u64(&[base as u64, digit as u64, seed]);
    permutation_element(value, base, dseed as u32)
}

/// Bases whose digit permutations are tabulated (the others are computed digit by digit):
/// the first 128 bases cover paths of some 20 bounces and take about 300 KB.
const TABULATED_BASES: usize = 128;

/// The digit permutations of the first [`TABULATED_BASES`] bases for one seed.
#[derive(Debug)]
pub struct DigitPermutations {
    /// Start of each base's table in `perms`; a base's table holds `digits × base` entries.
    offsets: Vec<u32>,
    perms: Vec<u16>,
}

impl DigitPermutations {
    fn new(seed: u64) -> DigitPermutations {
        let mut offsets = Vec::with_capacity(TABULATED_BASES);
        let mut perms = Vec::new();
        for &base in &PRIMES[..TABULATED_BASES] {
            offsets.push(perms.len() as u32);
            for digit in 0..digit_count(base) {
                for v in 0..base {
                    perms.push(permute_digit(base, digit, v, seed) as u16);
                }
            }
        }
        DigitPermutations { offsets, perms }
    }

    /// The permutations for `seed`, built once per seed and shared by every sampler.
    pub fn for_seed(seed: u64) -> Arc<DigitPermutations> {
        /// The permutations built so far, by seed.
        type Cache = Mutex<Vec<(u64, Arc<DigitPermutations>)>>;
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let cache = CACHE.get_or_init(|| Mutex::new(Vec::new()));
        let mut cache = cache.lock().unwrap_or_else(|e| e.into_inner());
        if let Some((_, p)) = cache.iter().find(|(s, _)| *s == seed) {
            return p.clone();
        }
        let p = Arc::new(DigitPermutations::new(seed));
        // A handful of seeds at most in one process (a render and its tests).
        if cache.len() >= 8 {
            cache.remove(0);
        }
        cache.push((seed, p.clone()));
        p
    }

    #[inline]
    fn permute(&self, base_index: usize, base: u32, digit: usize, value: u32, seed: u64) -> u32 {
        if base_index < TABULATED_BASES {
            let o = self.offsets[base_index] as usize + digit * base as usize + value as usize;
            self.perms[o] as u32
        } else {
            permute_digit(base, digit, value, seed)
        }
    }
}

/// Radical inverse with each digit position's values permuted (pbrt-v4's
/// `ScrambledRadicalInverse`): the digits past those of `a` are zeros, permuted too, so the
/// points fill their strata rather than sit at the strata's corners.
pub fn scrambled_radical_inverse(
    base_index: usize,
    mut a: u64,
    perms: &DigitPermutations,
    seed: u64,
) -> f32 {
    let base = PRIMES[base_index];
    let b = base as u64;
    let limit = u64::MAX / b - b;
    let inv_base = 1.0 / base as f32;
    let mut inv_base_m = 1.0f32;
    let mut reversed = 0u64;
    let mut digit = 0;
    while 1.0 - (base - 1) as f32 * inv_base_m < 1.0 && reversed < limit {
        let next = a / b;
        let value = (a - next * b) as u32;
        reversed = reversed * b + perms.permute(base_index, base, digit, value, seed) as u64;
        inv_base_m *= inv_base;
        digit += 1;
        a = next;
    }
    (inv_base_m * reversed as f32).min(ONE_MINUS_EPSILON)
}

/// Owen-scrambled radical inverse: digit i's values are permuted by a permutation chosen by a
/// hash of `hash` and the digits already emitted (the more significant ones), so the
/// scrambling nests: every elementary interval is permuted independently.
pub fn owen_scrambled_radical_inverse(base_index: usize, mut a: u64, hash: u64) -> f32 {
    let base = PRIMES[base_index];
    let b = base as u64;
    let limit = u64::MAX / b - b;
    let inv_base = 1.0 / base as f32;
    let mut inv_base_m = 1.0f32;
    let mut reversed = 0u64;
    while 1.0 - inv_base_m < 1.0 && reversed < limit {
        let next = a / b;
        let value = (a - next * b) as u32;
        let digit_hash = mix_bits(hash ^ reversed);
        reversed = reversed * b + permutation_element(value, base, digit_hash as u32) as u64;
        inv_base_m *= inv_base;
        a = next;
    }
    (inv_base_m * reversed as f32).min(ONE_MINUS_EPSILON)
}

/// The Halton sampler's tiling of the image (pbrt-v4's `HaltonSampler`): the first two
/// dimensions, scaled by 2^j × 3^k (the smallest powers covering min(resolution, 128)), map the
/// sample index to a pixel of a 2^j × 3^k tile, which the Chinese remainder theorem inverts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HaltonTiling {
    /// 2^j, 3^k.
    scales: [u64; 2],
    /// j, k.
    exponents: [u32; 2],
    /// (3^k)⁻¹ mod 2^j and (2^j)⁻¹ mod 3^k.
    mult_inverse: [u64; 2],
}

/// Largest tile edge, as pbrt-v4's `MaxHaltonResolution`.
const MAX_HALTON_RESOLUTION: u32 = 128;

/// x⁻¹ mod n by the extended Euclidean algorithm (x and n coprime).
fn multiplicative_inverse(a: i64, n: i64) -> u64 {
    let (mut r0, mut r1) = (a, n);
    let (mut s0, mut s1) = (1i64, 0i64);
    while r1 != 0 {
        let q = r0 / r1;
        (r0, r1) = (r1, r0 - q * r1);
        (s0, s1) = (s1, s0 - q * s1);
    }
    s0.rem_euclid(n) as u64
}

impl HaltonTiling {
    /// The tiling for a film of `resolution` pixels.
    pub fn new(resolution: [u32; 2]) -> HaltonTiling {
        let mut scales = [1u64; 2];
        let mut exponents = [0u32; 2];
        for i in 0..2 {
            let base = [2u64, 3][i];
            while scales[i] < resolution[i].clamp(1, MAX_HALTON_RESOLUTION) as u64 {
                scales[i] *= base;
                exponents[i] += 1;
            }
        }
        let mult_inverse = [
            multiplicative_inverse(scales[1] as i64, scales[0] as i64),
            multiplicative_inverse(scales[0] as i64, scales[1] as i64),
        ];
        HaltonTiling {
            scales,
            exponents,
            mult_inverse,
        }
    }

    /// The Halton index of sample `index` of pixel (`x`, `y`): the pixel's offset in the
    /// tile, i₀ ≡ Φ₂⁻¹(x mod 2^j) (mod 2^j) and i₀ ≡ Φ₃⁻¹(y mod 3^k) (mod 3^k), solved by the
    /// Chinese remainder theorem, plus `index` whole tiles.
    pub fn index(&self, x: i32, y: i32, index: u64) -> u64 {
        let stride = self.scales[0] * self.scales[1];
        let mut offset = 0u64;
        if stride > 1 {
            let pm = [
                x.rem_euclid(MAX_HALTON_RESOLUTION as i32) as u64,
                y.rem_euclid(MAX_HALTON_RESOLUTION as i32) as u64,
            ];
            for i in 0..2 {
                let dim_offset = inverse_radical_inverse(pm[i], [2, 3][i], self.exponents[i]);
                offset = (offset
                    + dim_offset * (stride / self.scales[i]) % stride * self.mult_inverse[i])
                    % stride;
            }
        }
        offset + index.wrapping_mul(stride)
    }

    /// The position of the sample with Halton index `h` inside its pixel: the digits of the
    /// first two dimensions below those that chose the pixel.
    pub fn pixel_2d(&self, h: u64) -> (f32, f32) {
        (
            radical_inverse(0, h >> self.exponents[0]),
            radical_inverse(1, h / self.scales[1]),
        )
    }
}

/// Dimension `d` (≥ 2) of the sample with Halton index `h`, randomised as asked.
pub fn sample_dimension(
    d: u32,
    h: u64,
    randomization: Randomization,
    perms: Option<&DigitPermutations>,
    seed: u64,
) -> f32 {
    // pbrt-v4 wraps to dimension 2 past its prime table.
    let d = if (d as usize) < PRIME_TABLE_SIZE {
        d as usize
    } else {
        2 + (d as usize - 2) % (PRIME_TABLE_SIZE - 2)
    };
    match (randomization, perms) {
        (Randomization::PermuteDigits, Some(p)) => scrambled_radical_inverse(d, h, p, seed),
        (Randomization::Owen | Randomization::FastOwen, _) => {
            owen_scrambled_radical_inverse(d, h, mix_bits(1 + ((d as u64) << 4)) ^ seed)
        }
        _ => radical_inverse(d, h),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primes_are_the_first_thousand() {
        assert_eq!(&PRIMES[..10], &[2, 3, 5, 7, 11, 13, 17, 19, 23, 29]);
        assert_eq!(PRIMES[999], 7919);
    }

    #[test]
    fn radical_inverses_by_hand() {
        // 6 = 110₂ → 0.011₂ = 3/8; 5 = 12₃ → 0.21₃ = 2/3 + 1/9 = 7/9; 7 = 12₅ → 0.21₅ = 11/25.
        assert_eq!(radical_inverse(0, 6), 0.375);
        assert!((radical_inverse(1, 5) - 7.0 / 9.0).abs() < 1e-7);
        assert!((radical_inverse(2, 7) - 11.0 / 25.0).abs() < 1e-7);
        assert_eq!(radical_inverse(0, 0), 0.0);
        assert_eq!(radical_inverse(0, 1), 0.5);
        // 0.1₂… the first Halton points in base 2: 1/2, 1/4, 3/4, 1/8.
        let v: Vec<f32> = (1..5).map(|a| radical_inverse(0, a)).collect();
        assert_eq!(v, [0.5, 0.25, 0.75, 0.125]);
        // Inverting: 0.21₃ mirrored is 12₃ = 5.
        assert_eq!(inverse_radical_inverse(7, 3, 2), 5);
        assert_eq!(inverse_radical_inverse(6, 2, 3), 3);
    }

    #[test]
    fn digit_permutations_are_permutations_and_stratify() {
        // With every digit position permuted, the first b^k indices still put one point in
        // each interval [j/b^k, (j+1)/b^k).
        let perms = DigitPermutations::new(7);
        for base_index in [0usize, 1, 2, 5, 200] {
            let b = PRIMES[base_index] as usize;
            let n = if b < 10 { b * b } else { b };
            let mut seen = vec![0; n];
            for a in 0..n as u64 {
                let v = scrambled_radical_inverse(base_index, a, &perms, 7);
                seen[(v * n as f32) as usize] += 1;
            }
            assert!(seen.iter().all(|&c| c == 1), "base {b}: {seen:?}");
            let mut seen = vec![0; n];
            for a in 0..n as u64 {
                let v = owen_scrambled_radical_inverse(base_index, a, 99);
                seen[(v * n as f32) as usize] += 1;
            }
            assert!(seen.iter().all(|&c| c == 1), "owen base {b}: {seen:?}");
        }
    }

    #[test]
    fn each_pixel_gets_its_own_residue_class() {
        // A 4 × 3 film: tile 4 × 3 (2², 3¹). The pixel position of a pixel's samples, scaled
        // by the tile, lands in that pixel.
        let t = HaltonTiling::new([4, 3]);
        assert_eq!((t.scales, t.exponents), ([4, 3], [2, 1]));
        for y in 0..3 {
            for x in 0..4 {
                for s in 0..5 {
                    let h = t.index(x, y, s);
                    assert_eq!(h % 12, t.index(x, y, 0));
                    let px = radical_inverse(0, h) * 4.0;
                    let py = radical_inverse(1, h) * 3.0;
                    assert_eq!((px as i32, py as i32), (x, y), "sample {s}");
                    // The in-pixel position is the fractional part.
                    let (fx, fy) = t.pixel_2d(h);
                    assert!((px.fract() - fx).abs() < 1e-5 && (py.fract() - fy).abs() < 1e-5);
                }
            }
        }
        // (3⁵)⁻¹ mod 2⁷ for a 128-pixel film: 243 · 59 = 14337 = 112·128 + 1.
        let t = HaltonTiling::new([1000, 1000]);
        assert_eq!(t.scales, [128, 243]);
        assert_eq!(t.mult_inverse[0], 59);
    }
}
