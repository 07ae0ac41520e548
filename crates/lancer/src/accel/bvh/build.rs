//! Building the BVH: binned SAH over primitive references, up to eight children per node
//! opened by greedy binary splits, large subtrees in parallel (rayon).

use super::{Bvh, EMPTY, LEAF, MAX_LEAF, MAX_SAH_DEPTH, Node, WIDTH};
use crate::math::{Bounds3, Vec3, Vec4};
use rayon::prelude::*;

/// Bins of the SAH split search, per axis.
const BINS: usize = 32;
/// Below this many primitives a subtree is built on the calling thread.
const PARALLEL_MIN: usize = 16 * 1024;
/// Two leaves replace one only when their boxes' areas sum to at most 75 % of the one's: the
/// rooms and walls this is for save a third, while splitting a mesh's compact leaves would
/// only add half-empty packets (memory) for a few percent.
const LEAF_SPLIT_MIN_GAIN: f32 = 0.25;

/// A primitive reference during the build: its box, with its index in `lo.w`'s bits.
#[derive(Clone, Copy, Debug)]
struct PrimRef {
    lo: Vec4,
    hi: Vec4,
}

impl PrimRef {
    /// Twice the centroid (min + max), enough for binning.
    #[inline(always)]
    fn c2(&self) -> Vec4 {
        self.lo + self.hi
    }
    #[inline(always)]
    fn index(&self) -> u32 {
        self.lo.w.to_bits()
    }
}

/// Box of a build range as two `Vec4` (w unused).
#[derive(Clone, Copy, Debug)]
struct Box4 {
    lo: Vec4,
    hi: Vec4,
}

impl Box4 {
    const EMPTY: Box4 = Box4 {
        lo: Vec4::splat(f32::INFINITY),
        hi: Vec4::splat(f32::NEG_INFINITY),
    };
    #[inline(always)]
    fn grow(&mut self, r: &PrimRef) {
        self.lo = self.lo.min(r.lo);
        self.hi = self.hi.max(r.hi);
    }
    #[inline(always)]
    fn union(&self, o: &Box4) -> Box4 {
        Box4 {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
        }
    }
    /// Half the surface area, dx·dy + dy·dz + dz·dx (0 for an empty box).
    #[inline(always)]
    fn half_area(&self) -> f32 {
        let d = (self.hi - self.lo).max(Vec4::ZERO);
        d.x * d.y + d.y * d.z + d.z * d.x
    }
    fn bounds3(&self) -> Bounds3 {
        Bounds3 {
            min: Vec3::from_vec4(self.lo),
            max: Vec3::from_vec4(self.hi),
        }
    }
}

fn fold_box(refs: &[PrimRef]) -> Box4 {
    if refs.len() > 64 * 1024 {
        return refs
            .par_chunks(16 * 1024)
            .map(fold_box)
            .reduce(|| Box4::EMPTY, |a, b| a.union(&b));
    }
    let mut b = Box4::EMPTY;
    for r in refs {
        b.grow(r);
    }
    b
}

/// Bounds of the centroids (doubled) of a range.
fn fold_centroids(refs: &[PrimRef]) -> Box4 {
    if refs.len() > 64 * 1024 {
        return refs
            .par_chunks(16 * 1024)
            .map(fold_centroids)
            .reduce(|| Box4::EMPTY, |a, b| a.union(&b));
    }
    let (mut lo, mut hi) = (Vec4::splat(f32::INFINITY), Vec4::splat(f32::NEG_INFINITY));
    for r in refs {
        let c = r.c2();
        lo = lo.min(c);
        hi = hi.max(c);
    }
    Box4 { lo, hi }
}

/// Per-axis bins: counts and boxes.
#[derive(Clone, Copy)]
struct Bins {
    count: [[u32; BINS]; 3],
    bounds: [[Box4; BINS]; 3],
}

impl Bins {
    fn new() -> Bins {
        Bins {
            count: [[0; BINS]; 3],
            bounds: [[Box4::EMPTY; BINS]; 3],
        }
    }
    fn merge(mut self, o: &Bins) -> Bins {
        for a in 0..3 {
            for b in 0..BINS {
                self.count[a][b] += o.count[a][b];
                self.bounds[a][b] = self.bounds[a][b].union(&o.bounds[a][b]);
            }
        }
        self
    }
}

/// Maps doubled centroids to bins: bin = ⌊(c − lo)·scale⌋ clamped to [0, BINS − 1].
#[derive(Clone, Copy)]
struct Binner {
    lo: Vec4,
    scale: Vec4,
}

