//! pbrt-v4's `BVHLightSampler`: a bounding volume hierarchy over the lights that have bounds,
//! walked from the root by choosing each child in proportion to its [`LightBounds::importance`]
//! at the point being lit, so that lights near and facing the point get the shadow rays. The
//! lights without bounds (distant and infinite) are chosen apart, each with probability
//! 1/(n_∞ + 1), the BVH as a whole taking the remaining 1/(n_∞ + 1).
//!
//! The probability of a light is the product of the child probabilities on the way to its
//! leaf; each light's path is kept as a bit trail (bit k = which child at depth k) so that
//! [`BvhLightSampler::pmf`] retraces it for multiple importance sampling.

use super::bounds::{LightBounds, LightExtent};
use super::compact::{CompactLightBounds, CompactLightBounds4};
use super::sample::LightSampleContext;
use crate::math::{Bounds3, Vec3};
use std::f32::consts::PI;

/// The largest float below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// An interior node: its two children's bounds side by side (lanes 0 and 1; lanes 2 and 3
/// repeat child 1), so that one 4-wide evaluation gives both importances, and where each child
/// is: an interior node's index, or a light's index with [`LEAF`] set. Leaves are not nodes of
/// their own, so a walk ends on the choice of a leaf without visiting it.
#[derive(Clone, Copy, Debug)]
struct Node {
    children: CompactLightBounds4,
    child: [u32; 2],
}

/// Marks a child that is a light (a leaf).
const LEAF: u32 = 1 << 31;

/// Where a light is in the sampler.
const UNBOUNDED: u64 = u64::MAX;
/// A bounded light that emits nothing: never chosen.
const NEVER: u64 = u64::MAX - 1;

/// pbrt-v4's light BVH sampler.
#[derive(Clone, Debug, Default)]
pub struct BvhLightSampler {
    /// The interior nodes, the root first (none when at most one light has bounds).
    nodes: Vec<Node>,
    /// The one bounded light when there is exactly one: its index and bounds (pbrt-v4 checks
    /// a lone root leaf's importance before choosing it).
    lone: Option<(u32, CompactLightBounds)>,
    /// Lights without bounds (distant, infinite).
    infinite: Vec<u32>,
    /// Per light: its bit trail in the BVH, or [`UNBOUNDED`] / [`NEVER`].
    trails: Vec<u64>,
    /// Probability of choosing an unbounded light, n_∞/(n_∞ + 1) (or 1 without a BVH).
    p_inf: f32,
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

impl BvhLightSampler {
    /// The sampler over lights of these extents ([`super::Light::extent`]).
    pub fn new(lights: &[LightExtent]) -> BvhLightSampler {
        let mut s = BvhLightSampler {
            nodes: Vec::new(),
            lone: None,
            infinite: Vec::new(),
            p_inf: 0.0,
            trails: vec![NEVER; lights.len()],
        };
        let mut bounded = Vec::new();
        for (i, light) in lights.iter().enumerate() {
            match light {
                LightExtent::Bounded(b) => bounded.push((i as u32, *b)),
                LightExtent::Unbounded => {
                    s.infinite.push(i as u32);
                    s.trails[i] = UNBOUNDED;
                }
                LightExtent::Dark => {}
            }
        }
        let has_bvh = !bounded.is_empty();
        if let [(i, b)] = bounded[..] {
            s.lone = Some((i, b.compact()));
            s.trails[i as usize] = 0;
        } else if has_bvh {
            s.build(&mut bounded, 0, 0);
        }
        let n = s.infinite.len();
        s.p_inf = n as f32 / (n + usize::from(has_bvh)).max(1) as f32;
        s
    }

    /// Bytes of the tables (capacity included).
    pub fn memory_bytes(&self) -> usize {
        self.nodes.capacity() * std::mem::size_of::<Node>()
            + self.infinite.capacity() * 4
            + self.trails.capacity() * 8
    }

