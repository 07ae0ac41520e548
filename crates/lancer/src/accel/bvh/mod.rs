//! An 8-wide bounding volume hierarchy built with the binned surface area heuristic.
//!
//! Build: top-down over primitive references; each node opens up to eight children by
//! repeated binary splits, greedily the one saving the most SAH cost, each chosen by the
//! binned SAH (32 bins over the centroids, all three axes); free slots also split small
//! leaves whose parts' boxes are much smaller than their common one. Large subtrees are built
//! in parallel (rayon). A leaf holds at most [`MAX_LEAF`] primitives, so that a leaf of
//! triangles fits one 4-wide packet. The build lives in `build`; this file holds the tree's
//! layout, its queries and the traversal.
//!
//! Traversal: one ray against a node's eight boxes at once (8-wide AVX slab test), children
//! visited nearest first, farther ones kept on a fixed stack with their entry distance.

mod build;

use super::packet::{PacketHits, RayPacket};
use super::simd::F8;
use crate::math::{Bounds3, Vec3, gamma, next_float_down};
use crate::ray::Ray;

/// Most primitives in one leaf.
pub const MAX_LEAF: usize = 4;
/// Beyond this depth (of the 4-wide tree) splits are median splits, which at least halve
/// every child: the depth, hence the traversal stack, stays bounded whatever the input.
const MAX_SAH_DEPTH: u32 = 24;
/// Children per node.
const WIDTH: usize = 8;
/// Size of the traversal stack: WIDTH − 1 entries per level at most, over at most
/// MAX_SAH_DEPTH levels of SAH splits and 32 of median splits (each at least halves).
const STACK: usize = (WIDTH - 1) * (MAX_SAH_DEPTH as usize + 32) + 1;
/// Flag of a child reference naming a leaf (the rest is the leaf's index).
const LEAF: u32 = 1 << 31;
/// Child reference of an unused slot (its box is empty and never crossed).
const EMPTY: u32 = u32::MAX;

/// Eight children's boxes side by side (one array per axis and side), so that one ray is
/// tested against all eight at once with 8-wide vector instructions.
#[derive(Clone, Copy, Debug)]
// Aligned to cache lines: a node is exactly four of them.
#[repr(C, align(64))]
struct Node {
    /// Lower corners: `min[axis][child]`.
    min: [[f32; WIDTH]; 3],
    /// Upper corners: `max[axis][child]`.
    max: [[f32; WIDTH]; 3],
    /// Child references: a node's index, `LEAF | count` (a leaf of `count` primitives), or
    /// `EMPTY`.
    child: [u32; WIDTH],
    /// Per leaf child, its [`Leaf::id`] (0 for the other slots). It fills the node's last
    /// cache line beside `child`: a leaf's id comes with the box test, not from a table.
    leaf_id: [u32; WIDTH],
}

impl Node {
    const UNUSED: Node = Node {
        min: [[f32::INFINITY; WIDTH]; 3],
        max: [[f32::NEG_INFINITY; WIDTH]; 3],
        child: [EMPTY; WIDTH],
        leaf_id: [0; WIDTH],
    };
}

/// A leaf as a traversal reaches it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Leaf {
    /// Its index among the leaves (`0..`[`Bvh::leaf_count`]), or, once
    /// [`Bvh::number_leaves_by_slot`] has run, the position of its first primitive in
    /// [`Bvh::indices`] (its primitives are the `count` from there).
    pub id: u32,
    /// Number of primitives in it, 1 to [`MAX_LEAF`].
    pub count: u32,
}

/// A BVH over primitives given by their bounds. It stores primitive indices only; the caller
/// intersects a leaf's primitives through a closure, so the same tree serves every kind of
/// shape (and packets of triangles, stored by the caller per leaf).
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Each leaf's range in `indices`: (first, count).
    leaves: Vec<[u32; 2]>,
    /// Bounds of everything.
    bounds: Bounds3,
    /// The root reference: a node whenever the tree holds a primitive (one leaf alone gets a
    /// node above it, whose box test turns away the rays that miss it).
    root: u32,
    /// Number of primitives in the tree.
    len: usize,
    /// Primitive indices in leaf order.
    pub indices: Vec<u32>,
}
impl Bvh {
    /// Number of nodes of the tree (wide nodes; leaves are stored in their parents' slots).
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes the tree occupies (nodes, leaf table and primitive indices).
    pub fn memory_bytes(&self) -> usize {
        std::mem::size_of::<Bvh>()
            + self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.leaves.capacity() * 8
            + self.indices.capacity() * 4
    }

