//! A bounding volume hierarchy built with the binned surface area heuristic.

use crate::math::{Bounds3, Vec3};
use crate::ray::Ray;

/// One node of the flattened tree. Interior nodes store their second child's index (the first
/// child follows them); leaves store a range of primitive indices.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Bounds3,
    /// Leaf: first primitive; interior: index of the second child.
    offset: u32,
    /// Leaf: primitive count (> 0); interior: 0.
    count: u16,
    /// Interior: split axis (which child is nearer depends on the ray's direction on it).
    axis: u8,
}

/// A BVH over primitives given by their bounds. It stores primitive indices only; the caller
/// intersects primitives through a closure, so the same tree serves every kind of shape.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Primitive indices in leaf order.
    pub indices: Vec<u32>,
}

const BINS: usize = 12;
const MAX_LEAF: usize = 2;

struct BuildPrim {
    bounds: Bounds3,
    centroid: Vec3,
    index: u32,
}

impl Bvh {
    /// Builds the tree over `bounds[i]` for every primitive `i` (binned SAH, 12 bins).
    pub fn build(bounds: &[Bounds3]) -> Bvh {
        let mut prims: Vec<BuildPrim> = bounds
            .iter()
            .enumerate()
            .map(|(i, b)| BuildPrim {
                bounds: *b,
                centroid: b.centroid(),
                index: i as u32,
            })
            .collect();
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * prims.len().max(1)),
            indices: Vec::with_capacity(prims.len()),
        };
        if !prims.is_empty() {
            bvh.build_rec(&mut prims, 0);
        }
        bvh
    }

    /// Bounds of everything in the tree.
    pub fn bounds(&self) -> Bounds3 {
        self.nodes.first().map_or(Bounds3::EMPTY, |n| n.bounds)
    }

    fn build_rec(&mut self, prims: &mut [BuildPrim], depth: u32) -> usize {
        let bounds = prims.iter().fold(Bounds3::EMPTY, |b, p| b.union(&p.bounds));
        let node_index = self.nodes.len();
        self.nodes.push(Node {
            bounds,
            offset: 0,
            count: 0,
            axis: 0,
        });
        let make_leaf = |bvh: &mut Bvh, prims: &[BuildPrim]| {
            let first = bvh.indices.len() as u32;
            bvh.indices.extend(prims.iter().map(|p| p.index));
            bvh.nodes[node_index].offset = first;
            bvh.nodes[node_index].count = prims.len() as u16;
        };
        if prims.len() <= MAX_LEAF {
            make_leaf(self, prims);
            return node_index;
        }
        let cb = prims
            .iter()
            .fold(Bounds3::EMPTY, |b, p| b.union_point(p.centroid));
        let axis = cb.max_extent();
        let (lo, hi) = (cb.min[axis], cb.max[axis]);
        // Deep in the tree, split by count so the depth stays below the traversal stack's size.
        let mid = if hi > lo && depth < 32 {
            // Bin centroids along the axis and pick the split of least SAH cost:
            // cost = N_left·A_left + N_right·A_right (relative to the parent's area).
            let mut counts = [0usize; BINS];
            let mut bb = [Bounds3::EMPTY; BINS];
            let scale = BINS as f32 / (hi - lo);
            let bin_of = |c: f32| (((c - lo) * scale) as usize).min(BINS - 1);
            for p in prims.iter() {
                let b = bin_of(p.centroid[axis]);
                counts[b] += 1;
                bb[b] = bb[b].union(&p.bounds);
            }
            let mut best = (f32::INFINITY, 0);
            for split in 1..BINS {
                let (mut bl, mut nl, mut br, mut nr) = (Bounds3::EMPTY, 0, Bounds3::EMPTY, 0);
                for i in 0..split {
                    bl = bl.union(&bb[i]);
                    nl += counts[i];
                }
                for i in split..BINS {
                    br = br.union(&bb[i]);
                    nr += counts[i];
                }
                let cost = nl as f32 * bl.surface_area() + nr as f32 * br.surface_area();
                if nl > 0 && nr > 0 && cost < best.0 {
                    best = (cost, split);
                }
            }
            let leaf_cost = prims.len() as f32 * bounds.surface_area();
            if best.1 == 0 || (prims.len() <= 16 && best.0 >= leaf_cost) {
                prims.len() / 2
            } else {
                let split = best.1;
                let mut i = 0;
                for j in 0..prims.len() {
                    if bin_of(prims[j].centroid[axis]) < split {
                        prims.swap(i, j);
                        i += 1;
                    }
                }
                i
            }
        } else {
            prims.len() / 2
        };
        if hi <= lo || mid == 0 || mid == prims.len() {
            // All centroids coincide: split in the middle of the list.
            if prims.len() <= u16::MAX as usize && hi <= lo && prims.len() <= 2 * MAX_LEAF {
                make_leaf(self, prims);
                return node_index;
            }
        }
        let mid = if mid == 0 || mid == prims.len() {
            prims.len() / 2
        } else {
            mid
        };
        let (left, right) = prims.split_at_mut(mid);
        self.build_rec(left, depth + 1);
        let second = self.build_rec(right, depth + 1);
        self.nodes[node_index].offset = second as u32;
        self.nodes[node_index].axis = axis as u8;
        node_index
    }

    /// Visits the primitives whose bounds the ray crosses, nearest subtree first. `hit(i, ray)`
    /// tests primitive `i` and returns the new `t_max` if it found a closer hit; the ray is
    /// shortened as hits are found, so farther subtrees are culled.
    #[inline]
    pub fn intersect<F: FnMut(u32, &Ray) -> Option<f32>>(&self, ray: &Ray, mut hit: F) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let mut ray = *ray;
        let inv_d = ray.d.recip();
        let neg = [inv_d.x < 0.0, inv_d.y < 0.0, inv_d.z < 0.0];
        let mut stack = [0u32; 64];
        let mut sp = 0usize;
        let mut node = 0usize;
        let mut found = false;
        loop {
            let n = &self.nodes[node];
            if slab(&n.bounds, &ray, inv_d) {
                if n.count > 0 {
                    for k in 0..n.count as usize {
                        let prim = self.indices[n.offset as usize + k];
                        if let Some(t) = hit(prim, &ray) {
                            ray.t_max = t;
                            found = true;
                        }
                    }
                } else {
                    let (first, second) = (node + 1, n.offset as usize);
                    let (near, far) = if neg[n.axis as usize] {
                        (second, first)
                    } else {
                        (first, second)
                    };
                    stack[sp] = far as u32;
                    sp += 1;
                    node = near;
                    continue;
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
        found
    }

    /// True as soon as `hit(i, ray)` reports a hit (shadow rays).
    #[inline]
    pub fn intersect_any<F: FnMut(u32, &Ray) -> bool>(&self, ray: &Ray, mut hit: F) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let inv_d = ray.d.recip();
        let mut stack = [0u32; 64];
        let mut sp = 0usize;
        let mut node = 0usize;
        loop {
            let n = &self.nodes[node];
            if slab(&n.bounds, ray, inv_d) {
                if n.count > 0 {
                    for k in 0..n.count as usize {
                        if hit(self.indices[n.offset as usize + k], ray) {
                            return true;
                        }
                    }
                } else {
                    stack[sp] = n.offset;
                    sp += 1;
                    node += 1;
                    continue;
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            node = stack[sp] as usize;
        }
    }
}

/// Slab test against precomputed 1/d; the far distance is enlarged by 2γ₃ so rounding never
/// culls a box the ray really crosses.
#[inline(always)]
fn slab(b: &Bounds3, ray: &Ray, inv_d: Vec3) -> bool {
    let t1 = (b.min - ray.o) * inv_d;
    let t2 = (b.max - ray.o) * inv_d;
    let tmin = t1.min(t2);
    let tmax = t1.max(t2) * (1.0 + 2.0 * crate::math::gamma(3));
    let t0 = tmin.max_element().max(0.0);
    let t1 = tmax.min_element().min(ray.t_max);
    t0 <= t1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{hash_u64, u32_to_unit_f32};

    fn rnd(i: u64) -> f32 {
        u32_to_unit_f32(hash_u64(&[i]) as u32)
    }

    #[test]
    fn bvh_finds_the_same_nearest_box_as_brute_force() {
        let boxes: Vec<Bounds3> = (0..500)
            .map(|i| {
                let c = Vec3::new(rnd(3 * i), rnd(3 * i + 1), rnd(3 * i + 2)) * 10.0;
                Bounds3::new(c, c + Vec3::splat(0.3))
            })
            .collect();
        let bvh = Bvh::build(&boxes);
        for k in 0..300u64 {
            let o = Vec3::new(rnd(10_000 + k), rnd(20_000 + k), rnd(30_000 + k)) * 12.0 - 1.0;
            let d = Vec3::new(
                rnd(40_000 + k) - 0.5,
                rnd(50_000 + k) - 0.5,
                rnd(60_000 + k) - 0.5,
            )
            .normalize();
            let ray = Ray::new(o, d);
            let brute = boxes
                .iter()
                .enumerate()
                .filter_map(|(i, b)| b.intersect_p(&ray).map(|(t0, _)| (t0, i as u32)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let mut best: Option<(f32, u32)> = None;
            bvh.intersect(&ray, |i, r| {
                let (t0, _) = boxes[i as usize].intersect_p(r)?;
                best = Some((t0, i));
                Some(t0)
            });
            assert_eq!(best.map(|b| b.1), brute.map(|b| b.1), "ray {k}");
            assert_eq!(
                bvh.intersect_any(&ray, |i, r| boxes[i as usize].intersect_p(r).is_some()),
                brute.is_some()
            );
        }
    }
}
