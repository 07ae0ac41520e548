//! pbrt-v4's `BVHLightSampler`: a bounding volume hierarchy over the lights that have bounds,
//! walked from the root by choosing each child in proportion to its [`super::LightBounds::importance`]
//! at the point being lit, so that lights near and facing the point get the shadow rays. The
//! lights without bounds (distant and infinite) are chosen apart, each with probability
//! 1/(n_∞ + 1), the BVH as a whole taking the remaining 1/(n_∞ + 1).
//!
//! The probability of a light is the product of the child probabilities on the way to its
//! leaf; each light's path is kept as a bit trail (bit k = which child at depth k) so that
//! [`BvhLightSampler::pmf`] retraces it for multiple importance sampling.
//!
//! The binary tree ([`super::bvh_build`]) is walked two levels at a time: a [`Quad`] holds a
//! node's two children and their four children, so that the importances of both levels are
//! evaluated side by side rather than one after the other, each level's choice waiting on the
//! previous one (the walk is a chain of square roots and divisions, bound by their latency).
//! Every importance and probability has the bits of the one-level walk.

use super::bounds::LightExtent;
use super::bvh_build::{BinaryNode, LEAF, build_tree};
use super::compact::{CompactLightBounds, CompactLightBounds4};
use super::sample::LightSampleContext;
use crate::sampling::ONE_MINUS_EPSILON;
use glam::{Vec4, Vec4Swizzles};

/// Two levels of the tree below a node: its children A and B (lanes 0 and 1 of `children`;
/// lanes 2 and 3 repeat B) and their children A₀, A₁, B₀, B₁ (lanes 0–3 of `grandchildren`),
/// each evaluated by one 4-wide [`CompactLightBounds4::importance`].
#[derive(Clone, Copy, Debug)]
struct Quad {
    children: CompactLightBounds4,
    grandchildren: CompactLightBounds4,
    /// A and B: a light's index with [`LEAF`], or anything else for an interior node (whose
    /// children are the grandchildren).
    child: [u32; 2],
    /// A₀, A₁, B₀, B₁ (those of a child that is a leaf unused): a light's index with
    /// [`LEAF`], or the index of the quad below that node.
    grandchild: [u32; 4],
    /// Some child is an interior node (otherwise `grandchildren` is not evaluated).
    deep: bool,
}

/// Where a light is in the sampler.
const UNBOUNDED: u64 = u64::MAX;
/// A bounded light that emits nothing: never chosen.
const NEVER: u64 = u64::MAX - 1;