    /// Frees the leaf table and the index array, for callers that keep their own data per
    /// leaf (packets): afterwards only the leaf-level queries ([`Bvh::traverse`],
    /// [`Bvh::intersect_any_leaves`]) may be used.
    pub fn drop_leaf_table(&mut self) {
        self.leaves = Vec::new();
        self.indices = Vec::new();
    }

    /// Renumbers the leaves by their ranges: each [`Leaf::id`] becomes the position of the
    /// leaf's first primitive in [`Bvh::indices`], so that a traversal hands over a leaf's
    /// range without a look-up in a table (a dependent load, a cache miss per leaf on large
    /// meshes). Frees the leaf table, which no longer applies; `indices` stays.
    pub fn number_leaves_by_slot(&mut self) {
        for node in &mut self.nodes {
            for k in 0..WIDTH {
                if node.child[k] != EMPTY && node.child[k] & LEAF != 0 {
                    node.leaf_id[k] = self.leaves[node.leaf_id[k] as usize][0];
                }
            }
        }
        self.leaves = Vec::new();
    }

    /// Bounds of everything in the tree.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Number of leaves; leaf ids run from 0 to this.
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// Positions in [`Bvh::indices`] of the primitives of the leaf numbered `id` among the
    /// leaves (not after [`Bvh::number_leaves_by_slot`]).
    #[inline(always)]
    pub fn leaf_range(&self, id: u32) -> std::ops::Range<usize> {
        let [first, count] = self.leaves[id as usize];
        first as usize..(first + count) as usize
    }

    /// Asks the memory system for a child the traversal will visit soon: a node's lines, or
    /// through `leaf_data` what a leaf's test will read.
    #[inline(always)]
    fn prefetch(&self, c: u32, id: u32, leaf_data: &impl Fn(Leaf)) {
        if c & LEAF == 0 {
            let p = self.nodes.as_ptr().wrapping_add(c as usize) as *const u8;
            for line in 0..std::mem::size_of::<Node>() / 64 {
                super::prefetch(p.wrapping_add(64 * line));
            }
        } else {
            leaf_data(Leaf {
                id,
                count: c & !LEAF,
            });
        }
    }

    /// Visits the leaves whose boxes the ray crosses, nearest first, the ray ending at
    /// `t_max` (its own end is not read). `leaf(leaf, t_max)` tests a leaf's primitives against
    /// the ray ending at `t_max` and returns the new end if it found a closer hit; farther
    /// subtrees are then culled (a returned −∞ ends the traversal at once: the any-hit query).
    /// `ray` itself is never copied, so a ray its caller has just written field by field is
    /// read once, by the slab set-up. Returns true if some leaf reported a hit.
    #[inline(always)]
    pub fn traverse<F: FnMut(Leaf, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        t_max: f32,
        leaf: F,
    ) -> bool {
        self.traverse_prefetching(ray, t_max, |_| {}, leaf)
    }

