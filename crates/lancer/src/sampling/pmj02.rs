//! Progressive multi-jittered (0, 2) point sets, generated rather than tabulated.
//!
//! pbrt-v4's `pmj02bn` sampler reads five precomputed tables of 65 536 points; lancer builds
//! its sets itself, once per process and only as long as the samples per pixel need
//! (rounded up to a power of four), from the published construction:
//!
//! - Christensen, Kensler, Kilpatrick, "Progressive Multi-Jittered Sample Sequences" (EGSR
//!   2018): from n points (n a power of 4) on a √n × √n grid, the next n points go in the
//!   subquadrants diagonally opposite the existing points of each cell (2n points), the last
//!   2n in the two subquadrants left over in each cell (4n points, which of the two comes
//!   first picked at random). Each point is placed so that every power-of-two prefix is a
//!   (0, 2)-net: for N = 2ᵏ points, each of the k + 1 shapes of elementary interval
//!   (2ʲ columns × 2ᵏ⁻ʲ rows, j = 0…k) holds exactly one point. Among the valid positions
//!   the best of a few random candidates — the farthest from the points already placed —
//!   is kept, the "bn" (blue-noise-like) variant.
//! - Pharr, "Efficient Generation of Points that Satisfy Two-Dimensional Elementary
//!   Intervals" (JCGT 2019): within the point's cell the valid positions are a product of
//!   valid x strata and valid y strata, each found by a search over the bits of the stratum
//!   index that prunes at the first occupied interval (no dart throwing).
//!
//! Why x and y decouple: a point at finest strata (X, Y), X, Y ∈ [0, 2ᵏ), lies in interval
//! (X ≫ (k−j), Y ≫ j) of shape j. The cell fixes the top bx bits of X and by of Y with
//! bx + by ≥ k; a shape with j > bx needs only top bits of Y that the cell fixes, one with
//! k − j > by only top bits of X that the cell fixes, and no shape needs both free parts.
//!
//! Points are 32-bit fixed point (value / 2³²); every set is a pure function of its index, so
//! renders are deterministic and a set of 4ᵐ points is a prefix of any larger one.

use super::rng::Pcg32;
use std::sync::{Arc, OnceLock};

/// Distinct point sets (pbrt-v4 has five tables); dimension pairs past them reuse a set
/// with the sample index permuted.
pub const N_PMJ02_SETS: usize = 4;

/// The largest set: 4⁸ = 65 536 points, as pbrt-v4's tables.
pub const MAX_PMJ02_SAMPLES: u32 = 1 << 16;

/// Random candidates per point for the blue-noise choice.
const N_CANDIDATES: usize = 8;

/// [`N_PMJ02_SETS`] sets of 2D points in 32-bit fixed point.
pub type Pmj02Sets = [Vec<[u32; 2]>; N_PMJ02_SETS];

/// The sets of at least `n` points (rounded up to a power of 4, at most
/// [`MAX_PMJ02_SAMPLES`]), generated on first use and kept for the process.
pub fn pmj02_sets(n: u32) -> Arc<Pmj02Sets> {
    static SETS: [OnceLock<Arc<Pmj02Sets>>; 9] = [const { OnceLock::new() }; 9];
    let n = n.clamp(1, MAX_PMJ02_SAMPLES);
    let log4 = n.next_power_of_two().trailing_zeros().div_ceil(2);
    SETS[log4 as usize]
        .get_or_init(|| {
            let len = 1usize << (2 * log4);
            Arc::new(std::array::from_fn(|s| generate_pmj02bn(len, s as u64)))
        })
        .clone()
}

/// Which elementary intervals of a 2ᵏ-point net hold a point: one bit per interval of each
/// shape j (2ʲ columns × 2ᵏ⁻ʲ rows), interval (c, r) at bit c·2ᵏ⁻ʲ + r of shape j.
struct Occupancy {
    k: u32,
    bits: Vec<Vec<bool>>,
}

impl Occupancy {
    fn new(k: u32, points: &[[u32; 2]]) -> Occupancy {
        let mut o = Occupancy {
            k,
            bits: vec![vec![false; 1 << k]; k as usize + 1],
        };
        for p in points {
            o.mark(*p);
        }
        o
    }

    #[inline]
    fn is_set(&self, j: u32, col: u32, row: u32) -> bool {
        self.bits[j as usize][((col << (self.k - j)) | row) as usize]
    }

    fn mark(&mut self, p: [u32; 2]) {
        let k = self.k;
        for j in 0..=k {
            // Shape j: x to j bits, y to k − j bits.
            let col = if j == 0 { 0 } else { p[0] >> (32 - j) };
            let row = if j == k { 0 } else { p[1] >> (32 - (k - j)) };
            self.bits[j as usize][((col << (k - j)) | row) as usize] = true;
        }
    }

