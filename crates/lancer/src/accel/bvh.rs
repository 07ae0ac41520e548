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
}

/// Four children's boxes side by side (one array per axis and side), so that one ray is
/// tested against all four at once with 4-wide vector instructions.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node4 {
    /// Lower corners: `min[axis][child]`.
    min: [[f32; 4]; 3],
    /// Upper corners: `max[axis][child]`.
    max: [[f32; 4]; 3],
    /// Interior child: index of its node; leaf child: its first primitive.
    child: [u32; 4],
    /// Leaf child: its primitive count; interior child: 0; empty slot: 0 with an empty box.
    count: [u32; 4],
}

/// A child reference on the traversal stack: a node (count 0) or a leaf's primitive range.
#[derive(Clone, Copy, Debug, Default)]
struct ChildRef {
    index: u32,
    count: u32,
}

/// A BVH over primitives given by their bounds. It stores primitive indices only; the caller
/// intersects primitives through a closure, so the same tree serves every kind of shape.
///
/// The tree is built binary (binned SAH) and then collapsed into a 4-wide tree: each node
/// holds up to four children, and a ray tests their four boxes at once.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// The binary tree, only while building.
    nodes: Vec<Node>,
    /// Bounds of everything.
    bounds: Bounds3,
    wide: Vec<Node4>,
    /// The root: a node, or a leaf when the tree has a single leaf.
    root: ChildRef,
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
            bounds: Bounds3::EMPTY,
            wide: Vec::new(),
            root: ChildRef::default(),
            indices: Vec::with_capacity(prims.len()),
        };
        if !prims.is_empty() {
            bvh.build_rec(&mut prims, 0);
            bvh.root = bvh.collapse(0);
            bvh.bounds = bvh.nodes[0].bounds;
            bvh.nodes = Vec::new();
        }
        bvh
    }

    /// The binary node `n` as a child reference of the wide tree, its subtree collapsed.
    fn collapse(&mut self, n: usize) -> ChildRef {
        let node = self.nodes[n];
        if node.count > 0 {
            return ChildRef {
                index: node.offset,
                count: node.count as u32,
            };
        }
        // Open the children with the largest boxes until there are four (or only leaves).
        let mut kids: Vec<usize> = vec![n + 1, node.offset as usize];
        while kids.len() < 4 {
            let widest = kids
                .iter()
                .enumerate()
                .filter(|(_, k)| self.nodes[**k].count == 0)
                .max_by(|a, b| {
                    let sa = self.nodes[*a.1].bounds.surface_area();
                    let sb = self.nodes[*b.1].bounds.surface_area();
                    sa.total_cmp(&sb)
                })
                .map(|(i, _)| i);
            let Some(i) = widest else { break };
            let k = kids.swap_remove(i);
            kids.push(k + 1);
            kids.push(self.nodes[k].offset as usize);
        }
        let index = self.wide.len();
        self.wide.push(Node4 {
            min: [[f32::INFINITY; 4]; 3],
            max: [[f32::NEG_INFINITY; 4]; 3],
            child: [0; 4],
            count: [0; 4],
        });
        for (slot, &k) in kids.iter().enumerate() {
            let b = self.nodes[k].bounds;
            let c = self.collapse(k);
            let w = &mut self.wide[index];
            for a in 0..3 {
                w.min[a][slot] = b.min[a];
                w.max[a][slot] = b.max[a];
            }
            w.child[slot] = c.index;
            w.count[slot] = c.count;
        }
        ChildRef {
            index: index as u32,
            count: 0,
        }
    }

    /// Bytes the tree occupies (nodes and primitive indices).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Bvh>()
            + self.wide.capacity() * std::mem::size_of::<Node4>()
            + self.indices.capacity() * 4
    }

    /// Bounds of everything in the tree.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    fn build_rec(&mut self, prims: &mut [BuildPrim], depth: u32) -> usize {
        let bounds = prims.iter().fold(Bounds3::EMPTY, |b, p| b.union(&p.bounds));
        let node_index = self.nodes.len();
        self.nodes.push(Node {
            bounds,
            offset: 0,
            count: 0,
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
        node_index
    }

    /// Visits the primitives whose bounds the ray crosses, nearest subtree first. `hit(i, ray)`
    /// tests primitive `i` and returns the new `t_max` if it found a closer hit; the ray is
    /// shortened as hits are found, so farther subtrees are culled.
    #[inline]
    pub fn intersect<F: FnMut(u32, &Ray) -> Option<f32>>(&self, ray: &Ray, mut hit: F) -> bool {
        if self.indices.is_empty() {
            return false;
        }
        let mut ray = *ray;
        let slabs = Slabs::new(&ray);
        // Entries carry the distance at which the ray enters their box, so that a subtree
        // found to lie beyond a closer hit is skipped when it is popped.
        let mut stack = [(ChildRef::default(), 0.0f32); 128];
        stack[0] = (self.root, 0.0);
        let mut sp = 1usize;
        let mut found = false;
        while sp > 0 {
            sp -= 1;
            let (c, t_enter) = stack[sp];
            if t_enter > ray.t_max {
                continue;
            }
            if c.count > 0 {
                for k in c.index..c.index + c.count {
                    if let Some(t) = hit(self.indices[k as usize], &ray) {
                        ray.t_max = t;
                        found = true;
                    }
                }
                continue;
            }
            let node = &self.wide[c.index as usize];
            let (t_near, mask) = slabs.test(node, ray.t_max);
            // Push the children crossed, farthest first, so the nearest is visited next.
            let mut order = [(0.0f32, 0usize); 4];
            let mut n = 0;
            for k in 0..4 {
                if mask[k] {
                    order[n] = (t_near[k], k);
                    n += 1;
                }
            }
            order[..n].sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
            for &(t, k) in &order[..n] {
                stack[sp] = (
                    ChildRef {
                        index: node.child[k],
                        count: node.count[k],
                    },
                    t,
                );
                sp += 1;
            }
        }
        found
    }

    /// True as soon as `hit(i, ray)` reports a hit (shadow rays).
    #[inline]
    pub fn intersect_any<F: FnMut(u32, &Ray) -> bool>(&self, ray: &Ray, mut hit: F) -> bool {
        if self.indices.is_empty() {
            return false;
        }
        let slabs = Slabs::new(ray);
        let mut stack = [ChildRef::default(); 128];
        stack[0] = self.root;
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            let c = stack[sp];
            if c.count > 0 {
                for k in c.index..c.index + c.count {
                    if hit(self.indices[k as usize], ray) {
                        return true;
                    }
                }
                continue;
            }
            let node = &self.wide[c.index as usize];
            let (_, mask) = slabs.test(node, ray.t_max);
            for (k, _) in mask.iter().enumerate().filter(|(_, m)| **m) {
                stack[sp] = ChildRef {
                    index: node.child[k],
                    count: node.count[k],
                };
                sp += 1;
            }
        }
        false
    }
}