    /// [`Bvh::traverse`], calling `leaf_data(leaf)` for each leaf it puts aside for later (a
    /// farther crossed child), so that its owner may prefetch what the leaf's test will read.
    #[inline(always)]
    pub fn traverse_prefetching<F: FnMut(Leaf, f32) -> Option<f32>>(
        &self,
        ray: &Ray,
        t_max: f32,
        leaf_data: impl Fn(Leaf),
        mut leaf: F,
    ) -> bool {
        if self.len == 0 {
            return false;
        }
        let slabs = Slabs::new(ray);
        let mut t_max = t_max;
        // (child, leaf id, entry distance). Left uninitialised: zeroing it (3 KiB then, 5
        // now) cost 5 % of a path tracer's time per ray.
        let mut stack = [std::mem::MaybeUninit::<(u32, u32, f32)>::uninit(); STACK];
        let mut sp = 0usize;
        let (mut cur, mut cur_id) = (self.root, 0u32);
        let mut found = false;
        loop {
            if cur & LEAF == 0 {
                let node = &self.nodes[cur as usize];
                let (t_near, all) = slabs.test(node, t_max);
                let mut mask = all;
                if mask != 0 {
                    let k0 = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    if mask == 0 {
                        (cur, cur_id) = (node.child[k0], node.leaf_id[k0]);
                        continue;
                    }
                    let k1 = mask.trailing_zeros() as usize;
                    if mask & (mask - 1) == 0 {
                        // Two crossed children (k0 < k1): the nearer first, and on equal
                        // entry distances the later one, as the general order below.
                        let (near, far) = if t_near[k1] <= t_near[k0] {
                            (k1, k0)
                        } else {
                            (k0, k1)
                        };
                        self.prefetch(node.child[far], node.leaf_id[far], &leaf_data);
                        stack[sp].write((node.child[far], node.leaf_id[far], t_near[far]));
                        sp += 1;
                        (cur, cur_id) = (node.child[near], node.leaf_id[near]);
                        continue;
                    }
                    // Order the crossed children by entry distance: push the farther ones
                    // (farthest first), descend into the nearest. Among equal distances the
                    // later child goes nearer the top, so it is visited first.
                    let mut mask = all;
                    let mut hits = [(0.0f32, 0usize); WIDTH];
                    let mut n = 0;
                    while mask != 0 {
                        let k = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let mut j = n;
                        while j > 0 && hits[j - 1].0 < t_near[k] {
                            hits[j] = hits[j - 1];
                            j -= 1;
                        }
                        hits[j] = (t_near[k], k);
                        n += 1;
                    }
                    for &(t, k) in &hits[..n - 1] {
                        self.prefetch(node.child[k], node.leaf_id[k], &leaf_data);
                        stack[sp].write((node.child[k], node.leaf_id[k], t));
                        sp += 1;
                    }
                    let k = hits[n - 1].1;
                    (cur, cur_id) = (node.child[k], node.leaf_id[k]);
                    continue;
                }
            } else if let Some(t) = leaf(
                Leaf {
                    id: cur_id,
                    count: cur & !LEAF,
                },
                t_max,
            ) {
                // −∞ is the any-hit query's "stop": nothing can be nearer.
                if t == f32::NEG_INFINITY {
                    return true;
                }
                t_max = t;
                found = true;
            }
            // Pop the next subtree that may still hold a closer hit.
            loop {
                if sp == 0 {
                    return found;
                }
                sp -= 1;
                // SAFETY: every entry below the stack pointer was written by a push.
                let (c, id, t) = unsafe { stack[sp].assume_init() };
                // Entered before t_max, as in the slab test.
                if t < t_max {
                    (cur, cur_id) = (c, id);
                    break;
                }
            }
        }
    }

    /// True as soon as `leaf(leaf, ray)` reports a hit in a leaf the ray crosses (shadow
    /// rays). Children are still visited nearest first: an occluder, when there is one, tends
    /// to be found after fewer leaves.
    #[inline]
    pub fn intersect_any_leaves<F: FnMut(Leaf, &Ray) -> bool>(&self, ray: &Ray, leaf: F) -> bool {
        self.intersect_any_leaves_prefetching(ray, |_| {}, leaf)
    }

    /// [`Bvh::intersect_any_leaves`], calling `leaf_data` on the leaves it puts aside as
    /// [`Bvh::traverse_prefetching`] does.
    #[inline]
    pub fn intersect_any_leaves_prefetching<F: FnMut(Leaf, &Ray) -> bool>(
        &self,
        ray: &Ray,
        leaf_data: impl Fn(Leaf),
        mut leaf: F,
    ) -> bool {
        // The first hit ends the search (−∞: nothing can be nearer), so the ray is never
        // shortened: no copy of it.
        self.traverse_prefetching(ray, ray.t_max, leaf_data, |reached, _| {
            leaf(reached, ray).then_some(f32::NEG_INFINITY)
        })
    }

