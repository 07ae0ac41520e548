//! Four triangles stored for intersection side by side, and the watertight ray–triangle test
//! of [`crate::shape::intersect_triangle_with`] run on all four at once.
//!
//! Each lane performs exactly the operations of the scalar test, in the same order and with
//! the same fused multiply-adds, so a packet finds the same hits with the same t, bit for bit.
//! Lanes whose edge function rounds to zero, where the scalar test redoes them in double
//! precision, are handed to the scalar test itself.

use super::simd::{F4, Lanes, MaskLanes, not_max_bits};
use crate::math::{PackedVec3, Vec3, gamma};
use crate::ray::Ray;
use crate::shape::{ShapeHit, TriangleRay, intersect_triangle_with};

/// Up to four triangles: `p[vertex][axis][lane]`, and an id per lane (`u32::MAX`: unused).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Tri4 {
    p: [[[f32; 4]; 3]; 3],
    /// The caller's id of each lane's triangle; `u32::MAX` marks an unused lane.
    pub ids: [u32; 4],
}

impl Tri4 {
    /// A packet of up to four triangles `(vertices, id)`; ids must not be `u32::MAX`.
    pub fn new(tris: &[([PackedVec3; 3], u32)]) -> Tri4 {
        let mut t = Tri4 {
            p: [[[0.0; 4]; 3]; 3],
            ids: [u32::MAX; 4],
        };
        for (lane, (v, id)) in tris.iter().take(4).enumerate() {
            for (k, p) in v.iter().enumerate() {
                for a in 0..3 {
                    t.p[k][a][lane] = p[a];
                }
            }
            t.ids[lane] = *id;
        }
        t
    }

    /// A packet that holds no triangle.
    pub const EMPTY: Tri4 = Tri4 {
        p: [[[0.0; 4]; 3]; 3],
        ids: [u32::MAX; 4],
    };

    /// True when no lane holds a triangle.
    pub fn is_empty(&self) -> bool {
        self.ids[0] == u32::MAX
    }

    /// Lane `lane`'s vertices.
    #[inline]
    pub fn vertices(&self, lane: usize) -> [Vec3; 3] {
        [0, 1, 2].map(|k| Vec3::new(self.p[k][0][lane], self.p[k][1][lane], self.p[k][2][lane]))
    }
}

impl Packet for Tri4 {
    #[inline(always)]
    fn used(&self) -> u32 {
        not_max_bits(&self.ids)
    }

    #[inline(always)]
    fn lane_vertices(&self, lane: usize) -> [Vec3; 3] {
        self.vertices(lane)
    }

    #[inline(always)]
    fn permuted(&self, pre: &TriangleRay) -> [[F4; 3]; 3] {
        let kz = pre.kz();
        let (kx, ky) = pre.kxy();
        [0, 1, 2].map(|k| {
            [
                F4::load(&self.p[k][kx]),
                F4::load(&self.p[k][ky]),
                F4::load(&self.p[k][kz]),
            ]
        })
    }
}

/// Up to four triangles named by their vertex indices into a shared position array, tested as
/// a [`Tri4`] packet would test them (the same operations on the same values, so the same hits
/// bit for bit) without copying their vertices into one.
#[derive(Clone, Copy, Debug)]
pub struct IndexedTri4<'a> {
    /// The shared vertex positions, the last one padding (see [`IndexedTri4::new`]).
    positions: &'a [PackedVec3],
    /// One to four triangles, each as three indices into `positions`.
    tris: &'a [[u32; 3]],
}

impl<'a> IndexedTri4<'a> {
    /// The packet of `tris` over `positions`.
    ///
    /// # Safety
    /// `tris` holds one to four triangles, and each of their indices is below
    /// `positions.len() − 1`: the last position is padding, of which a vertex's 16-byte load
    /// reads the first 4 bytes when the vertex before it is loaded.
    #[inline(always)]
    pub unsafe fn new(positions: &'a [PackedVec3], tris: &'a [[u32; 3]]) -> IndexedTri4<'a> {
        debug_assert!((1..=4).contains(&tris.len()));
        debug_assert!(
            tris.iter()
                .flatten()
                .all(|&i| (i as usize) + 1 < positions.len())
        );
        IndexedTri4 { positions, tris }
    }
}