impl Binner {
    #[inline(always)]
    fn bins(&self, c: Vec4) -> [usize; 3] {
        let b = ((c - self.lo) * self.scale)
            .max(Vec4::ZERO)
            .min(Vec4::splat((BINS - 1) as f32));
        // In [0, BINS − 1]: the signed conversion is one instruction, the unsigned one several.
        [
            b.x as i32 as usize,
            b.y as i32 as usize,
            b.z as i32 as usize,
        ]
    }
    // The axis indexes several parallel arrays at once.
    #[allow(clippy::needless_range_loop)]
    fn fill(&self, refs: &[PrimRef]) -> Bins {
        if refs.len() > 64 * 1024 {
            return refs
                .par_chunks(16 * 1024)
                .map(|c| self.fill(c))
                .reduce(Bins::new, |a, b| a.merge(&b));
        }
        let mut bins = Bins::new();
        if refs.len() < 1024 {
            self.add(&mut bins, refs);
            return bins;
        }
        // Two sets of bins, for the even and the odd references: neighbours in a mesh often
        // fall in the same bin, and one set made each update wait for the previous one's
        // store. Merging is exact (counts, minima, maxima), so the result is the same. (A
        // small range would spend more on clearing and merging the second set.)
        let mut odd = Bins::new();
        let mut pairs = refs.chunks_exact(2);
        for pair in &mut pairs {
            self.add_one(&mut bins, &pair[0]);
            self.add_one(&mut odd, &pair[1]);
        }
        self.add(&mut bins, pairs.remainder());
        bins.merge(&odd)
    }

    /// Adds `refs` to `bins`, one after another.
    #[inline(always)]
    fn add(&self, bins: &mut Bins, refs: &[PrimRef]) {
        for r in refs {
            self.add_one(bins, r);
        }
    }

    /// Adds `r` to its bin on each axis.
    // The axis indexes several parallel arrays at once.
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    fn add_one(&self, bins: &mut Bins, r: &PrimRef) {
        let b = self.bins(r.c2());
        for a in 0..3 {
            bins.count[a][b[a]] += 1;
            bins.bounds[a][b[a]].grow(r);
        }
    }
}

/// A range of the reference array with its box, while a node's children are being opened.
#[derive(Clone, Copy)]
struct Range {
    start: usize,
    end: usize,
    bounds: Box4,
}

/// Splits `refs` in two (both non-empty, `refs.len()` ≥ 2): returns the size of the first
/// part and both parts' boxes.
// Axis and bin index several parallel arrays at once.
#[allow(clippy::needless_range_loop)]
fn split(refs: &mut [PrimRef], depth: u32) -> (usize, Box4, Box4) {
    let n = refs.len();
    let cb = fold_centroids(refs);
    let ext = cb.hi - cb.lo;
    let axis = if ext.x >= ext.y && ext.x >= ext.z {
        0
    } else if ext.y >= ext.z {
        1
    } else {
        2
    };
    if depth < MAX_SAH_DEPTH && ext[axis] > 0.0 {
        // Binned SAH: cost(split) = A_left·⌈N_left/4⌉ + A_right·⌈N_right/4⌉ (leaves are
        // tested four primitives at a time); the least over the BINS − 1 planes of each axis
        // wins.
        let scale = Vec4::from_array([0, 1, 2, 3].map(|a| {
            if a < 3 && ext[a] > 0.0 {
                BINS as f32 * (1.0 - 1e-6) / ext[a]
            } else {
                0.0
            }
        }));
        let binner = Binner { lo: cb.lo, scale };
        let bins = binner.fill(refs);
        let mut best = (f32::INFINITY, 0usize, 0usize);
        for a in 0..3 {
            if ext[a] <= 0.0 {
                continue;
            }
            // Only the occupied bins matter: the planes between two occupied bins all split
            // the same way at the same cost, and the first of them (just after the lower
            // bin) is the one the full sweep kept (it keeps the first least cost). A small
            // range occupies a few of the BINS bins.
            let mut used = [0u8; BINS];
            let mut m = 0;
            for (b, &c) in bins.count[a].iter().enumerate() {
                used[m] = b as u8;
                m += (c > 0) as usize;
            }
            let used = &used[..m];
            // Right-to-left sweep: right_cost[j] for the plane just after occupied bin j − 1
            // (everything from occupied bin j on lies right of it).
            let mut right_cost = [0.0f32; BINS];
            let (mut rb, mut rn) = (Box4::EMPTY, 0u32);
            for j in (1..m).rev() {
                let b = used[j] as usize;
                rb = rb.union(&bins.bounds[a][b]);
                rn += bins.count[a][b];
                right_cost[j] = rb.half_area() * rn.div_ceil(4) as f32;
            }
            let (mut lb, mut ln) = (Box4::EMPTY, 0u32);
            for j in 1..m {
                let b = used[j - 1] as usize;
                lb = lb.union(&bins.bounds[a][b]);
                ln += bins.count[a][b];
                let cost = lb.half_area() * ln.div_ceil(4) as f32 + right_cost[j];
                if cost < best.0 {
                    best = (cost, a, b + 1);
                }
            }
        }
        if best.0.is_finite() {
            let (_, a, plane) = best;
            // Partition: references in bins below the plane first.
            // Without a branch on the side (it mispredicted half the time): a reference that
            // stays is swapped with itself, so the references end in the same order.
            let (lo, scale, plane_f) = (binner.lo[a], binner.scale[a], plane as f32);
            let (mut i, mut j) = (0usize, n);
            while i < j {
                // Its bin, (c − lo)·scale floored and clamped to [0, BINS − 1], is below the
                // whole number `plane` exactly when (c − lo)·scale is (a NaN counts as bin 0).
                let x = (refs[i].c2()[a] - lo) * scale;
                let below = x < plane_f || x.is_nan();
                let k = if below { i } else { j - 1 };
                refs.swap(i, k);
                i += below as usize;
                j -= !below as usize;
            }
            let (mut lb, mut rb) = (Box4::EMPTY, Box4::EMPTY);
            for b in 0..BINS {
                if b < plane {
                    lb = lb.union(&bins.bounds[a][b]);
                } else {
                    rb = rb.union(&bins.bounds[a][b]);
                }
            }
            if i > 0 && i < n {
                return (i, lb, rb);
            }
        }
    }
    // Median split along the widest centroid axis (or anywhere, when the centroids coincide).
    let mid = n / 2;
    if ext[axis] > 0.0 {
        refs.select_nth_unstable_by(mid, |p, q| p.c2()[axis].total_cmp(&q.c2()[axis]));
    }
    let (l, r) = refs.split_at(mid);
    (mid, fold_box(l), fold_box(r))
}