    /// Visits the primitives whose leaves the ray crosses, nearest leaf first. `hit(i, ray)`
    /// tests primitive `i` and returns the new `t_max` if it found a closer hit.
    #[inline]
    pub fn intersect<F: FnMut(u32, &Ray) -> Option<f32>>(&self, ray: &Ray, mut hit: F) -> bool {
        self.traverse(ray, ray.t_max, |leaf, t_max| {
            self.leaf_nearest(leaf, ray, t_max, &mut hit)
        })
    }

    /// True as soon as `hit(i, ray)` reports a hit (shadow rays).
    #[inline]
    pub fn intersect_any<F: FnMut(u32, &Ray) -> bool>(&self, ray: &Ray, mut hit: F) -> bool {
        self.intersect_any_leaves(ray, |leaf, r| self.leaf_any(leaf, r, &mut hit))
    }

    /// Tests leaf `leaf`'s primitives one after another, each against `ray` ending at `t_max`
    /// and then shortened to the nearest hit so far: the new end if one was hit. (Through the
    /// leaf table: not after [`Bvh::number_leaves_by_slot`].)
    #[inline(always)]
    pub fn leaf_nearest<F: FnMut(u32, &Ray) -> Option<f32>>(
        &self,
        leaf: Leaf,
        ray: &Ray,
        t_max: f32,
        hit: &mut F,
    ) -> Option<f32> {
        let mut r = Ray { t_max, ..*ray };
        let mut found = None;
        for k in self.leaf_range(leaf.id) {
            if let Some(t) = hit(self.indices[k], &r) {
                r.t_max = t;
                found = Some(t);
            }
        }
        found
    }

    /// True if any of leaf `leaf`'s primitives is hit.
    #[inline(always)]
    pub fn leaf_any<F: FnMut(u32, &Ray) -> bool>(
        &self,
        leaf: Leaf,
        ray: &Ray,
        hit: &mut F,
    ) -> bool {
        self.leaf_range(leaf.id).any(|k| hit(self.indices[k], ray))
    }
}