impl Packet for IndexedTri4<'_> {
    #[inline(always)]
    fn used(&self) -> u32 {
        (1u32 << self.tris.len().min(4)) - 1
    }

    #[inline]
    fn lane_vertices(&self, lane: usize) -> [Vec3; 3] {
        self.tris[lane].map(|i| Vec3::from(self.positions[i as usize]))
    }

    /// The vertices' coordinates in the ray's axis order, as lanes (unused lanes repeat the
    /// last triangle).
    #[inline(always)]
    fn permuted(&self, pre: &TriangleRay) -> [[F4; 3]; 3] {
        let kz = pre.kz();
        let (kx, ky) = pre.kxy();
        // SAFETY: the constructor's contract: one to four triangles, whose vertices each have
        // a position after them (padding at the end).
        unsafe { self.transposed([kx, ky, kz]) }
    }
}

impl IndexedTri4<'_> {
    /// [`Packet::permuted`]: vertex k of the four triangles as lanes ([`F4::positions_as_lanes`]),
    /// lanes past the last triangle repeating it.
    ///
    /// # Safety
    /// [`IndexedTri4::new`]'s contract.
    #[inline(always)]
    unsafe fn transposed(&self, axes: [usize; 3]) -> [[F4; 3]; 3] {
        let last = self.tris.len() - 1;
        // SAFETY: lanes are clamped to the last triangle, below `tris.len()`; every index is
        // below `positions.len() − 1` (the contract). Written out: `array::map` here was left
        // out of line, a call per packet.
        unsafe {
            let t = |l: usize| *self.tris.get_unchecked(l.min(last));
            let (t0, t1, t2, t3) = (t(0), t(1), t(2), t(3));
            let p = self.positions;
            [
                F4::positions_as_lanes(p, [t0[0], t1[0], t2[0], t3[0]], axes),
                F4::positions_as_lanes(p, [t0[1], t1[1], t2[1], t3[1]], axes),
                F4::positions_as_lanes(p, [t0[2], t1[2], t2[2], t3[2]], axes),
            ]
        }
    }
}

/// Up to four triangles tested side by side: [`Tri4`] (vertices copied into the packet) and
/// [`IndexedTri4`] (vertices gathered through their indices) give their lanes, the test is
/// theirs in common.
pub trait Packet {
    /// Lanes holding triangles, as a mask (bit k for lane k).
    fn used(&self) -> u32;

    /// Lane `lane`'s vertices.
    fn lane_vertices(&self, lane: usize) -> [Vec3; 3];

    /// The vertices' coordinates in the ray's axis order (kx, ky, kz), as lanes:
    /// `[vertex][axis]` (unused lanes hold any finite values).
    fn permuted(&self, pre: &TriangleRay) -> [[F4; 3]; 3];

    /// The nearest hit with 0 < t ≤ `t_max` among the lanes: (lane, hit). As in the scalar
    /// test and pbrt-v4's `IntersectTriangle`, a hit at exactly `t_max` is accepted, so among
    /// equal t the highest lane wins, exactly as when the lanes are tested one after another,
    /// each against the ray shortened to the hit before. (Coplanar surfaces, such as a prism
    /// standing on a floor, then resolve as in pbrt-v4: the triangle tested last.) Inlined
    /// into the traversal loops: the ray and its set-up stay in registers across the leaves.
    #[inline(always)]
    fn intersect_to(&self, ray: &Ray, t_max: f32, pre: &TriangleRay) -> Option<(usize, ShapeHit)> {
        let (o, s) = ray_lanes(ray, pre);
        let found = test(o, s, F4::splat(t_max), self.permuted(pre), self.used());
        nearest(ray, t_max, pre, found, |lane| self.lane_vertices(lane))
    }

