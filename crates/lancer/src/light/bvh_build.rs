//! Building pbrt-v4's light BVH (`BVHLightSampler::buildBVH`): the lights split recursively
//! at the bucket boundary of least [`cost`], into a binary tree whose nodes hold their two
//! children's bounds, and each light's bit trail (bit k = which child at depth k).
//! [`super::bvh::BvhLightSampler`] lays the tree out for its walks.

use super::bounds::LightBounds;
use super::compact::CompactLightBounds;
use crate::math::{Bounds3, Vec3};
use std::f32::consts::PI;

/// Marks a child that is a light (a leaf): the light's index with this bit set.
pub(super) const LEAF: u32 = 1 << 31;

/// An interior node of the binary tree: its two children's bounds, prepared for importance,
/// and where each child is (a node's index, or a light's index with [`LEAF`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct BinaryNode {
    /// Child 0's and child 1's bounds.
    pub bounds: [CompactLightBounds; 2],
    /// Child 0 and child 1.
    pub child: [u32; 2],
}

/// The tree over `lights` (at least two), its root first; writes each light's bit trail into
/// `trails` (indexed by the lights' indices).
pub(super) fn build_tree(lights: &mut [(u32, LightBounds)], trails: &mut [u64]) -> Vec<BinaryNode> {
    let mut nodes = Vec::with_capacity(lights.len().saturating_sub(1));
    build(lights, 0, 0, &mut nodes, trails);
    nodes
}

/// Builds the subtree over `lights` (at least one), whose path from the root is `trail`
/// (`depth` bits); returns the reference its parent keeps (a light's index with [`LEAF`], or
/// its node's index) and its bounds.
fn build(
    lights: &mut [(u32, LightBounds)],
    trail: u64,
    depth: u32,
    nodes: &mut Vec<BinaryNode>,
    trails: &mut [u64],
) -> (u32, LightBounds) {
    if let [(i, b)] = *lights {
        trails[i as usize] = trail;
        return (i | LEAF, b);
    }
    let mid = split(lights, depth);
    let node = nodes.len();
    let placeholder = lights[0].1.compact();
    nodes.push(BinaryNode {
        bounds: [placeholder; 2],
        child: [0; 2],
    });
    let (left, right) = lights.split_at_mut(mid);
    let (r0, b0) = build(left, trail, depth + 1, nodes, trails);
    let (r1, b1) = build(right, trail | (1u64 << depth), depth + 1, nodes, trails);
    nodes[node] = BinaryNode {
        bounds: [b0.compact(), b1.compact()],
        child: [r0, r1],
    };
    (node as u32, b0.union(&b1))
}

/// Buckets per axis for the split search.
const BUCKETS: usize = 12;

/// The cost of a group of lights in a split (pbrt-v4's `EvaluateCost`): power × the solid
/// angle measure of its emission, M_Ω = 2π(1 − cos θ_o) + π/2·(2θ_w sin θ_o − cos(θ_o − 2θ_w)
/// − 2θ_o sin θ_o + cos θ_o) with θ_w = min(θ_o + θ_e, π), × its box's surface area, × how
/// elongated the parent box is along the split axis.
fn cost(b: &LightBounds, parent: &Bounds3, dim: usize) -> f32 {
    if b.phi == 0.0 {
        return 0.0;
    }
    let theta_o = b.normals.cos_theta.clamp(-1.0, 1.0).acos();
    let theta_e = b.cos_theta_e.clamp(-1.0, 1.0).acos();
    let theta_w = (theta_o + theta_e).min(PI);
    let sin_theta_o = theta_o.sin();
    let m_omega = 2.0 * PI * (1.0 - theta_o.cos())
        + PI / 2.0
            * (2.0 * theta_w * sin_theta_o
                - (theta_o - 2.0 * theta_w).cos()
                - 2.0 * theta_o * sin_theta_o
                + theta_o.cos());
    let d = parent.diagonal();
    let kr = if d[dim] > 0.0 {
        d.max_element() / d[dim]
    } else {
        1.0
    };
    b.phi * m_omega * kr * b.bounds.surface_area()
}

/// Where to split `lights` (more than one), at tree depth `depth`: the bucket boundary of
/// least [`cost`] over the three axes (pbrt-v4's `buildBVH`), the lights of the buckets
/// below it moved first; the middle when no boundary has a cost.
fn split(lights: &mut [(u32, LightBounds)], depth: u32) -> usize {
    let mut bounds = Bounds3::EMPTY;
    let mut centroids = Bounds3::EMPTY;
    for (_, b) in lights.iter() {
        bounds = bounds.union(&b.bounds);
        centroids = centroids.union_point(b.centroid());
    }
    // The cheapest of the bucket boundaries along the three axes.
    let mut best: Option<(f32, usize, usize)> = None;
    let bucket_of = |c: Vec3, dim: usize| -> usize {
        let t = (c[dim] - centroids.min[dim]) / (centroids.max[dim] - centroids.min[dim]);
        ((t * BUCKETS as f32) as usize).min(BUCKETS - 1)
    };
    // Past 48 levels only halving keeps the bit trail within 64 bits.
    for dim in 0..3 {
        if depth >= 48 || centroids.max[dim] == centroids.min[dim] {
            continue;
        }
        let mut buckets = [None::<LightBounds>; BUCKETS];
        for (_, b) in lights.iter() {
            let k = bucket_of(b.centroid(), dim);
            buckets[k] = Some(buckets[k].map_or(*b, |a| a.union(b)));
        }
        let add = |acc: Option<LightBounds>, b: &Option<LightBounds>| match (acc, b) {
            (Some(a), Some(b)) => Some(a.union(b)),
            (a, b) => a.or(*b),
        };
        // The buckets up to k united from the first on, as pbrt-v4 folds them: one running
        // union gives every k the same bits. Those after k are folded from k + 1 each time
        // (union is not associative in its last bits: a running union from the end would
        // differ).
        let mut below = buckets[0];
        for k in 1..BUCKETS - 1 {
            below = add(below, &buckets[k]);
            let above = buckets[k + 1..].iter().fold(None, add);
            let c = below.map_or(0.0, |b| cost(&b, &bounds, dim))
                + above.map_or(0.0, |b| cost(&b, &bounds, dim));
            if c > 0.0 && best.is_none_or(|(m, _, _)| c < m) {
                best = Some((c, dim, k));
            }
        }
    }
    let mut mid = match best {
        Some((_, dim, k)) => {
            // Partition: buckets ≤ k first.
            let mut m = 0;
            for j in 0..lights.len() {
                if bucket_of(lights[j].1.centroid(), dim) <= k {
                    lights.swap(j, m);
                    m += 1;
                }
            }
            m
        }
        None => lights.len() / 2,
    };
    if mid == 0 || mid == lights.len() {
        mid = lights.len() / 2;
    }
    mid
}