impl Bvh {
    /// Visits the leaves whose boxes the rays of `rp` cross, each leaf once with the lanes
    /// whose ray crosses it before its end `hits.t` (lane k's). `leaf(id, lanes, hits)` tests
    /// the leaf's primitives against those rays and may shorten their ends (nearest hits; −∞
    /// ends a lane's search, the any-hit query's "stop"); a lane's farther boxes are then
    /// culled for it. Each lane's box tests are the single ray's
    /// ([`Slabs::test`]'s operations on its own values), so a ray is culled where it would be
    /// alone. The children are visited in the order of their centres along the packet's
    /// direction ([`RayPacket::order`]), nearest first: so which leaves a lane tests, and in
    /// what order, depends on its own ray and that direction alone, never on the other lanes
    /// (of two hits at exactly the same t, the one kept does not depend on the packet either).
    #[inline(always)]
    pub fn traverse_packet<F: FnMut(Leaf, u32, &mut PacketHits)>(
        &self,
        rp: &RayPacket,
        hits: &mut PacketHits,
        mut leaf: F,
    ) {
        if self.len == 0 {
            return;
        }
        let grow = F8::splat(1.0 + 2.0 * gamma(3));
        // Child `k` of `node` against the rays of `lanes` ending at `t_end` (one float below
        // their ends): the lanes that cross it, the single ray's test in each lane.
        let crossing = |node: &Node, k: usize, lanes: u32, t_end: F8| {
            let mut t0 = F8::splat(0.0);
            let mut t1 = t_end;
            for a in 0..3 {
                let (lo, hi) = (F8::splat(node.min[a][k]), F8::splat(node.max[a][k]));
                let near = F8::select(rp.neg[a], hi, lo);
                let far = F8::select(rp.neg[a], lo, hi);
                let tn = near.sub(rp.o[a]).mul(rp.inv_d[a]);
                let tf = far.sub(rp.o[a]).mul(rp.inv_d[a]).mul(grow);
                t0 = tn.max(t0);
                t1 = tf.min(t1);
            }
            t0.le_bits(t1) & lanes
        };
        // Pushed subtrees as (child, parent node, slot << 8 | lanes): a popped one is tested
        // again against the lanes' ends as they are then, which culls exactly the lanes whose
        // entry distance is no longer before their end (the single ray's pop). Twelve bytes an
        // entry, left uninitialised as the single ray's stack.
        let mut stack = [std::mem::MaybeUninit::<(u32, u32, u32)>::uninit(); STACK];
        let mut sp = 0usize;
        // (child, its leaf id, lanes).
        let mut cur = (self.root, 0u32, rp.active);
        // Each lane's end, one float below t_max, as the single-ray test takes it.
        let mut t_end = hits.t.map(next_float_down);
        loop {
            let (node_ref, id, lanes) = cur;
            if node_ref & LEAF == 0 {
                let node = &self.nodes[node_ref as usize];
                let mut order = [(0.0f32, 0u32, 0u32); WIDTH];
                let mut n = 0;
                for k in 0..WIDTH {
                    if node.child[k] == EMPTY {
                        continue;
                    }
                    let crossed = crossing(node, k, lanes, t_end);
                    if crossed == 0 {
                        continue;
                    }
                    // Ordered by the box's centre along the packet's direction (twice it).
                    let key = (0..3)
                        .map(|a| (node.min[a][k] + node.max[a][k]) * rp.order[a])
                        .sum::<f32>();
                    let mut j = n;
                    while j > 0 && order[j - 1].0 < key {
                        order[j] = order[j - 1];
                        j -= 1;
                    }
                    order[j] = (key, k as u32, crossed);
                    n += 1;
                }
                if n > 0 {
                    for &(_, k, m) in &order[..n - 1] {
                        stack[sp].write((node.child[k as usize], node_ref, k << 8 | m));
                        sp += 1;
                    }
                    let (_, k, m) = order[n - 1];
                    cur = (node.child[k as usize], node.leaf_id[k as usize], m);
                    continue;
                }
            } else {
                let count = node_ref & !LEAF;
                leaf(Leaf { id, count }, lanes, hits);
                t_end = hits.t.map(next_float_down);
            }
            // Pop the next subtree some lane may still find a closer hit in.
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                // SAFETY: every entry below the stack pointer was written by a push.
                let (c, parent, slot_lanes) = unsafe { stack[sp].assume_init() };
                let (parent, slot) = (&self.nodes[parent as usize], (slot_lanes >> 8) as usize);
                let m = crossing(parent, slot, slot_lanes & 0xff, t_end);
                if m != 0 {
                    cur = (c, parent.leaf_id[slot], m);
                    break;
                }
            }
        }
    }
}

/// A ray prepared for slab tests: its origin, 1/d, and for each axis whether d is negative
/// (then the box's near side on that axis is its max).
struct Slabs {
    o: [F8; 3],
    inv_d: [F8; 3],
    neg: [bool; 3],
}

impl Slabs {
    #[inline(always)]
    fn new(ray: &Ray) -> Slabs {
        let inv: Vec3 = ray.d.recip();
        Slabs {
            o: [F8::splat(ray.o.x), F8::splat(ray.o.y), F8::splat(ray.o.z)],
            inv_d: [F8::splat(inv.x), F8::splat(inv.y), F8::splat(inv.z)],
            neg: [inv.x < 0.0, inv.y < 0.0, inv.z < 0.0],
        }
    }