    /// True if any lane's triangle is hit with 0 < t ≤ `ray.t_max`.
    #[inline(always)]
    fn intersect_any(&self, ray: &Ray, pre: &TriangleRay) -> bool {
        let (o, s) = ray_lanes(ray, pre);
        let found = test(o, s, F4::splat(ray.t_max), self.permuted(pre), self.used());
        any(ray, pre, found, |lane| self.lane_vertices(lane))
    }
}

/// The nearest of the hits `found` by [`test`] on the ray ending at `t_max`: (lane, hit),
/// lanes to redo tested by the scalar test on `vertices(lane)`. As in the scalar test and
/// pbrt-v4's `IntersectTriangle`, a hit at exactly `t_max` is accepted, so among equal t the
/// highest lane wins, exactly as when the lanes are tested one after another, each against the
/// ray shortened to the hit before. (Coplanar surfaces, such as a prism standing on a floor,
/// then resolve as in pbrt-v4.)
#[inline(always)]
fn nearest(
    ray: &Ray,
    t_max: f32,
    pre: &TriangleRay,
    found: Found<F4>,
    vertices: impl Fn(usize) -> [Vec3; 3],
) -> Option<(usize, ShapeHit)> {
    let Found {
        mut mask,
        t,
        b1,
        b2,
        redo,
    } = found;
    if redo != 0 {
        return nearest_redo(ray, t_max, pre, found, vertices);
    }
    // Lanes in increasing order, each kept if not beyond the nearest so far (the scaled test
    // in `test` compares t·det, so t itself may still round past t_max).
    let mut best = None;
    let mut t_max = t_max;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let t_lane = t.lane(lane);
        if t_lane <= t_max {
            t_max = t_lane;
            best = Some(lane);
        }
    }
    // Read from the registers: a hit record copied through memory in pieces stalled here.
    best.map(|lane| {
        (
            lane,
            ShapeHit {
                t: t_max,
                u: b1.lane(lane),
                v: b2.lane(lane),
            },
        )
    })
}

/// [`nearest`] when some lanes are to be redone by the scalar test (an edge function rounded
/// to zero): the lanes in order, each against the ray shortened to the nearest hit so far.
/// Inlined although rare: its result then meets the common path's in registers, where a
/// result returned through memory stalled every hit (the hit record read back in pieces).
#[inline(always)]
fn nearest_redo(
    ray: &Ray,
    t_max: f32,
    pre: &TriangleRay,
    found: Found<F4>,
    vertices: impl Fn(usize) -> [Vec3; 3],
) -> Option<(usize, ShapeHit)> {
    let Found { mut mask, redo, .. } = found;
    let (t, b1, b2) = (found.t.to_array(), found.b1.to_array(), found.b2.to_array());
    let mut best: Option<(usize, ShapeHit)> = None;
    let mut t_max = t_max;
    for lane in 0..4 {
        let bit = 1 << lane;
        if redo & bit != 0 {
            mask &= !bit;
            let [p0, p1, p2] = vertices(lane);
            let r = Ray { t_max, ..*ray };
            if let Some(h) = intersect_triangle_with(&r, pre, p0, p1, p2) {
                t_max = h.t;
                best = Some((lane, h));
            }
        } else if mask & bit != 0 && t[lane] <= t_max {
            t_max = t[lane];
            best = Some((
                lane,
                ShapeHit {
                    t: t[lane],
                    u: b1[lane],
                    v: b2[lane],
                },
            ));
        }
    }
    best
}

/// True if [`test`] `found` a hit, lanes to redo tested by the scalar test on
/// `vertices(lane)`.
#[inline(always)]
fn any(
    ray: &Ray,
    pre: &TriangleRay,
    found: Found<F4>,
    vertices: impl Fn(usize) -> [Vec3; 3],
) -> bool {
    let Found { mask, redo, .. } = found;
    if mask & !redo != 0 {
        return true;
    }
    (0..4).any(|lane| {
        redo & (1 << lane) != 0 && {
            let [p0, p1, p2] = vertices(lane);
            intersect_triangle_with(ray, pre, p0, p1, p2).is_some()
        }
    })
}