/// A ray prepared for slab tests: its origin, 1/d, and for each axis whether d is negative
/// (then the box's far side on that axis is its min).
struct Slabs {
    o: [f32; 3],
    inv_d: [f32; 3],
    neg: [bool; 3],
}

impl Slabs {
    #[inline(always)]
    fn new(ray: &Ray) -> Slabs {
        let inv = ray.d.recip();
        Slabs {
            o: ray.o.to_array(),
            inv_d: inv.to_array(),
            neg: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0],
        }
    }

    /// The slab test against a node's four boxes at once: t_near = max over axes of the
    /// entry distances, t_far = min of the exit distances (enlarged by 2γ₃ so that rounding
    /// never culls a box the ray crosses); a box is crossed when t_near ≤ t_far, t_far ≥ 0
    /// and t_near < t_max.
    #[inline(always)]
    fn test(&self, node: &Node4, t_max: f32) -> ([f32; 4], [bool; 4]) {
        let mut t0 = [0.0f32; 4];
        let mut t1 = [t_max; 4];
        for a in 0..3 {
            let (near, far) = if self.neg[a] {
                (&node.max[a], &node.min[a])
            } else {
                (&node.min[a], &node.max[a])
            };
            for k in 0..4 {
                let tn = (near[k] - self.o[a]) * self.inv_d[a];
                let tf = (far[k] - self.o[a]) * self.inv_d[a] * (1.0 + 2.0 * crate::math::gamma(3));
                t0[k] = if tn > t0[k] { tn } else { t0[k] };
                t1[k] = if tf < t1[k] { tf } else { t1[k] };
            }
        }
        let mut mask = [false; 4];
        for k in 0..4 {
            mask[k] = t0[k] <= t1[k];
        }
        (t0, mask)
    }
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