    /// Every X ∈ [0, 2ᵏ) whose top `bx` bits are `cx` and whose intervals of the shapes
    /// j ≥ bx (which need only the top k − j ≤ by bits of Y, those of `cy`) are all free.
    fn valid_x(&self, cx: u32, bx: u32, cy: u32, by: u32, out: &mut Vec<u32>) {
        let k = self.k;
        let row = |j: u32| cy >> (by - (k - j));
        let mut stack = vec![(cx, bx)];
        while let Some((prefix, bits)) = stack.pop() {
            if self.is_set(bits, prefix, row(bits)) {
                continue;
            }
            if bits == k {
                out.push(prefix);
            } else {
                stack.push((prefix << 1 | 1, bits + 1));
                stack.push((prefix << 1, bits + 1));
            }
        }
    }

    /// Every Y ∈ [0, 2ᵏ) whose top `by` bits are `cy` and whose intervals of the shapes
    /// j = k − t ≤ k − by (t bits of Y, the top j ≤ bx bits of X from `cx`) are all free.
    fn valid_y(&self, cx: u32, bx: u32, cy: u32, by: u32, out: &mut Vec<u32>) {
        let k = self.k;
        let mut stack = vec![(cy, by)];
        while let Some((prefix, bits)) = stack.pop() {
            let j = k - bits;
            if self.is_set(j, cx >> (bx - j), prefix) {
                continue;
            }
            if bits == k {
                out.push(prefix);
            } else {
                stack.push((prefix << 1 | 1, bits + 1));
                stack.push((prefix << 1, bits + 1));
            }
        }
    }
}

/// The points placed so far in a grid of 2ᵇ × 2ᵇ cells, for nearest-neighbour distances on
/// the torus.
struct Grid {
    b: u32,
    cells: Vec<Vec<u32>>,
}

impl Grid {
    fn new(b: u32, points: &[[u32; 2]]) -> Grid {
        let mut g = Grid {
            b,
            cells: vec![Vec::new(); 1 << (2 * b)],
        };
        for (i, p) in points.iter().enumerate() {
            g.insert(i as u32, *p);
        }
        g
    }

    fn cell(&self, p: [u32; 2]) -> (u32, u32) {
        if self.b == 0 {
            (0, 0)
        } else {
            (p[0] >> (32 - self.b), p[1] >> (32 - self.b))
        }
    }

    fn insert(&mut self, i: u32, p: [u32; 2]) {
        let (cx, cy) = self.cell(p);
        self.cells[((cy << self.b) | cx) as usize].push(i);
    }

    /// Squared toroidal distance from `p` to the nearest point within two cells of it.
    fn min_dist2(&self, p: [u32; 2], points: &[[u32; 2]]) -> f64 {
        let side = 1i64 << self.b;
        let (cx, cy) = self.cell(p);
        let r = 2.min(side / 2);
        let mut best = f64::INFINITY;
        let axis = |a: u32, b: u32| {
            // The wrap-around difference of two fixed-point coordinates, in [0, 1/2].
            let d = a.wrapping_sub(b).min(b.wrapping_sub(a));
            d as f64 * (1.0 / 4_294_967_296.0)
        };
        for dy in -r..=r {
            for dx in -r..=r {
                let x = (cx as i64 + dx).rem_euclid(side);
                let y = (cy as i64 + dy).rem_euclid(side);
                for &i in &self.cells[((y << self.b) | x) as usize] {
                    let q = points[i as usize];
                    let (ex, ey) = (axis(p[0], q[0]), axis(p[1], q[1]));
                    best = best.min(ex * ex + ey * ey);
                }
            }
        }
        best
    }
}

/// The first `n` points of the pmj02bn sequence number `set` (deterministic: a PCG32 stream
/// per set).
pub fn generate_pmj02bn(n: usize, set: u64) -> Vec<[u32; 2]> {
    let mut rng = Pcg32::new(0x706d_6a30_3262_6e00 ^ set, set);
    let mut pts: Vec<[u32; 2]> = Vec::with_capacity(n);
    if n == 0 {
        return pts;
    }
    pts.push([rng.next_u32(), rng.next_u32()]);
    let mut m = 1usize; // a power of 4
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    while pts.len() < n {
        let half = m.trailing_zeros() / 2; // √m = 2^half
        // m → 2m: each cell of the √m grid gets a point in the subquadrant (of the 2√m grid)
        // diagonally opposite its existing point; 2m = 2ᵏ with k odd.
        let b = half + 1;
        let k = 2 * half + 1;
        let mut occ = Occupancy::new(k, &pts);
        let mut grid = Grid::new(b, &pts);
        for i in 0..m {
            if pts.len() == n {
                return pts;
            }
            let p = pts[i];
            let cell = (p[0] >> (32 - b) ^ 1, p[1] >> (32 - b) ^ 1);
            let q = place(&occ, &grid, &pts, cell, b, &mut rng, &mut xs, &mut ys);
            occ.mark(q);
            grid.insert(pts.len() as u32, q);
            pts.push(q);
        }
        // 2m → 4m: the two subquadrants left in each cell, in random order; 4m = 2ᵏ, k even.
        let k = 2 * half + 2;
        let mut occ = Occupancy::new(k, &pts);
        let flips: Vec<bool> = (0..m).map(|_| rng.next_u32() & 1 == 1).collect();
        for pass in 0..2 {
            for i in 0..m {
                if pts.len() == n {
                    return pts;
                }
                let p = pts[i];
                let (cx, cy) = (p[0] >> (32 - b), p[1] >> (32 - b));
                let cell = if flips[i] == (pass == 0) {
                    (cx ^ 1, cy)
                } else {
                    (cx, cy ^ 1)
                };
                let q = place(&occ, &grid, &pts, cell, b, &mut rng, &mut xs, &mut ys);
                occ.mark(q);
                grid.insert(pts.len() as u32, q);
                pts.push(q);
            }
        }
        m *= 4;
    }
    pts
}