/// The ray's part of [`test`] for one ray against four triangles: its origin in the ray's axis
/// order (o[kx], o[ky], o[kz]) and its shear (S_x, S_y, S_z), as lanes.
#[inline(always)]
fn ray_lanes(ray: &Ray, pre: &TriangleRay) -> ([F4; 3], [F4; 3]) {
    let kz = pre.kz();
    let (kx, ky) = pre.kxy();
    let o = ray.o.to_array();
    let s = pre.shear();
    (
        [F4::splat(o[kx]), F4::splat(o[ky]), F4::splat(o[kz])],
        [F4::splat(s.x), F4::splat(s.y), F4::splat(s.z)],
    )
}

/// What [`test`] finds, kept in vector registers: the lanes hit, their t and barycentrics
/// (b₁, b₂), and the lanes to redo with the scalar test.
#[derive(Clone, Copy)]
pub(crate) struct Found<L> {
    /// Lanes hit (not counting those to redo).
    pub mask: u32,
    /// Each lane's t.
    pub t: L,
    /// Each lane's barycentric b₁.
    pub b1: L,
    /// Each lane's barycentric b₂.
    pub b2: L,
    /// Lanes whose edge function rounded to zero: the scalar test decides them.
    pub redo: u32,
}

impl<L: Lanes> Found<L> {
    /// No lane hit; lanes `redo` to redo.
    #[inline(always)]
    fn none(redo: u32) -> Found<L> {
        let zero = L::splat(0.0);
        Found {
            mask: 0,
            t: zero,
            b1: zero,
            b2: zero,
            redo,
        }
    }
}