    /// Builds the subtree over `lights` (at least one), whose path from the root is `trail`
    /// (`depth` bits); returns the reference to it its parent keeps (a light's index with
    /// [`LEAF`], or the index of its node) and its bounds.
    fn build(
        &mut self,
        lights: &mut [(u32, LightBounds)],
        trail: u64,
        depth: u32,
    ) -> (u32, LightBounds) {
        if let [(i, b)] = *lights {
            self.trails[i as usize] = trail;
            return (i | LEAF, b);
        }
        let mid = split(lights, depth);
        let node = self.nodes.len();
        self.nodes.push(Node {
            children: CompactLightBounds4::new([lights[0].1.compact(); 4]),
            child: [0; 2],
        });
        let (left, right) = lights.split_at_mut(mid);
        let (r0, b0) = self.build(left, trail, depth + 1);
        let (r1, b1) = self.build(right, trail | (1u64 << depth), depth + 1);
        let (c0, c1) = (b0.compact(), b1.compact());
        self.nodes[node] = Node {
            children: CompactLightBounds4::new([c0, c1, c1, c1]),
            child: [r0, r1],
        };
        (node as u32, b0.union(&b1))
    }

    /// Chooses a light for the point `ctx` with the uniform number `u`: its index and
    /// probability, or `None` when no light can light the point.
    ///
    /// Walking down, child 0 is taken with probability p₀ = I₀/(I₀ + I₁) (the children's
    /// importances at the point) and `u` is rescaled to the part it fell in, so one number
    /// makes every choice; the light's probability is the product of the choices' (times the
    /// BVH's share 1 − p_∞).
    #[inline]
    pub fn sample(&self, ctx: &LightSampleContext, u: f32) -> Option<(usize, f32)> {
        let p_inf = self.p_inf;
        if u < p_inf {
            let n = self.infinite.len();
            let k = ((u / p_inf * n as f32) as usize).min(n - 1);
            return Some((self.infinite[k] as usize, p_inf / n as f32));
        }
        let (p, n) = (ctx.p, ctx.ns);
        let mut pmf = 1.0 - p_inf;
        let Some(root) = self.nodes.first() else {
            // One light: chosen wherever its importance is not zero.
            let (i, b) = self.lone.as_ref()?;
            return (b.importance(p, n) > 0.0).then_some((*i as usize, pmf));
        };
        let mut u = ((u - p_inf) / (1.0 - p_inf)).min(ONE_MINUS_EPSILON);
        let mut nd = root;
        loop {
            let imp = nd.children.importance(p, n);
            let (i0, i1) = (imp.x, imp.y);
            if i0 == 0.0 && i1 == 0.0 {
                return None;
            }
            let p0 = i0 / (i0 + i1);
            let child = if u < p0 {
                pmf *= p0;
                u = (u / p0).min(ONE_MINUS_EPSILON);
                nd.child[0]
            } else {
                pmf *= 1.0 - p0;
                u = ((u - p0) / (1.0 - p0)).min(ONE_MINUS_EPSILON);
                nd.child[1]
            };
            if child & LEAF != 0 {
                return Some(((child & !LEAF) as usize, pmf));
            }
            nd = &self.nodes[child as usize];
        }
    }