/// A new point in `cell` of the 2ᵇ × 2ᵇ grid, in free elementary intervals of `occ`: the
/// farthest from the placed points of [`N_CANDIDATES`] random valid positions, each jittered
/// uniformly within its finest stratum (x to 2⁻ᵏ, y to 2⁻ᵏ).
#[allow(clippy::too_many_arguments)]
fn place(
    occ: &Occupancy,
    grid: &Grid,
    pts: &[[u32; 2]],
    cell: (u32, u32),
    b: u32,
    rng: &mut Pcg32,
    xs: &mut Vec<u32>,
    ys: &mut Vec<u32>,
) -> [u32; 2] {
    let k = occ.k;
    xs.clear();
    ys.clear();
    occ.valid_x(cell.0, b, cell.1, b, xs);
    occ.valid_y(cell.0, b, cell.1, b, ys);
    assert!(
        !xs.is_empty() && !ys.is_empty(),
        "pmj02: no free (0, 2) stratum in cell {cell:?} of a 2^{k} net"
    );
    let mut best = ([0u32; 2], -1.0f64);
    for _ in 0..N_CANDIDATES {
        let x = xs[(rng.next_u32() as usize) % xs.len()];
        let y = ys[(rng.next_u32() as usize) % ys.len()];
        let q = [
            (x << (32 - k)) | (rng.next_u32() >> k),
            (y << (32 - k)) | (rng.next_u32() >> k),
        ];
        let d = grid.min_dist2(q, pts);
        if d > best.1 {
            best = (q, d);
        }
    }
    best.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// True when the first 2ᵏ points put exactly one point in every elementary interval of
    /// every shape 2ʲ × 2ᵏ⁻ʲ.
    fn is_02_net(pts: &[[u32; 2]], k: u32) -> bool {
        (0..=k).all(|j| {
            let mut count = vec![0u32; 1 << k];
            for p in &pts[..1 << k] {
                let col = if j == 0 { 0 } else { p[0] >> (32 - j) };
                let row = if j == k { 0 } else { p[1] >> (32 - (k - j)) };
                count[((col << (k - j)) | row) as usize] += 1;
            }
            count.iter().all(|&c| c == 1)
        })
    }

    #[test]
    fn every_power_of_two_prefix_is_a_02_net() {
        // Powers of 4 are the (0, 2) nets of the construction; the odd powers of 2 in
        // between are the progressive property.
        for set in 0..N_PMJ02_SETS as u64 {
            let pts = generate_pmj02bn(4096, set);
            for k in 0..=12 {
                assert!(is_02_net(&pts, k), "set {set}, first 2^{k} points");
            }
        }
    }

    #[test]
    fn each_prefix_of_4m_is_jittered_in_its_square_grid() {
        // Multi-jittered: the first 4ᵐ points, one per cell of the 2ᵐ × 2ᵐ grid.
        let pts = generate_pmj02bn(1024, 2);
        for m in 0..=5u32 {
            let mut cells = vec![0u32; 1 << (2 * m)];
            for p in &pts[..1 << (2 * m)] {
                let (x, y) = if m == 0 {
                    (0, 0)
                } else {
                    (p[0] >> (32 - m), p[1] >> (32 - m))
                };
                cells[((y << m) | x) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "m = {m}");
        }
    }

    #[test]
    fn generation_is_deterministic_and_progressive() {
        let a = generate_pmj02bn(256, 1);
        let b = generate_pmj02bn(1024, 1);
        assert_eq!(a[..], b[..256], "a short set is a prefix of a long one");
        assert_eq!(a, generate_pmj02bn(256, 1));
        assert_ne!(a, generate_pmj02bn(256, 0), "sets differ");
        let s = pmj02_sets(10);
        assert_eq!(s[0].len(), 16, "10 samples round up to 16");
        assert_eq!(s[3][..], generate_pmj02bn(16, 3)[..]);
    }

    #[test]
    fn the_largest_sets_are_nets_too() {
        let pts = generate_pmj02bn(MAX_PMJ02_SAMPLES as usize, 0);
        for k in [14, 15, 16] {
            assert!(is_02_net(&pts, k), "first 2^{k} points");
        }
    }
}
