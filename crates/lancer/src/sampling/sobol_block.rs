//! Eight dimensions of one `sobol` sample at once, with the default fast Owen scrambling.
//!
//! Every dimension of a sample shares the Sobol index a, so dimensions j … j + 7 are
//! ⨁_{k: bit k of a set} (column k of C_j, …, column k of C_{j+7}): one eight-wide XOR per set
//! bit instead of one per set bit and dimension. The columns are kept transposed (row k holds
//! column k of every dimension, side by side) so that those eight columns are one contiguous
//! load, and the scramble (four multiplicative rounds and a bit reversal) runs on eight lanes
//! too; the compiler turns both loops into vector code. The values are bit for bit those of
//! the one-dimension path ([`super::sobol::sobol_sample_reversed`] then
//! [`super::sobol::fast_owen_scramble_reversed`]).

use super::hash::u32_to_unit_f32;
use super::sobol::{N_SOBOL_DIMENSIONS, fast_owen_scramble_reversed, sobol_matrices};

/// Dimensions computed together.
pub const BLOCK: usize = 8;

/// Length of a row of [`columns_by_bit`]: the table's dimensions and [`BLOCK`] more, so that a
/// block starting at any table dimension reads one contiguous slice.
const ROW: usize = N_SOBOL_DIMENSIONS + BLOCK;

/// The table dimension that sampler dimension `d` ≥ 2 uses: `d` itself inside the table, then
/// again from 2 (dimensions 0 and 1 place the sample in its pixel).
#[inline]
pub fn table_dimension(d: usize) -> usize {
    let n = N_SOBOL_DIMENSIONS;
    if d < n { d } else { 2 + (d - 2) % (n - 2) }
}

/// Row k: the bit-reversed column k of the generator matrix of each dimension `i` < [`ROW`]
/// (dimension [`table_dimension`]`(i)` past the table's end, so that the padding continues
/// the sequence of dimensions as the sampler numbers them).
fn columns_by_bit() -> &'static [[u32; ROW]; 32] {
    static T: std::sync::OnceLock<Box<[[u32; ROW]; 32]>> = std::sync::OnceLock::new();
    T.get_or_init(|| {
        let m = sobol_matrices();
        let mut t = Box::new([[0u32; ROW]; 32]);
        for (k, row) in t.iter_mut().enumerate() {
            for (i, c) in row.iter_mut().enumerate() {
                *c = m[table_dimension(i)][k].reverse_bits();
            }
        }
        t
    })
}

/// The scrambling seeds of the sampler's dimensions `i` < [`ROW`], from those of the table's
/// dimensions (`seed_of(table_dimension(i))`), padded as [`columns_by_bit`] is.
pub fn padded_seeds(seed_of: impl Fn(usize) -> u32) -> Box<[u32]> {
    (0..ROW).map(|i| seed_of(table_dimension(i))).collect()
}

/// Sampler dimensions `d` … `d + 7` (`d` ≥ 2) of Sobol point `a` (its low 32 bits), each
/// fast-Owen scrambled by its seed from `seeds` ([`padded_seeds`]), as floats in [0, 1).
#[inline]
pub fn sobol_block(a: u64, d: usize, seeds: &[u32]) -> [f32; BLOCK] {
    let t = table_dimension(d);
    let cols = columns_by_bit();
    let mut v = [0u32; BLOCK];
    let mut a = a as u32;
    while a != 0 {
        let row = &cols[(a.trailing_zeros() & 31) as usize][t..t + BLOCK];
        for (x, c) in v.iter_mut().zip(row) {
            *x ^= c;
        }
        a &= a - 1;
    }
    // The scramble lane by lane (inlined, the loop is vector code).
    let seeds = &seeds[t..t + BLOCK];
    let mut out = [0.0f32; BLOCK];
    for ((o, x), s) in out.iter_mut().zip(v).zip(seeds) {
        *o = u32_to_unit_f32(fast_owen_scramble_reversed(x, *s));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::sobol::sobol_sample_reversed;

    #[test]
    fn blocks_equal_the_one_dimension_path_bit_for_bit() {
        let seed_of = |d: usize| (d as u32).wrapping_mul(0x9e37_79b9) ^ 0x1234_5678;
        let seeds = padded_seeds(seed_of);
        let n = N_SOBOL_DIMENSIONS;
        for a in [
            0u64,
            1,
            2,
            3,
            77,
            0xffff,
            0x1234_5678,
            0xffff_ffff,
            0x1_0000_0005,
        ] {
            // Starts inside the table, straddling its end, and far past it (wrapped).
            for d in [2, 3, 9, n - 9, n - 8, n - 3, n - 1, n, n + 5, 3 * n + 7] {
                let block = sobol_block(a, d, &seeds);
                for (j, got) in block.into_iter().enumerate() {
                    let td = table_dimension(d + j);
                    let want = u32_to_unit_f32(fast_owen_scramble_reversed(
                        sobol_sample_reversed(a, td),
                        seed_of(td),
                    ));
                    assert_eq!(got.to_bits(), want.to_bits(), "a {a} d {d} lane {j}");
                }
            }
        }
    }

    #[test]
    fn dimension_one_table_is_pascals_recurrence_on_every_column() {
        // The samplers read dimension 1 from the table instead of `sobol_1`; both are linear
        // over GF(2), so agreeing on the 32 unit indices makes them agree everywhere.
        use crate::sampling::sobol::{sobol_1, sobol_sample};
        for k in 0..32 {
            assert_eq!(sobol_sample(1 << k, 1), sobol_1(1 << k), "column {k}");
        }
    }

    #[test]
    fn padding_continues_the_wrapped_dimensions() {
        let n = N_SOBOL_DIMENSIONS;
        assert_eq!(table_dimension(5), 5);
        assert_eq!(table_dimension(n), 2);
        assert_eq!(table_dimension(n + 1), 3);
        assert_eq!(table_dimension(2 * n - 2), 2);
        // A block that starts just before the table's end reads the padding, which holds the
        // dimensions the sampler wraps to.
        for i in 0..BLOCK {
            assert_eq!(
                table_dimension(table_dimension(n - 1) + i),
                table_dimension(n - 1 + i)
            );
        }
    }
}