/// The tests on the lanes `used`: lane k tests the triangle of vertices `v` (`[vertex][axis]`,
/// axes in the ray's order kx, ky, kz) against the ray of origin `o` (in that order too) and
/// shear `s`, ending at `t_max`. One ray against four triangles ([`F4`]), or eight rays, each
/// in its own axis order, against one triangle ([`super::packet`]).
#[inline(always)]
pub(crate) fn test<L: Lanes>(
    o: [L; 3],
    s: [L; 3],
    t_max: L,
    v: [[L; 3]; 3],
    used: u32,
) -> Found<L> {
    let [ox, oy, oz] = o;
    let [sx, sy, sz] = s;
    // Translate to the ray's origin, permute (kx, ky, kz), shear in x and y:
    // x' = x + S_x·z, y' = y + S_y·z.
    let vert = |k: usize| {
        let [x, y, z] = v[k];
        let z = z.sub(oz);
        let x = x.sub(ox).add(sx.mul(z));
        let y = y.sub(oy).add(sy.mul(z));
        (x, y, z)
    };
    let (p0x, p0y, p0z) = vert(0);
    let (p1x, p1y, p1z) = vert(1);
    let (p2x, p2y, p2z) = vert(2);
    // Edge functions e_i = a·b − c·d by Kahan's difference of products:
    // cd = c·d, err = fma(−c, d, cd), dop = fma(a, b, −cd), e = dop + err.
    let dop = |a: L, b: L, c: L, d: L| {
        let cd = c.mul(d);
        let err = c.neg_mul_add(d, cd);
        a.mul_sub(b, cd).add(err)
    };
    let e0 = dop(p1x, p2y, p1y, p2x);
    let e1 = dop(p2x, p0y, p2y, p0x);
    let e2 = dop(p0x, p1y, p0y, p1x);
    let zero = L::splat(0.0);
    let redo = e0.eq(zero).or(e1.eq(zero)).or(e2.eq(zero)).bits() & used;
    // Same signs: not (some negative and some positive).
    let some_neg = e0.lt(zero).or(e1.lt(zero)).or(e2.lt(zero));
    let some_pos = e0.gt(zero).or(e1.gt(zero)).or(e2.gt(zero));
    let edges_ok = some_neg.and(some_pos).bits() ^ L::ALL;
    if edges_ok & used & !redo == 0 {
        // The ray passes outside every triangle (the common case): stop early.
        return Found::none(redo);
    }
    let det = e0.add(e1).add(e2);
    let (p0z, p1z, p2z) = (p0z.mul(sz), p1z.mul(sz), p2z.mul(sz));
    // t_scaled = e₀z₀ + e₁z₁ + e₂z₂, compared with t_max·det on det's side.
    let t_scaled = e0.mul(p0z).add(e1.mul(p1z)).add(e2.mul(p2z));
    let tmd = t_max.mul(det);
    let neg_ok = det.lt(zero).and(t_scaled.lt(zero)).and(t_scaled.ge(tmd));
    let pos_ok = det.gt(zero).and(t_scaled.gt(zero)).and(t_scaled.le(tmd));
    let inside = neg_ok.or(pos_ok).and_not(some_neg.and(some_pos));
    let mut mask = inside.bits() & used & !redo;
    if mask == 0 {
        return Found::none(redo);
    }
    let inv_det = L::splat(1.0).div(det);
    let t = t_scaled.mul(inv_det);
    // Conservative bound on t's rounding error (PBRT-v4 §6.8.7): t must exceed δ_t.
    let max3 = |a: L, b: L, c: L| {
        let (a, b, c) = (a.abs(), b.abs(), c.abs());
        c.max(b).max(a)
    };
    let max_zt = max3(p0z, p1z, p2z);
    let max_xt = max3(p0x, p1x, p2x);
    let max_yt = max3(p0y, p1y, p2y);
    let delta_z = L::splat(gamma(3)).mul(max_zt);
    let g5 = L::splat(gamma(5));
    let delta_x = g5.mul(max_xt.add(max_zt));
    let delta_y = g5.mul(max_yt.add(max_zt));
    // δ_e = 2(γ₂·max_x·max_y + δ_y·max_x + δ_x·max_y)
    let delta_e = L::splat(2.0).mul(
        L::splat(gamma(2))
            .mul(max_xt)
            .mul(max_yt)
            .add(delta_y.mul(max_xt))
            .add(delta_x.mul(max_yt)),
    );
    let max_e = max3(e0, e1, e2);
    // δ_t = 3(γ₃·max_e·max_z + δ_e·max_z + δ_z·max_e)·|1/det|
    let delta_t = L::splat(3.0)
        .mul(
            L::splat(gamma(3))
                .mul(max_e)
                .mul(max_zt)
                .add(delta_e.mul(max_zt))
                .add(delta_z.mul(max_e)),
        )
        .mul(inv_det.abs());
    mask &= t.gt(delta_t).bits();
    Found {
        mask,
        t,
        b1: e1.mul(inv_det),
        b2: e2.mul(inv_det),
        redo,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two coplanar triangles overlapping under the ray (z = 0, ray straight down from z = 1):
    /// both are hit at t = 1 exactly. The packet must pick what testing the lanes one after
    /// another picks: the scalar test accepts t = t_max, so the later lane wins.
    #[test]
    fn equal_t_goes_to_the_later_lane_as_in_the_scalar_test() {
        let a = [[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]].map(PackedVec3::from);
        let b = [[-2.0, -2.0, 0.0], [3.0, -2.0, 0.0], [-2.0, 3.0, 0.0]].map(PackedVec3::from);
        let ray = Ray::new(Vec3::new(0.1, 0.2, 1.0), Vec3::new(0.0, 0.0, -1.0));
        let pre = TriangleRay::new(&ray);
        let p = Tri4::new(&[(a, 7), (b, 9)]);
        let (lane, h) = p
            .intersect_to(&ray, ray.t_max, &pre)
            .expect("both triangles are hit");
        assert_eq!(h.t, 1.0);
        assert_eq!((lane, p.ids[lane]), (1, 9));
        // The scalar sequence: b is tested against the ray shortened to a's hit, and kept.
        let ha = intersect_triangle_with(&ray, &pre, a[0].into(), a[1].into(), a[2].into());
        let short = Ray {
            t_max: ha.expect("a is hit").t,
            ..ray
        };
        assert!(
            intersect_triangle_with(&short, &pre, b[0].into(), b[1].into(), b[2].into()).is_some()
        );
        // And a hit beyond t_max is still refused.
        let shorter = Ray { t_max: 0.99, ..ray };
        assert!(p.intersect_to(&shorter, shorter.t_max, &pre).is_none());
    }
}
