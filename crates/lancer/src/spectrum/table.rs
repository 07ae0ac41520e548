//! The RGB → spectrum coefficient table, fitted when the crate is compiled.
//!
//! `build.rs` fits every grid point with [`super::fit`] (the same code the library runs) and
//! writes the coefficients as little-endian `f32` (3 × 40³ × 3 of them, 2.3 MB) to the build's
//! output directory; the library includes those bytes and reads its lookups from them in place
//! (no decoded copy: a process reads in only the pages its lookups touch). A process therefore pays nothing to fit the table, and every build has the
//! same table bit for bit (the fit is plain IEEE arithmetic in a fixed order, whatever the
//! optimisation level or the number of threads). [`CoefficientTable::fit`] fits it afresh at
//! run time; the tests check that the two agree bit for bit.

use std::sync::OnceLock;

use super::fit::{self, TABLE_LEN, TABLE_RES, Z_MAX, Z_MIN};
use crate::math::Rgb;

/// The coefficients fitted by the build script: each an `f32`, little-endian, in the order
/// of [`fit::table_index`].
static SHIPPED: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/uplift_table.bin"));

/// The Rec. 2020 table fitted by the build script (for colours outside the sRGB gamut), in the
/// same layout.
static SHIPPED_REC2020: &[u8] =
    include_bytes!(concat!(env!("OUT_DIR"), "/uplift_table_rec2020.bin"));

/// φ(z) = S⁻¹(z) = (z − ½)/√(z(1 − z)) in single precision, for the table's z_k and its
/// lookups alike (so that a lookup at z_k has a fraction of exactly 0 or 1).
#[inline]
fn phi_f32(z: f32) -> f32 {
    (z - 0.5) / (z * (1.0 - z)).sqrt()
}

/// Coefficients of the sigmoid spectra of a grid over the colour cube, interpolated to uplift
/// any colour without a fit, after pbrt-v4's `RGBToSpectrumTable`.
///
/// A colour with largest component z = rgb\[l\] (l ∈ {0, 1, 2}) is placed at (l, z, x, y) with
/// x = rgb[(l+1) mod 3]/z and y = rgb[(l+2) mod 3]/z in [0, 1]. Each of the three blocks l has
/// n = [`TABLE_RES`] grid points per axis, denser where the coefficients change fastest:
///
/// - z_k = smoothstep(smoothstep(k/(n−1))) (pbrt-v4's spacing), kept inside
///   [10⁻⁷, 1 − 10⁻⁷], where colours near black and near white need large coefficients;
/// - x_i = smoothstep(i/(n−1)), likewise y_j (pbrt-v4 spaces them uniformly): near 0 lie
///   saturated colours, near 1 near-greys and near-whites. With uniform spacing the error
///   reaches 1.7·10⁻² near white at this resolution, and 3·10⁻³ at 64.
///
/// Each point holds the coefficients fitted to its colour. A lookup interpolates them
/// trilinearly, linearly in x and y, and along z linearly in φ(z) = S⁻¹(z) =
/// (z − ½)/√(z(1 − z)) rather than in z: φ(z) is exactly c₂ for a grey, and it follows the
/// growth of the coefficients towards black and white.
pub struct CoefficientTable {
    /// z_k, ascending from 0 to 1.
    z: [f32; TABLE_RES],
    /// φ(z_k).
    phi: [f32; TABLE_RES],
    /// x_i (and y_i), ascending from 0 to 1.
    ratio: [f32; TABLE_RES],
    /// Coefficients, at index ((l·n + k)·n + j)·n + i for z_k, x_i, y_j.
    coeffs: Coeffs,
}

/// The coefficient triples: fitted in this process, or read in place from the bytes the
/// build script shipped (so that a process holds no decoded copy of the 2.3 MB, and only the
/// pages its lookups touch are read in).
enum Coeffs {
    Fitted(Vec<[f32; 3]>),
    /// Little-endian `f32`, three per entry.
    Encoded(&'static [u8]),
}

impl Coeffs {
    /// Number of triples.
    fn len(&self) -> usize {
        match self {
            Coeffs::Fitted(v) => v.len(),
            Coeffs::Encoded(b) => b.len() / 12,
        }
    }

