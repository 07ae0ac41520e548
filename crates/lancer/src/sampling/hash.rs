//! Hashes that turn (seed, pixel, sample index, dimension) into well-mixed bits: the sampler is
//! a pure function of them, so a render can be split and resumed with identical pixels.

/// The 64-bit finaliser of MurmurHash3 with Stafford's "Mix13" constants: every input bit
/// affects every output bit.
#[inline]
pub fn mix_bits(mut v: u64) -> u64 {
    v ^= v >> 31;
    v = v.wrapping_mul(0x7fb5_d329_728e_a185);
    v ^= v >> 27;
    v = v.wrapping_mul(0x81da_def4_bc2d_d44d);
    v ^= v >> 33;
    v
}

/// Hash of several 64-bit words, order-dependent.
#[inline]
pub fn hash_u64(words: &[u64]) -> u64 {
    let mut h = 0x9e37_79b9_7f4a_7c15u64;
    for &w in words {
        h = mix_bits(h ^ w.wrapping_add(0x9e37_79b9_7f4a_7c15).wrapping_add(h << 6));
    }
    h
}

/// A uniform float in [0, 1) from the top 24 bits of `v` (exactly representable, never 1).
#[inline]
pub fn u32_to_unit_f32(v: u32) -> f32 {
    (v >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// The `i`-th element of a pseudo-random permutation of `0..n` chosen by `seed`, computed
/// without storing the permutation (Kensler 2013, "Correlated Multi-Jittered Sampling": a
/// bijective hash on the next power of two, cycle-walked until it lands below `n`).
pub fn permutation_element(mut i: u32, n: u32, seed: u32) -> u32 {
    if n <= 1 {
        return 0;
    }
    let mut w = n - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    let p = seed;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dcb303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e501cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860a3df);
        i &= w;
        i ^= i >> 5;
        if i < n {
            break;
        }
    }
    (i.wrapping_add(p)) % n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn permutation_is_a_bijection() {
        for n in [1u32, 2, 3, 7, 16, 100] {
            for seed in [0u32, 1, 12345, 0xdead_beef] {
                let mut seen = vec![false; n as usize];
                for i in 0..n {
                    let e = permutation_element(i, n, seed) as usize;
                    assert!(!seen[e], "n={n} seed={seed} repeats {e}");
                    seen[e] = true;
                }
            }
        }
    }

    #[test]
    fn unit_floats_stay_below_one() {
        assert_eq!(u32_to_unit_f32(0), 0.0);
        assert!(u32_to_unit_f32(u32::MAX) < 1.0);
    }
}