/// A split planned for a child while a node is opened: `refs` are already ordered for it.
#[derive(Clone, Copy)]
struct Split {
    /// SAH cost saved: A·⌈n/4⌉ − (A_l·⌈n_l/4⌉ + A_r·⌈n_r/4⌉).
    gain: f32,
    mid: usize,
    lb: Box4,
    rb: Box4,
}

/// Plans the split of `refs` (box `bounds`): the SAH split above leaf size, the best of the
/// few orderings at leaf size, nothing for one primitive.
fn plan_split(refs: &mut [PrimRef], bounds: &Box4, depth: u32) -> Option<Split> {
    let n = refs.len();
    let packets = |m: usize| m.div_ceil(MAX_LEAF) as f32;
    let (mid, lb, rb) = if n > MAX_LEAF {
        split(refs, depth)
    } else {
        let (_, axis, mid) = leaf_split(refs, bounds)?;
        refs.sort_by(|p, q| p.c2()[axis].total_cmp(&q.c2()[axis]));
        (mid, fold_box(&refs[..mid]), fold_box(&refs[mid..]))
    };
    let gain = bounds.half_area() * packets(n)
        - (lb.half_area() * packets(mid) + rb.half_area() * packets(n - mid));
    Some(Split { gain, mid, lb, rb })
}

/// The best split of a leaf's few primitives into two leaves, if SAH prefers it: a leaf's
/// packet costs its box's area whatever it holds, so two leaves win when their areas sum to
/// less than the whole's, A_left + A_right < A (e.g. two walls of a room, whose common box
/// every ray inside the room would otherwise cross). Returns (area saved, axis, size of the
/// first part when sorted by centroid along the axis).
fn leaf_split(refs: &[PrimRef], bounds: &Box4) -> Option<(f32, usize, usize)> {
    let n = refs.len();
    if !(2..=MAX_LEAF).contains(&n) {
        return None;
    }
    let whole = bounds.half_area();
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        let mut sorted = [refs[0]; MAX_LEAF];
        sorted[..n].copy_from_slice(refs);
        sorted[..n].sort_by(|p, q| p.c2()[axis].total_cmp(&q.c2()[axis]));
        for mid in 1..n {
            let cost = fold_box(&sorted[..mid]).half_area() + fold_box(&sorted[mid..n]).half_area();
            let gain = whole - cost;
            if gain > LEAF_SPLIT_MIN_GAIN * whole && best.is_none_or(|b| gain > b.0) {
                best = Some((gain, axis, mid));
            }
        }
    }
    best
}