    /// Probability that [`BvhLightSampler::sample`] chooses light `light` at `ctx`: the
    /// product of the child probabilities along the light's bit trail.
    #[inline]
    pub fn pmf(&self, ctx: &LightSampleContext, light: usize) -> f32 {
        let Some(&trail) = self.trails.get(light) else {
            return 0.0;
        };
        match trail {
            UNBOUNDED => return self.p_inf / self.infinite.len() as f32,
            NEVER => return 0.0,
            _ => {}
        }
        let (p, n) = (ctx.p, ctx.ns);
        let pmf = 1.0 - self.p_inf;
        let Some(root) = self.nodes.first() else {
            return match &self.lone {
                Some((_, b)) if b.importance(p, n) > 0.0 => pmf,
                _ => 0.0,
            };
        };
        let (mut trail, mut pmf, mut nd) = (trail, pmf, root);
        loop {
            let imp = nd.children.importance(p, n);
            let (i0, i1) = (imp.x, imp.y);
            if i0 == 0.0 && i1 == 0.0 {
                return 0.0;
            }
            let p0 = i0 / (i0 + i1);
            let bit = (trail & 1) as usize;
            pmf *= if bit == 0 { p0 } else { 1.0 - p0 };
            let child = nd.child[bit];
            if child & LEAF != 0 {
                return pmf;
            }
            nd = &self.nodes[child as usize];
            trail >>= 1;
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::DirectionCone;

    /// A point light's extent: φ = 4π·I, emitting everywhere.
    fn point(x: f32, y: f32, z: f32, i: f32) -> LightExtent {
        if i == 0.0 {
            return LightExtent::Dark;
        }
        LightExtent::Bounded(LightBounds {
            bounds: Bounds3::from_point(Vec3::new(x, y, z)),
            phi: 4.0 * PI * i,
            normals: DirectionCone::ENTIRE_SPHERE,
            cos_theta_e: 0.0,
            two_sided: false,
        })
    }

    fn lights() -> Vec<LightExtent> {
        let mut v = Vec::new();
        let mut rng = crate::sampling::Pcg32::new(5, 1);
        for _ in 0..37 {
            let p = [rng.uniform(), rng.uniform(), rng.uniform()].map(|c| c * 6.0 - 3.0);
            v.push(point(p[0], p[1], p[2], 0.1 + 3.0 * rng.uniform()));
        }
        // A spot light pointing down, and a one-sided quad facing up above the point.
        v.push(LightExtent::Bounded(LightBounds {
            bounds: Bounds3::from_point(Vec3::new(0.0, 2.0, 0.0)),
            phi: 4.0 * PI * 5.0,
            normals: DirectionCone {
                w: -Vec3::Y,
                cos_theta: 0.9,
            },
            cos_theta_e: (0.9f32.acos() - 0.8f32.acos()).cos(),
            two_sided: false,
        }));
        v.push(LightExtent::Unbounded);
        v.push(point(0.0, 0.0, 0.0, 0.0));
        v.push(LightExtent::Bounded(LightBounds {
            bounds: Bounds3::new(Vec3::new(-1.0, 3.0, -1.0), Vec3::new(1.0, 3.0, 1.0)),
            phi: 10.0,
            normals: DirectionCone {
                w: Vec3::Y,
                cos_theta: 1.0,
            },
            cos_theta_e: 0.0,
            two_sided: false,
        }));
        v
    }

    fn ctx() -> LightSampleContext {
        LightSampleContext {
            p: Vec3::new(0.2, -0.1, 0.3),
            n: Vec3::Y,
            ns: Vec3::Y,
        }
    }

    #[test]
    fn pmf_sums_to_one_and_matches_sampling_frequencies() {
        let lights = lights();
        let s = BvhLightSampler::new(&lights);
        let c = ctx();
        let pmf: Vec<f64> = (0..lights.len()).map(|i| s.pmf(&c, i) as f64).collect();
        let total: f64 = pmf.iter().sum();
        assert!((total - 1.0).abs() < 1e-4, "{total}");
        // The infinite light gets 1/2; the black point light and the quad, which faces away
        // from the point, nothing.
        assert!((pmf[38] - 0.5).abs() < 1e-6 && pmf[39] == 0.0 && pmf[40] == 0.0);
        // 99.9th percentile of χ² with ~40 degrees of freedom is about 73.
        let (chi2, bins) = chi_square(&s, &c, &pmf);
        assert!(chi2 < 73.0, "chi2 {chi2} over {bins} bins");
    }

    /// χ² of 200 000 choices (u stratified and scrambled) against the PMF, and the number of
    /// bins it sums over (those expecting more than 5); also checks that each choice reports
    /// its light's PMF and that lights of PMF zero are never chosen.
    fn chi_square(s: &BvhLightSampler, c: &LightSampleContext, pmf: &[f64]) -> (f64, usize) {
        let n = 200_000;
        let mut counts = vec![0u32; pmf.len()];
        for k in 0..n {
            let u = (k as f32 + 0.5) / n as f32;
            let u = (u * 7919.0).fract();
            let (i, p) = s.sample(c, u).expect("a light");
            assert!((p as f64 - pmf[i]).abs() < 1e-5 * pmf[i].max(1e-3), "{i}");
            counts[i] += 1;
        }
        let mut chi2 = 0.0;
        let mut dof = 0;
        for (i, &o) in counts.iter().enumerate() {
            let e = pmf[i] * n as f64;
            if e > 5.0 {
                chi2 += (o as f64 - e).powi(2) / e;
                dof += 1;
            } else {
                assert!(e > 0.0 || o == 0);
            }
        }
        (chi2, dof)
    }

    /// A one-sided quad light of half-size `h` at height `y`, facing down, as the Cornell
    /// box's (an area light: θ_o = 0, θ_e = π/2).
    fn ceiling_quad(x: f32, y: f32, h: f32, phi: f32) -> LightExtent {
        LightExtent::Bounded(LightBounds {
            bounds: Bounds3::new(Vec3::new(x - h, y, -h), Vec3::new(x + h, y, h)),
            phi,
            normals: DirectionCone {
                w: -Vec3::Y,
                cos_theta: 1.0,
            },
            cos_theta_e: 0.0,
            two_sided: false,
        })
    }

    #[test]
    fn few_lights_sample_as_their_pmf_says() {
        // Two, three and four area lights (the sizes the light BVH meets in small scenes),
        // lit from points on the floor, on a wall, and in a medium (n = 0).
        let sets = [
            vec![
                ceiling_quad(0.0, 2.0, 0.3, 5.0),
                ceiling_quad(0.1, 2.0, 0.3, 5.0),
            ],
            vec![
                ceiling_quad(-1.0, 2.0, 0.2, 3.0),
                ceiling_quad(1.0, 1.5, 0.4, 8.0),
                point(0.0, 1.0, 0.5, 0.2),
            ],
            vec![
                ceiling_quad(-1.0, 2.0, 0.2, 3.0),
                ceiling_quad(1.0, 1.5, 0.4, 8.0),
                point(0.0, 1.0, 0.5, 0.2),
                point(0.5, 0.3, -0.5, 1.0),
            ],
        ];
        let points = [
            (Vec3::new(0.3, 0.0, 0.2), Vec3::Y),
            (Vec3::new(-1.5, 1.0, 0.0), Vec3::X),
            (Vec3::new(0.2, 1.0, 0.1), Vec3::ZERO),
        ];
        for lights in &sets {
            let s = BvhLightSampler::new(lights);
            for &(p, n) in &points {
                let c = LightSampleContext { p, n, ns: n };
                let pmf: Vec<f64> = (0..lights.len()).map(|i| s.pmf(&c, i) as f64).collect();
                let total: f64 = pmf.iter().sum();
                assert!((total - 1.0).abs() < 1e-5, "{total}");
                // Each lit light's PMF is its share of importance down the tree: never 0
                // here, where every light faces the point.
                assert!(pmf.iter().all(|&q| q > 0.0), "{pmf:?}");
                // 99.9th percentile of χ² with 1, 2, 3 degrees of freedom (bins − 1): 10.8,
                // 13.8, 16.3.
                let (chi2, bins) = chi_square(&s, &c, &pmf);
                assert_eq!(bins, lights.len());
                let bound = [10.8, 13.8, 16.3][bins - 2];
                assert!(chi2 < bound, "chi2 {chi2} over {bins} bins");
            }
        }
    }

    #[test]
    fn a_lone_light_is_chosen_wherever_it_can_light() {
        // One quad facing down at y = 2, then with a sky beside it (which takes half).
        for sky in [false, true] {
            let mut lights = vec![ceiling_quad(0.0, 2.0, 0.3, 5.0)];
            if sky {
                lights.push(LightExtent::Unbounded);
            }
            let s = BvhLightSampler::new(&lights);
            let share = if sky { 0.5 } else { 1.0 };
            let below = ctx();
            assert_eq!(s.pmf(&below, 0), share);
            assert_eq!(s.sample(&below, 0.99), Some((0, share)));
            // Above the quad, its back faces the point: never chosen.
            let above = LightSampleContext {
                p: Vec3::new(0.0, 3.0, 0.0),
                n: Vec3::Y,
                ns: Vec3::Y,
            };
            assert_eq!(s.pmf(&above, 0), 0.0);
            assert_eq!(s.sample(&above, 0.99), None);
            if sky {
                assert_eq!(s.sample(&above, 0.2), Some((1, 0.5)));
                assert_eq!(s.pmf(&above, 1), 0.5);
            }
        }
        // No light with bounds: nothing to choose.
        let s = BvhLightSampler::new(&[LightExtent::Dark]);
        assert_eq!(s.sample(&ctx(), 0.5), None);
        assert_eq!(s.pmf(&ctx(), 0), 0.0);
    }

    #[test]
    fn nearer_lights_are_chosen_more_often() {
        let lights = vec![point(0.0, 1.0, 0.0, 1.0), point(0.0, 10.0, 0.0, 1.0)];
        let s = BvhLightSampler::new(&lights);
        let c = LightSampleContext {
            p: Vec3::ZERO,
            n: Vec3::Y,
            ns: Vec3::Y,
        };
        // Importance φ/d²: 1 against 1/100.
        assert!((s.pmf(&c, 0) - 100.0 / 101.0).abs() < 1e-5);
        assert!((s.pmf(&c, 0) + s.pmf(&c, 1) - 1.0).abs() < 1e-6);
    }
}