    /// Triple `i`.
    #[inline]
    fn get(&self, i: usize) -> [f32; 3] {
        match self {
            Coeffs::Fitted(v) => v[i],
            Coeffs::Encoded(b) => {
                let e = &b[12 * i..12 * i + 12];
                std::array::from_fn(|m| {
                    f32::from_le_bytes([e[4 * m], e[4 * m + 1], e[4 * m + 2], e[4 * m + 3]])
                })
            }
        }
    }

    /// Every triple, in order.
    #[cfg(test)]
    fn to_vec(&self) -> Vec<[f32; 3]> {
        (0..self.len()).map(|i| self.get(i)).collect()
    }
}

impl CoefficientTable {
    /// A table of [`fit::TABLE_LEN`] coefficient triples in the grid's index order.
    fn from_coefficients(coeffs: Coeffs) -> CoefficientTable {
        assert_eq!(
            coeffs.len(),
            TABLE_LEN,
            "coefficient table of the wrong size"
        );
        let z: [f32; TABLE_RES] = std::array::from_fn(|k| fit::z_grid(k) as f32);
        CoefficientTable {
            z,
            phi: z.map(phi_f32),
            ratio: std::array::from_fn(|i| fit::ratio_grid(i) as f32),
            coeffs,
        }
    }

    /// A table written by the build script (little-endian `f32`), read in place.
    fn from_bytes(bytes: &'static [u8]) -> CoefficientTable {
        CoefficientTable::from_coefficients(Coeffs::Encoded(bytes))
    }

    /// Fits every grid point now, on `threads` threads (about 0.6 s of processor time); the
    /// result is the table the build script shipped, bit for bit.
    pub fn fit(threads: usize) -> CoefficientTable {
        CoefficientTable::from_coefficients(Coeffs::Fitted(fit::fit_table(
            threads,
            &super::cie::XYZ_TO_SRGB,
        )))
    }

    /// The table fitted at compile time, set up on first use.
    pub fn get() -> &'static CoefficientTable {
        static TABLE: OnceLock<CoefficientTable> = OnceLock::new();
        TABLE.get_or_init(|| CoefficientTable::from_bytes(SHIPPED))
    }