/// pbrt-v4's light BVH sampler.
#[derive(Clone, Debug, Default)]
pub struct BvhLightSampler {
    /// The quads, the root's first (none when at most one light has bounds).
    quads: Vec<Quad>,
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

/// Child 0 with probability p₀ = i₀/(i₀ + i₁), else child 1, by `u`, which is rescaled to the
/// part it fell in (so that one number makes every choice); `pmf` is multiplied by the
/// choice's probability ([`child_pmf`]). `None` when neither child has importance.
///
/// The test u < p₀ is made as u·(i₀ + i₁) < i₀, with no division before it, and the child is
/// picked by selects rather than a branch: for a point lit by two lights alike (a quad's
/// two triangles) the choice is a coin toss, which a branch would mispredict half the time.
/// u′ = u·(i₀ + i₁)/i₀ for child 0, (u·(i₀ + i₁) − i₀)/i₁ for child 1: pbrt-v4's u/p₀ and
/// (u − p₀)/(1 − p₀) up to rounding. A chosen child's importance is never 0 (child 0 needs
/// i₀ > u·(i₀ + i₁) ≥ 0; child 1 is refused when i₁ = 0, where u·i₀ rounds to i₀ only for a
/// subnormal i₀), so the division is safe.
#[inline(always)]
fn choose(i0: f32, i1: f32, u: &mut f32, pmf: &mut f32) -> Option<usize> {
    let sum = i0 + i1;
    if i0 == 0.0 && i1 == 0.0 {
        return None;
    }
    let us = *u * sum;
    // The test and s = [second] as vector lanes (a compare mask and-ed with 1.0, no trip
    // through an integer register); i_c and the part below the chosen one as products with s,
    // exact for finite importances (a select of floats the compiler may turn into a branch).
    let m = Vec4::splat(us).cmpge(Vec4::splat(i0)) & Vec4::splat(i1).cmpgt(Vec4::ZERO);
    let second = m.bitmask() & 1 != 0;
    let s = Vec4::select(m, Vec4::ONE, Vec4::ZERO).x;
    let ic = i1 * s + i0 * (1.0 - s);
    let below = i0 * s;
    *pmf *= ic / sum;
    *u = ((us - below) / ic).min(ONE_MINUS_EPSILON);
    Some(usize::from(second))
}

/// The probability of child `bit` (0 or 1) at a node whose children have importances i₀, i₁,
/// i_bit/(i₀ + i₁) (as [`choose`] computes it, bit for bit); `None` when neither has any.
#[inline(always)]
fn child_pmf(i0: f32, i1: f32, bit: usize) -> Option<f32> {
    if i0 == 0.0 && i1 == 0.0 {
        return None;
    }
    Some(if bit == 0 { i0 } else { i1 } / (i0 + i1))
}

/// Lanes 2k and 2k + 1 of `v` (k is the previous level's choice, a coin toss as often as
/// not: a blend, not a branch).
#[inline(always)]
fn lane_pair(v: Vec4, k: usize) -> (f32, f32) {
    let v = Vec4::select(glam::BVec4A::splat(k != 0), v.zwzw(), v);
    (v.x, v.y)
}

/// Lays out the binary tree `nodes` (root first) as quads: the quad of node `node`, then
/// those below it; returns its index.
fn lay_out(nodes: &[BinaryNode], node: usize, quads: &mut Vec<Quad>) -> u32 {
    let nd = &nodes[node];
    let index = quads.len();
    let [a, b] = nd.bounds;
    quads.push(Quad {
        children: CompactLightBounds4::new([a, b, b, b]),
        grandchildren: CompactLightBounds4::new([a, b, b, b]),
        child: nd.child,
        grandchild: [0; 4],
        deep: false,
    });
    // A leaf child's lanes repeat the other child's (never used).
    let mut lanes = [a, a, b, b];
    let mut grandchild = [0; 4];
    for (k, &c) in nd.child.iter().enumerate() {
        if c & LEAF != 0 {
            continue;
        }
        let below = &nodes[c as usize];
        lanes[2 * k] = below.bounds[0];
        lanes[2 * k + 1] = below.bounds[1];
        for (g, &r) in below.child.iter().enumerate() {
            grandchild[2 * k + g] = if r & LEAF != 0 {
                r
            } else {
                lay_out(nodes, r as usize, quads)
            };
        }
    }
    let q = &mut quads[index];
    q.deep = nd.child.iter().any(|&c| c & LEAF == 0);
    q.grandchildren = CompactLightBounds4::new(lanes);
    q.grandchild = grandchild;
    index as u32
}

impl BvhLightSampler {
    /// The sampler over lights of these extents ([`super::Light::extent`]).
    pub fn new(lights: &[LightExtent]) -> BvhLightSampler {
        let mut s = BvhLightSampler {
            quads: Vec::new(),
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
            let nodes = build_tree(&mut bounded, &mut s.trails);
            lay_out(&nodes, 0, &mut s.quads);
        }
        let n = s.infinite.len();
        s.p_inf = n as f32 / (n + usize::from(has_bvh)).max(1) as f32;
        s
    }

    /// Bytes of the tables (capacity included).
    pub fn memory_bytes(&self) -> usize {
        self.quads.capacity() * std::mem::size_of::<Quad>()
            + self.infinite.capacity() * 4
            + self.trails.capacity() * 8
    }

