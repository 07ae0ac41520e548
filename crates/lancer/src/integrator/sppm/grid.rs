//! The visible points of an iteration, hashed into a uniform grid so that a photon finds those
//! whose sphere (their pixel's radius) may hold it, as pbrt-v4's SPPM does: cells about as
//! wide as the largest radius, each visible point listed in every cell its sphere's bounding
//! box overlaps, cells hashed into a table of about one bucket per visible point.
//!
//! Built in the order of the points given, so that a bucket lists its points in that order,
//! each once: the photons' deposits, and so the image, depend neither on the thread count nor
//! on the grid (a pixel's deposits are the photons within its radius, in photon order).

use crate::math::Vec3;
use crate::sampling::hash_u64;

/// The most cells along an axis (a degenerate radius cannot make the grid unbounded).
const MAX_RES: i32 = 1 << 20;

/// Visible points by grid cell.
#[derive(Clone, Debug)]
pub struct VisibleGrid {
    lo: Vec3,
    hi: Vec3,
    res: [i32; 3],
    mask: u64,
    /// Start of each bucket's run in `items` (one more entry than there are buckets).
    starts: Vec<u32>,
    /// The points' indices, bucket by bucket.
    items: Vec<u32>,
}

impl VisibleGrid {
    /// The grid of `points` (centre and radius, indexed by their position in the slice);
    /// `None` when there is none with a positive, finite radius and a finite centre.
    pub fn build(points: &[(Vec3, f32)]) -> Option<VisibleGrid> {
        let valid = |(p, r): &(Vec3, f32)| p.is_finite() && r.is_finite() && *r > 0.0;
        let live: Vec<usize> = (0..points.len()).filter(|&i| valid(&points[i])).collect();
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        let mut max_r = 0.0f32;
        for &i in &live {
            let (p, r) = points[i];
            lo = lo.min(p - Vec3::splat(r));
            hi = hi.max(p + Vec3::splat(r));
            max_r = max_r.max(r);
        }
        if live.is_empty() || max_r <= 0.0 {
            return None;
        }
        // Cells about the largest radius wide along the longest axis (pbrt-v4's resolution).
        let diag = hi - lo;
        let max_diag = diag.max_element();
        let base = ((max_diag / max_r) as i32).clamp(1, MAX_RES);
        let res = [0, 1, 2].map(|i| ((base as f32 * diag[i] / max_diag) as i32).max(1));
        let buckets = live.len().next_power_of_two();
        let mut grid = VisibleGrid {
            lo,
            hi,
            res,
            mask: buckets as u64 - 1,
            starts: vec![0; buckets + 1],
            items: Vec::new(),
        };
        // Two passes: count each bucket's entries, then fill them in point order.
        let each_cell = |f: &mut dyn FnMut(usize, usize)| {
            for &i in &live {
                let (p, r) = points[i];
                let a = grid.cell(p - Vec3::splat(r)).0;
                let b = grid.cell(p + Vec3::splat(r)).0;
                for z in a[2]..=b[2] {
                    for y in a[1]..=b[1] {
                        for x in a[0]..=b[0] {
                            f(grid.bucket([x, y, z]), i);
                        }
                    }
                }
            }
        };
        // A point is listed once per bucket, though several of its cells may hash to the same
        // bucket (a photon must meet it once, and the listing must not depend on how many
        // buckets there are): its cells come one after the other, so a repeat is the last
        // entry of the bucket.
        let mut last = vec![u32::MAX; buckets];
        let mut counts = vec![0u32; buckets];
        each_cell(&mut |h, i| {
            if last[h] != i as u32 {
                last[h] = i as u32;
                counts[h] += 1;
            }
        });
        let mut starts = vec![0u32; buckets + 1];
        for h in 0..buckets {
            starts[h + 1] = starts[h] + counts[h];
        }
        let mut items = vec![0u32; starts[buckets] as usize];
        let mut next = starts.clone();
        last.fill(u32::MAX);
        each_cell(&mut |h, i| {
            if last[h] != i as u32 {
                last[h] = i as u32;
                items[next[h] as usize] = i as u32;
                next[h] += 1;
            }
        });
        grid.starts = starts;
        grid.items = items;
        Some(grid)
    }

    /// The cell holding `p` (clamped to the grid) and whether `p` is inside the grid's bounds.
    #[inline]
    fn cell(&self, p: Vec3) -> ([i32; 3], bool) {
        let mut inside = true;
        let c = [0, 1, 2].map(|i| {
            let extent = self.hi[i] - self.lo[i];
            let o = if extent > 0.0 {
                (p[i] - self.lo[i]) / extent
            } else {
                0.0
            };
            let c = (self.res[i] as f32 * o) as i32;
            inside &= o.is_finite() && c >= 0 && c < self.res[i];
            c.clamp(0, self.res[i] - 1)
        });
        (c, inside)
    }

    /// The bucket of cell `c`.
    #[inline]
    fn bucket(&self, c: [i32; 3]) -> usize {
        (hash_u64(&[c[0] as u64, c[1] as u64, c[2] as u64]) & self.mask) as usize
    }

    /// The points listed in the bucket of the cell holding `p`, in the order they were
    /// given: every point whose sphere holds `p` is among them (with some others, of other
    /// cells or farther away, which the caller tests). Empty outside the grid.
    #[inline]
    pub fn candidates(&self, p: Vec3) -> &[u32] {
        let (c, inside) = self.cell(p);
        if !inside {
            return &[];
        }
        let h = self.bucket(c);
        &self.items[self.starts[h] as usize..self.starts[h + 1] as usize]
    }
}