/// The nodes and leaves of a subtree, references relative to its own arrays.
#[derive(Default)]
struct Out {
    nodes: Vec<Node>,
    leaves: Vec<[u32; 2]>,
}

impl Out {
    /// Appends another subtree's arrays, returning its root reference relocated.
    fn append(&mut self, o: Out, root: u32) -> u32 {
        let (dn, dl) = (self.nodes.len() as u32, self.leaves.len() as u32);
        let reloc = |c: u32| {
            if c == EMPTY {
                c
            } else if c & LEAF != 0 {
                LEAF | ((c & !LEAF) + dl)
            } else {
                c + dn
            }
        };
        self.nodes.extend(o.nodes.into_iter().map(|mut n| {
            n.child = n.child.map(reloc);
            n
        }));
        self.leaves.extend(o.leaves);
        reloc(root)
    }
}

/// Builds the subtree over `refs` (which start at `first` in the final index array) and
/// returns its root reference.
fn build_rec(
    out: &mut Out,
    refs: &mut [PrimRef],
    first: usize,
    bounds: Box4,
    depth: u32,
    plan: Option<Split>,
) -> u32 {
    let n = refs.len();
    if n <= MAX_LEAF {
        out.leaves.push([first as u32, n as u32]);
        return LEAF | (out.leaves.len() as u32 - 1);
    }
    // Open up to WIDTH children, greedily: each step makes the split that saves the most SAH
    // cost, counting A·⌈n/4⌉ for n primitives in a box of area A (what they cost as packets).
    // Small leaves are split too while slots are free, when two thin boxes beat their common
    // one (two walls of a room, whose shared box every ray inside would otherwise cross).
    let mut kids: Vec<(Range, Option<Split>)> = Vec::with_capacity(WIDTH);
    let first_split = plan.or_else(|| plan_split(&mut refs[..], &bounds, depth));
    kids.push((
        Range {
            start: 0,
            end: n,
            bounds,
        },
        first_split,
    ));
    while kids.len() < WIDTH {
        let best = kids
            .iter()
            .enumerate()
            .filter_map(|(i, (k, sp))| {
                let sp = sp.as_ref()?;
                // A kid too big for a leaf must be split eventually: it always may be.
                (sp.gain > 0.0 || k.end - k.start > MAX_LEAF).then_some((i, sp.gain))
            })
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((i, _)) = best else { break };
        let (k, sp) = kids[i];
        let sp = sp.expect("planned");
        let (l, r) = refs[k.start..k.end].split_at_mut(sp.mid);
        let (ls, rs) = (
            // Planned as the next level's: a kid left with many primitives becomes a node.
            plan_split(l, &sp.lb, depth + 1),
            plan_split(r, &sp.rb, depth + 1),
        );
        kids[i] = (
            Range {
                start: k.start,
                end: k.start + sp.mid,
                bounds: sp.lb,
            },
            ls,
        );
        kids.push((
            Range {
                start: k.start + sp.mid,
                end: k.end,
                bounds: sp.rb,
            },
            rs,
        ));
    }
    kids.sort_by_key(|k| k.0.start);
    let index = out.nodes.len();
    out.nodes.push(Node::UNUSED);
    let mut refs_of_kids: Vec<&mut [PrimRef]> = Vec::with_capacity(WIDTH);
    let mut rest = refs;
    let mut at = 0;
    for (k, _) in &kids {
        let (a, b) = rest.split_at_mut(k.end - at);
        refs_of_kids.push(a);
        rest = b;
        at = k.end;
    }
    let children: Vec<u32> = if n >= PARALLEL_MIN {
        let subs: Vec<(Out, u32)> = refs_of_kids
            .into_par_iter()
            .zip(kids.par_iter())
            .map(|(r, k)| {
                let mut o = Out::default();
                let (k, plan) = *k;
                let root = build_rec(&mut o, r, first + k.start, k.bounds, depth + 1, plan);
                (o, root)
            })
            .collect();
        // Room for all of them at once: growing by doubling would hold up to twice the tree.
        out.nodes
            .reserve_exact(subs.iter().map(|(o, _)| o.nodes.len()).sum());
        out.leaves
            .reserve_exact(subs.iter().map(|(o, _)| o.leaves.len()).sum());
        subs.into_iter().map(|(o, r)| out.append(o, r)).collect()
    } else {
        refs_of_kids
            .into_iter()
            .zip(kids.iter())
            .map(|(r, &(k, plan))| build_rec(out, r, first + k.start, k.bounds, depth + 1, plan))
            .collect()
    };
    let node = &mut out.nodes[index];
    for (slot, ((k, _), c)) in kids.iter().zip(children).enumerate() {
        for a in 0..3 {
            node.min[a][slot] = k.bounds.lo[a];
            node.max[a][slot] = k.bounds.hi[a];
        }
        node.child[slot] = c;
    }
    index as u32
}
impl Bvh {
    /// Builds the tree over `bounds[i]` for every primitive `i` (binned SAH, in parallel on
    /// the current rayon pool).
    pub fn build(bounds: &[Bounds3]) -> Bvh {
        Bvh::build_with(bounds.len(), |i| bounds[i])
    }