    /// Chooses a light for the point `ctx` with the uniform number `u`: its index and
    /// probability, or `None` when no light can light the point.
    ///
    /// Walking down, child 0 is taken with probability p₀ = I₀/(I₀ + I₁) (the children's
    /// importances at the point; see [`choose`]); the light's probability is the product of
    /// the choices' (times the BVH's share 1 − p_∞).
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
        let Some(root) = self.quads.first() else {
            // One light: chosen wherever its importance is not zero.
            let (i, b) = self.lone.as_ref()?;
            return (b.importance(p, n) > 0.0).then_some((*i as usize, pmf));
        };
        let mut u = ((u - p_inf) / (1.0 - p_inf)).min(ONE_MINUS_EPSILON);
        let mut q = root;
        loop {
            // Both levels' importances first: neither waits on a choice.
            let imp = q.children.importance(p, n);
            let grand = if q.deep {
                q.grandchildren.importance(p, n)
            } else {
                Vec4::ZERO
            };
            let c = choose(imp.x, imp.y, &mut u, &mut pmf)?;
            let r = q.child[c];
            if r & LEAF != 0 {
                return Some(((r & !LEAF) as usize, pmf));
            }
            let (g0, g1) = lane_pair(grand, c);
            let g = choose(g0, g1, &mut u, &mut pmf)?;
            let r = q.grandchild[2 * c + g];
            if r & LEAF != 0 {
                return Some(((r & !LEAF) as usize, pmf));
            }
            q = &self.quads[r as usize];
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
        let Some(root) = self.quads.first() else {
            return match &self.lone {
                Some((_, b)) if b.importance(p, n) > 0.0 => pmf,
                _ => 0.0,
            };
        };
        let (mut trail, mut pmf, mut q) = (trail, pmf, root);
        loop {
            let imp = q.children.importance(p, n);
            let c = (trail & 1) as usize;
            let Some(pc) = child_pmf(imp.x, imp.y, c) else {
                return 0.0;
            };
            pmf *= pc;
            if q.child[c] & LEAF != 0 {
                return pmf;
            }
            let (g0, g1) = lane_pair(q.grandchildren.importance(p, n), c);
            let g = ((trail >> 1) & 1) as usize;
            let Some(pg) = child_pmf(g0, g1, g) else {
                return 0.0;
            };
            pmf *= pg;
            let r = q.grandchild[2 * c + g];
            if r & LEAF != 0 {
                return pmf;
            }
            q = &self.quads[r as usize];
            trail >>= 2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::DirectionCone;
    use crate::light::LightBounds;
    use crate::math::{Bounds3, Vec3};
    use std::f32::consts::PI;

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

    /// pbrt-v4's walk, one level at a time over the binary tree, each child's importance
    /// evaluated on its own.
    fn one_level_sample(
        nodes: &[BinaryNode],
        c: &LightSampleContext,
        u: f32,
    ) -> Option<(usize, f32)> {
        let (mut u, mut pmf, mut node) = (u.min(ONE_MINUS_EPSILON), 1.0f32, 0usize);
        loop {
            let nd = &nodes[node];
            let [i0, i1] = nd.bounds.map(|b| b.importance(c.p, c.ns));
            let k = choose(i0, i1, &mut u, &mut pmf)?;
            if nd.child[k] & LEAF != 0 {
                return Some(((nd.child[k] & !LEAF) as usize, pmf));
            }
            node = nd.child[k] as usize;
        }
    }

    #[test]
    fn two_levels_at_a_time_give_the_bits_of_one() {
        // The bounded lights of `lights()` (a tree some 7 levels deep, odd and even leaf
        // depths), from points all around.
        let lights: Vec<LightExtent> = lights()
            .into_iter()
            .filter(|l| matches!(l, LightExtent::Bounded(_)))
            .collect();
        let s = BvhLightSampler::new(&lights);
        let mut bounded: Vec<_> = lights
            .iter()
            .enumerate()
            .map(|(i, l)| match l {
                LightExtent::Bounded(b) => (i as u32, *b),
                _ => unreachable!(),
            })
            .collect();
        let nodes = build_tree(&mut bounded, &mut vec![0; lights.len()]);
        let mut rng = crate::sampling::Pcg32::new(7, 2);
        let mut chosen = 0;
        for _ in 0..300 {
            let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 8.0 - 4.0;
            let n = match (rng.uniform() * 3.0) as u32 {
                0 => Vec3::ZERO,
                _ => crate::math::normalize(
                    Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5,
                ),
            };
            let c = LightSampleContext { p, n, ns: n };
            for _ in 0..20 {
                let u = rng.uniform();
                let got = s.sample(&c, u);
                let want = one_level_sample(&nodes, &c, u);
                assert_eq!(
                    got.map(|(i, q)| (i, q.to_bits())),
                    want.map(|(i, q)| (i, q.to_bits())),
                    "{c:?} u {u}"
                );
                if let Some((i, q)) = got {
                    assert_eq!(s.pmf(&c, i).to_bits(), q.to_bits());
                    chosen += 1;
                }
            }
        }
        assert!(chosen > 3000, "{chosen}");
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