    /// The Rec. 2020 table fitted at compile time (colours in linear Rec. 2020, seen under
    /// D65, [`super::cie::XYZ_TO_REC2020`]), set up on first use.
    pub fn get_rec2020() -> &'static CoefficientTable {
        static TABLE: OnceLock<CoefficientTable> = OnceLock::new();
        TABLE.get_or_init(|| CoefficientTable::from_bytes(SHIPPED_REC2020))
    }

    /// The interpolated coefficients of a colour in [0, 1]³ that is not grey (so its largest
    /// component is positive).
    pub fn lookup(&self, rgb: Rgb) -> [f32; 3] {
        let n = TABLE_RES;
        let c = rgb.to_array();
        // The largest component, ties to the later one (as pbrt-v4).
        let l = if c[0] > c[1] {
            if c[0] > c[2] { 0 } else { 2 }
        } else if c[1] > c[2] {
            1
        } else {
            2
        };
        let z = c[l];
        let x = c[(l + 1) % 3] / z;
        let y = c[(l + 2) % 3] / z;
        // Cell and fraction along x or y: v between x_i and x_{i+1}.
        let cell = |v: f32| {
            let i = self.ratio.partition_point(|&r| r <= v).clamp(1, n - 1) - 1;
            (i, (v - self.ratio[i]) / (self.ratio[i + 1] - self.ratio[i]))
        };
        let (i, fx) = cell(x);
        let (j, fy) = cell(y);
        // Along z, the fraction is measured in φ(z) = S⁻¹(z) (exact for greys, whose
        // coefficients are (0, 0, φ(z)), and tame where φ grows without bound near 0 and 1).
        let z = z.clamp(Z_MIN as f32, Z_MAX as f32);
        let k = self.z.partition_point(|&zk| zk <= z).clamp(1, n - 1) - 1;
        let fz = (phi_f32(z) - self.phi[k]) / (self.phi[k + 1] - self.phi[k]);
        let at = |dk: usize, dj: usize, di: usize| {
            self.coeffs.get(fit::table_index(l, k + dk, i + di, j + dj))
        };
        let lerp =
            |a: [f32; 3], b: [f32; 3], t: f32| std::array::from_fn(|m| a[m] + (b[m] - a[m]) * t);
        let plane = |dk: usize| {
            lerp(
                lerp(at(dk, 0, 0), at(dk, 0, 1), fx),
                lerp(at(dk, 1, 0), at(dk, 1, 1), fx),
                fy,
            )
        };
        lerp(plane(0), plane(1), fz)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bits(coeffs: &[[f32; 3]]) -> Vec<u32> {
        coeffs.iter().flatten().map(|v| v.to_bits()).collect()
    }

    #[test]
    fn shipped_table_is_a_fresh_fit_bit_for_bit() {
        // The build script's table (fitted by unoptimised code, on the build's thread count)
        // is what the library fits now, on two threads.
        let shipped = CoefficientTable::get();
        assert_eq!(SHIPPED.len(), TABLE_LEN * 12);
        assert_eq!(shipped.coeffs.len(), TABLE_LEN);
        let fresh = CoefficientTable::fit(2);
        assert!(
            bits(&shipped.coeffs.to_vec()) == bits(&fresh.coeffs.to_vec()),
            "the shipped table differs from a fresh fit"
        );
        assert_eq!(shipped.z, fresh.z);
        assert_eq!(shipped.phi, fresh.phi);
        assert_eq!(shipped.ratio, fresh.ratio);
        // A sample of rows fitted on their own, one thread: each row is a pure function of
        // its index (so the thread count cannot matter).
        let fitter = fit::Fitter::new();
        let n = TABLE_RES;
        for row in [0, 7, n + 13, 2 * n + 39] {
            let (l, j) = (row / n, row % n);
            let values = fitter.table_row(row);
            for k in 0..n {
                for i in 0..n {
                    let shipped = shipped.coeffs.get(fit::table_index(l, k, i, j));
                    assert_eq!(
                        shipped.map(f32::to_bits),
                        values[k * n + i].map(f32::to_bits),
                        "row {row}, k {k}, i {i}"
                    );
                }
            }
        }
    }

    #[test]
    fn bytes_decode_to_the_coefficients_they_encode() {
        // Little-endian f32, three per entry: 1.0 is 00 00 80 3f.
        let mut coeffs = vec![[0.0f32; 3]; TABLE_LEN];
        coeffs[0] = [1.0, -2.5, 3.0e-8];
        coeffs[TABLE_LEN - 1] = [f32::MAX, f32::MIN_POSITIVE, -0.0];
        let bytes: Vec<u8> = coeffs
            .iter()
            .flatten()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        assert_eq!(bytes.len(), TABLE_LEN * 12);
        assert_eq!(&bytes[..4], &[0x00, 0x00, 0x80, 0x3f]);
        let table = CoefficientTable::from_bytes(Vec::leak(bytes));
        assert!(bits(&table.coeffs.to_vec()) == bits(&coeffs));
    }

    #[test]
    fn grid_lookups_return_the_stored_coefficients() {
        // At a grid colour every fraction is 0 (or 1 at the upper ends, where the next cell's
        // weight is the whole), so the lookup is the stored entry itself.
        let table = CoefficientTable::get();
        for (l, k, i, j) in [(0, 10, 3, 30), (1, 25, 38, 0), (2, 38, 20, 21)] {
            let c = Rgb::from_array(fit::grid_colour(l, k, i, j).map(|v| v as f32));
            let got = table.lookup(c);
            let stored = table.coeffs.get(fit::table_index(l, k, i, j));
            for m in 0..3 {
                assert!(
                    (got[m] - stored[m]).abs() <= 1e-4 * stored[m].abs().max(1.0),
                    "({l}, {k}, {i}, {j}): {got:?} vs {stored:?}"
                );
            }
        }
    }
}