    /// [`Bvh::build`] over `n` primitives whose bounds `bounds(i)` gives, without a list of
    /// them (the build's own references hold them).
    pub fn build_with(n: usize, bounds: impl Fn(usize) -> Bounds3 + Sync) -> Bvh {
        let mut refs: Vec<PrimRef> = (0..n)
            .into_par_iter()
            .map(|i| {
                let b = bounds(i);
                PrimRef {
                    lo: b.min.extend(f32::from_bits(i as u32)),
                    hi: b.max.extend(0.0),
                }
            })
            .collect();
        if refs.is_empty() {
            return Bvh::default();
        }
        let all = fold_box(&refs);
        let mut out = Out::default();
        let mut root = build_rec(&mut out, &mut refs, 0, all, 0, None);
        if root & LEAF != 0 {
            // A tree of one leaf still gets a node above it: its box test turns away the rays
            // that pass far from the few primitives, which the leaf would test one by one (a
            // scene's one disk light beside a large mesh cost 4 % of its render so).
            let mut node = Node::UNUSED;
            for a in 0..3 {
                node.min[a][0] = all.lo[a];
                node.max[a][0] = all.hi[a];
            }
            node.child[0] = root;
            out.nodes.push(node);
            root = out.nodes.len() as u32 - 1;
        }
        // Leaf references become `LEAF | count`, their numbers going to `leaf_id` (the build
        // numbered them in its references).
        let leaves = &out.leaves;
        out.nodes.par_iter_mut().for_each(|node| {
            for k in 0..WIDTH {
                let c = node.child[k];
                if c != EMPTY && c & LEAF != 0 {
                    node.leaf_id[k] = c & !LEAF;
                    node.child[k] = LEAF | leaves[(c & !LEAF) as usize][1];
                }
            }
        });
        let indices = refs.par_iter().map(PrimRef::index).collect();
        drop(refs);
        // The arrays grew by doubling: give back what they hold in reserve.
        out.nodes.shrink_to_fit();
        out.leaves.shrink_to_fit();
        Bvh {
            nodes: out.nodes,
            leaves: out.leaves,
            bounds: all.bounds3(),
            root,
            len: n,
            indices,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::Ray;

    #[test]
    fn a_room_gets_one_leaf_per_wall() {
        // Six walls of a 2³ room, two triangles' boxes each (the same box twice). Pairing two
        // walls in a leaf would give a box every ray inside the room crosses.
        let walls: Vec<Bounds3> = (0..6)
            .map(|w| {
                let (axis, side) = (w / 2, if w % 2 == 0 { -1.0 } else { 1.0 });
                let (mut lo, mut hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
                lo[axis] = side;
                hi[axis] = side;
                Bounds3::new(lo, hi)
            })
            .collect();
        let boxes: Vec<Bounds3> = walls.iter().flat_map(|b| [*b, *b]).collect();
        let bvh = Bvh::build(&boxes);
        for leaf in 0..bvh.leaf_count() as u32 {
            let wall = |k: usize| bvh.indices[k] / 2;
            let r = bvh.leaf_range(leaf);
            let w0 = wall(r.start);
            assert!(r.clone().all(|k| wall(k) == w0), "leaf {leaf} mixes walls");
        }
    }

    #[test]
    fn coincident_centroids_still_build_a_shallow_tree() {
        let boxes = vec![Bounds3::new(Vec3::ZERO, Vec3::ONE); 10_000];
        let bvh = Bvh::build(&boxes);
        assert_eq!(bvh.indices.len(), 10_000);
        assert!(bvh.leaf_count() >= 10_000 / MAX_LEAF);
        let ray = Ray::new(Vec3::new(0.5, 0.5, -1.0), Vec3::Z);
        let mut n = 0;
        bvh.intersect_any(&ray, |_, _| {
            n += 1;
            false
        });
        assert_eq!(n, 10_000, "every primitive visited once");
    }
}
