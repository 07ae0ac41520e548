//! The light vertices of an iteration hashed for merging (as the paper's SmallVCM): cells
//! 2r wide, each vertex in the one cell holding it, cells hashed into a table of about one
//! bucket per vertex (cells along x in consecutive buckets); a query at p visits the
//! 2 × 2 × 2 cells nearest p, which cover the sphere of radius r around it.
//!
//! The buckets are filled by a stable counting sort (each vertex's bucket computed in
//! parallel), so a bucket lists its vertices in their order, and a query visits each distinct
//! bucket once, in a fixed order: the merges, and their sum, do not depend on the threads.

use crate::math::Vec3;
use rayon::prelude::*;

/// Light vertices by cell.
#[derive(Clone, Debug)]
pub struct MergeGrid {
    lo: Vec3,
    /// 1 / cell width (1/(2r)).
    inv_cell: f32,
    mask: u32,
    /// Start of each bucket's run in `items` (one more entry than there are buckets).
    starts: Vec<u32>,
    /// The vertices' indices, bucket by bucket, each bucket in vertex order.
    items: Vec<u32>,
    /// Their positions, in the same order (a query tests them without reading the
    /// vertices).
    positions: Vec<Vec3>,
    /// r².
    r2: f32,
}

/// The bucket of cell (`x`, `y`, `z`) in a table of `mask` + 1 buckets: x + y·P₁ + z·P₂, so
/// that cells next to each other along x are in consecutive buckets, whose vertices a query
/// reads in one run.
#[inline]
fn bucket(x: i32, y: i32, z: i32, mask: u32) -> u32 {
    (x as u32)
        .wrapping_add((y as u32).wrapping_mul(73_856_093))
        .wrapping_add((z as u32).wrapping_mul(19_349_663))
        & mask
}

impl MergeGrid {
    /// The grid of `points` for queries of radius `radius`; `None` when there is no point or
    /// the radius is not positive and finite.
    pub fn build(points: &[Vec3], radius: f32) -> Option<MergeGrid> {
        if points.is_empty() || !(radius > 0.0 && radius.is_finite()) {
            return None;
        }
        let lo = points
            .iter()
            .fold(Vec3::splat(f32::INFINITY), |a, &p| a.min(p));
        let n = points.len().next_power_of_two();
        let mut grid = MergeGrid {
            lo,
            inv_cell: 0.5 / radius,
            mask: n as u32 - 1,
            starts: Vec::new(),
            items: Vec::new(),
            positions: Vec::new(),
            r2: radius * radius,
        };
        let hashes: Vec<u32> = points
            .par_iter()
            .map(|&p| {
                let c = (p - grid.lo) * grid.inv_cell;
                bucket(
                    c.x.floor() as i32,
                    c.y.floor() as i32,
                    c.z.floor() as i32,
                    grid.mask,
                )
            })
            .collect();
        let mut starts = vec![0u32; n + 1];
        for &h in &hashes {
            starts[h as usize + 1] += 1;
        }
        for i in 0..n {
            starts[i + 1] += starts[i];
        }
        let mut next = starts.clone();
        let mut items = vec![0u32; points.len()];
        for (i, &h) in hashes.iter().enumerate() {
            items[next[h as usize] as usize] = i as u32;
            next[h as usize] += 1;
        }
        grid.positions = items.iter().map(|&i| points[i as usize]).collect();
        grid.starts = starts;
        grid.items = items;
        Some(grid)
    }

    /// Calls `f` with every point within the radius of `p` (|pᵢ − p|² ≤ r²), each once, in a
    /// fixed order (they are among the points of the 2 × 2 × 2 cells nearest `p`).
    #[inline]
    pub fn for_each_near(&self, p: Vec3, mut f: impl FnMut(u32)) {
        let c = (p - self.lo) * self.inv_cell - Vec3::splat(0.5);
        if !c.is_finite() {
            return;
        }
        let (x, y, z) = (c.x.floor() as i32, c.y.floor() as i32, c.z.floor() as i32);
        // The pairs of cells along x are consecutive buckets: one run each (unless the pair
        // wraps around the table, or a bucket was visited already by a colliding pair).
        let mut seen = [u32::MAX; 8];
        let mut n = 0;
        for k in 0..4 {
            let h0 = bucket(x, y + (k & 1), z + (k >> 1), self.mask);
            let h1 = (h0 + 1) & self.mask;
            let new0 = !seen[..n].contains(&h0);
            if new0 {
                seen[n] = h0;
                n += 1;
            }
            let new1 = !seen[..n].contains(&h1);
            if new1 {
                seen[n] = h1;
                n += 1;
            }
            if new0 && new1 && h1 == h0 + 1 {
                self.scan(h0 as usize, h0 as usize + 2, p, &mut f);
            } else {
                if new0 {
                    self.scan(h0 as usize, h0 as usize + 1, p, &mut f);
                }
                if new1 {
                    self.scan(h1 as usize, h1 as usize + 1, p, &mut f);
                }
            }
        }
    }

    /// Calls `f` with the points of buckets `b0..b1` within the radius of `p`.
    #[inline]
    fn scan(&self, b0: usize, b1: usize, p: Vec3, f: &mut impl FnMut(u32)) {
        let (a, b) = (self.starts[b0] as usize, self.starts[b1] as usize);
        for (&i, &q) in self.items[a..b].iter().zip(&self.positions[a..b]) {
            if (q - p).length_squared() <= self.r2 {
                f(i);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point within the radius is found exactly once, and no other, whatever the
    /// bucket collisions (a table of far fewer buckets than cells).
    #[test]
    fn finds_every_point_within_the_radius_once() {
        let mut pts = Vec::new();
        let mut s = 1u32;
        let mut rnd = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32
        };
        for _ in 0..500 {
            pts.push(Vec3::new(rnd(), rnd(), rnd() * 0.3));
        }
        let r = 0.07;
        // 500 points (a table of 512 buckets), and 3 (4 buckets: pairs wrap around).
        for count in [500, 3] {
            let pts = &pts[..count];
            let grid = MergeGrid::build(pts, r).unwrap();
            for q in 0..300 {
                let p = Vec3::new(rnd(), rnd(), rnd() * 0.3);
                let p = if count == 3 {
                    pts[q % 3] + (p - pts[q % 3]) * 0.1
                } else {
                    p
                };
                let mut found = vec![0u32; pts.len()];
                grid.for_each_near(p, |i| found[i as usize] += 1);
                for (i, v) in pts.iter().enumerate() {
                    let inside = (*v - p).length_squared() <= r * r;
                    assert_eq!(
                        found[i],
                        u32::from(inside),
                        "{count} points, query {q}: point {i}"
                    );
                }
            }
        }
        assert!(MergeGrid::build(&[], 1.0).is_none());
        assert!(MergeGrid::build(&pts, 0.0).is_none());
    }
}