    /// The slab test against a node's eight boxes at once: per axis t = (b − o)·(1/d);
    /// t_near = max(0, entry distances), t_far = min(t_max⁻, exit distances·(1 + 2γ₃)) (the
    /// enlargement keeps rounding from culling a box the ray crosses; t_max⁻ is the float
    /// below t_max); a box is crossed when t_near ≤ t_far. So a box entered at t_max or later
    /// is culled, as pbrt-v4's `Bounds3::IntersectP` (`tMin < raytMax`) does: of two coplanar
    /// surfaces at the same t, the one in a box the ray enters only at that t is not tested. Returns the entry distances and the mask of crossed boxes (bit k for
    /// child k). NaNs (0·∞ when the origin lies on a slab plane) leave the bound unchanged.
    #[inline(always)]
    fn test(&self, node: &Node, t_max: f32) -> ([f32; WIDTH], u32) {
        let mut t0 = F8::splat(0.0);
        let mut t1 = F8::splat(next_float_down(t_max));
        let grow = F8::splat(1.0 + 2.0 * gamma(3));
        for a in 0..3 {
            let (near, far) = if self.neg[a] {
                (&node.max[a], &node.min[a])
            } else {
                (&node.min[a], &node.max[a])
            };
            let tn = F8::load(near).sub(self.o[a]).mul(self.inv_d[a]);
            let tf = F8::load(far).sub(self.o[a]).mul(self.inv_d[a]).mul(grow);
            t0 = tn.max(t0);
            t1 = tf.min(t1);
        }
        (t0.to_array(), t0.le_bits(t1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::normalize;
    use crate::sampling::{hash_u64, u32_to_unit_f32};

    fn rnd(i: u64) -> f32 {
        u32_to_unit_f32(hash_u64(&[i]) as u32)
    }

    #[test]
    fn a_tree_of_one_leaf_turns_away_rays_that_miss_its_box() {
        for n in 1..=MAX_LEAF as u64 {
            let boxes: Vec<Bounds3> = (0..n)
                .map(|i| {
                    let c = Vec3::new(i as f32, 0.0, 0.0);
                    Bounds3::new(c, c + Vec3::splat(0.5))
                })
                .collect();
            let bvh = Bvh::build(&boxes);
            assert_eq!(bvh.node_count(), 1, "one node above the leaf");
            let mut visits = 0;
            let far = Ray::new(Vec3::new(0.25, 10.0, 0.25), Vec3::new(0.0, 0.0, 1.0));
            bvh.intersect_any(&far, |_, _| {
                visits += 1;
                false
            });
            assert_eq!(visits, 0, "{n} boxes: a ray passing above them");
            let through = Ray::new(Vec3::new(0.25, 0.25, -5.0), Vec3::new(0.0, 0.0, 1.0));
            bvh.intersect_any(&through, |_, _| {
                visits += 1;
                false
            });
            assert_eq!(
                visits, n,
                "{n} boxes: a ray through the first one reaches the leaf"
            );
        }
    }

    #[test]
    fn bvh_finds_the_same_nearest_box_as_brute_force() {
        for n in [0usize, 1, 3, 4, 5, 17, 500, 20_000] {
            let boxes: Vec<Bounds3> = (0..n as u64)
                .map(|i| {
                    let c = Vec3::new(rnd(3 * i), rnd(3 * i + 1), rnd(3 * i + 2)) * 10.0;
                    Bounds3::new(c, c + Vec3::splat(0.3))
                })
                .collect();
            let bvh = Bvh::build(&boxes);
            let mut seen = bvh.indices.clone();
            seen.sort_unstable();
            assert_eq!(
                seen,
                (0..n as u32).collect::<Vec<_>>(),
                "each primitive once"
            );
            for k in 0..300u64 {
                let o = Vec3::new(rnd(10_000 + k), rnd(20_000 + k), rnd(30_000 + k)) * 12.0 - 1.0;
                let d = normalize(Vec3::new(
                    rnd(40_000 + k) - 0.5,
                    rnd(50_000 + k) - 0.5,
                    rnd(60_000 + k) - 0.5,
                ));
                let ray = Ray::new(o, d);
                let brute = boxes
                    .iter()
                    .enumerate()
                    .filter_map(|(i, b)| b.intersect_p(&ray).map(|(t0, _)| (t0, i as u32)))
                    .min_by(|a, b| a.0.total_cmp(&b.0));
                let mut best: Option<(f32, u32)> = None;
                bvh.intersect(&ray, |i, r| {
                    let (t0, _) = boxes[i as usize].intersect_p(r)?;
                    if t0 >= r.t_max {
                        return None;
                    }
                    best = Some((t0, i));
                    Some(t0)
                });
                assert_eq!(best.map(|b| b.0), brute.map(|b| b.0), "n {n} ray {k}");
                assert_eq!(
                    bvh.intersect_any(&ray, |i, r| boxes[i as usize].intersect_p(r).is_some()),
                    brute.is_some()
                );
            }
        }
    }
}
