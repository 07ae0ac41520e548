//! Eight rays traced together: a packet's set-up for the 8-wide slab test and for the
//! watertight triangle test run on eight rays at once against one triangle, and the nearest
//! hit each ray has found so far.
//!
//! A packet pays where its rays cross the same boxes and triangles: the camera rays of one
//! pixel's samples do. Each lane computes exactly what the single-ray test computes for its ray
//! (the same operations in the same order: [`super::tri4::test`] is generic over the width), so
//! a ray finds the same hit in a packet as alone; lanes whose edge function rounds to zero are
//! redone by the scalar test, as for single rays.

use super::simd::{F8, M8};
use super::tri4::{Packet, test};
use crate::math::Vec3;
use crate::ray::Ray;
use crate::shape::{ShapeHit, TriangleRay, intersect_triangle_with};

/// Rays in a packet.
pub const LANES: usize = 8;

/// Eight rays set up for packet queries (lanes without a ray hold a copy of one that has one,
/// and are left out by the masks).
pub struct RayPacket {
    /// The rays.
    pub rays: [Ray; LANES],
    /// Each ray's set-up for the watertight test.
    pub pre: [TriangleRay; LANES],
    /// Lanes holding a ray (bit k for lane k).
    pub active: u32,
    /// The direction along which the BVH's children are visited nearest first: the packet's,
    /// given by its caller, the same whichever lanes hold rays.
    pub order: Vec3,
    /// Origins, per axis.
    pub(super) o: [F8; 3],
    /// 1/d, per axis.
    pub(super) inv_d: [F8; 3],
    /// Lanes whose direction is negative, per axis (the box's near side is then its max).
    pub(super) neg: [M8; 3],
    /// Each ray's origin in its own axis order (o[kx], o[ky], o[kz]).
    o_perm: [F8; 3],
    /// Each ray's shear (S_x, S_y, S_z).
    shear: [F8; 3],
    /// Lanes whose kz is 0, and those whose kz is 1 (the others: 2).
    kz0: M8,
    kz1: M8,
}

impl RayPacket {
    /// The packet of `rays`, lanes `active` (at least one) holding rays, whose BVH children
    /// are visited in their order along `order` (the rays' common direction, say).
    pub fn new(rays: &[Ray; LANES], active: u32, order: Vec3) -> RayPacket {
        debug_assert!(active != 0 && active <= 0xff);
        let first = active.trailing_zeros() as usize;
        let rays: [Ray; LANES] = std::array::from_fn(|k| {
            if active >> k & 1 != 0 {
                rays[k]
            } else {
                rays[first]
            }
        });
        let pre = rays.each_ref().map(TriangleRay::new);
        let axis = |f: &dyn Fn(usize) -> f32| F8::from_array(std::array::from_fn(f));
        let inv: [Vec3; LANES] = rays.each_ref().map(|r| r.d.recip());
        let o = [0, 1, 2].map(|a| axis(&|k| rays[k].o[a]));
        let inv_d = [0, 1, 2].map(|a| axis(&|k| inv[k][a]));
        let neg = [0, 1, 2].map(|a| {
            M8::from_bits(
                inv.iter()
                    .enumerate()
                    .fold(0, |m, (k, v)| m | ((v[a] < 0.0) as u32) << k),
            )
        });
        let o_perm = [0, 1, 2].map(|i| {
            axis(&|k| {
                let (kx, ky) = pre[k].kxy();
                rays[k].o[[kx, ky, pre[k].kz()][i]]
            })
        });
        let shear = [0, 1, 2].map(|i| axis(&|k| pre[k].shear()[i]));
        let kz_is = |z: usize| {
            M8::from_bits((0..LANES).fold(0, |m, k| m | ((pre[k].kz() == z) as u32) << k))
        };
        RayPacket {
            rays,
            pre,
            active,
            order,
            o,
            inv_d,
            neg,
            o_perm,
            shear,
            kz0: kz_is(0),
            kz1: kz_is(1),
        }
    }

    /// The coordinates of point `p` in each lane's axis order (p[kx], p[ky], p[kz]).
    #[inline(always)]
    fn permuted(&self, p: Vec3) -> [F8; 3] {
        let (x, y, z) = (F8::splat(p.x), F8::splat(p.y), F8::splat(p.z));
        // kz = 0: (y, z, x); kz = 1: (z, x, y); kz = 2: (x, y, z).
        let pick = |a: F8, b: F8, c: F8| F8::select(self.kz0, a, F8::select(self.kz1, b, c));
        [pick(y, z, x), pick(z, x, y), pick(x, y, z)]
    }
}

/// Each ray's nearest hit so far: its end (the ray's t_max until a hit shortens it), the hit's
/// barycentrics, and the caller's id of the triangle hit.
#[derive(Clone, Copy, Debug)]
pub struct PacketHits {
    /// Each lane's end: its nearest hit's t, or the end it started with.
    pub t: F8,
    /// Each lane's hit barycentrics (b₁, b₂), where it has one.
    pub u: F8,
    pub v: F8,
    /// Each lane's id of what it hit (`u32::MAX`: nothing yet).
    pub id: [u32; LANES],
}

impl PacketHits {
    /// No hit yet, lane k ending at `t_max[k]`.
    pub fn new(t_max: [f32; LANES]) -> PacketHits {
        PacketHits {
            t: F8::from_array(t_max),
            u: F8::splat(0.0),
            v: F8::splat(0.0),
            id: [u32::MAX; LANES],
        }
    }

    /// Lane `k`'s hit, if it has one.
    pub fn hit(&self, k: usize) -> Option<(u32, ShapeHit)> {
        (self.id[k] != u32::MAX).then(|| {
            (
                self.id[k],
                ShapeHit {
                    t: self.t.lane(k),
                    u: self.u.lane(k),
                    v: self.v.lane(k),
                },
            )
        })
    }

    /// Sets lane `k`'s hit to `h` on `id`.
    #[inline]
    pub fn set(&mut self, k: usize, id: u32, h: ShapeHit) {
        let set = |x: F8, value: f32| {
            let mut a = x.to_array();
            a[k] = value;
            F8::from_array(a)
        };
        self.t = set(self.t, h.t);
        self.u = set(self.u, h.u);
        self.v = set(self.v, h.v);
        self.id[k] = id;
    }
}

/// Tests the triangles of `p` (its lanes in order) against the rays of lanes `lanes`, each
/// ending at its own `hits.t`, keeping in `hits` each ray's nearest hit as
/// [`Packet::intersect_to`] keeps it for one ray: the scaled test against the end the ray
/// entered the leaf with, then each triangle kept if its t is not beyond the nearest so far
/// (so among equal t the later triangle wins). `id(j)` names lane j's triangle. Returns the
/// lanes that found a hit here.
#[inline(always)]
pub fn leaf_nearest<P: Packet>(
    p: &P,
    rp: &RayPacket,
    lanes: u32,
    hits: &mut PacketHits,
    id: impl Fn(usize) -> u32,
) -> u32 {
    let entry = hits.t;
    let mut found_any = 0;
    let mut used = p.used();
    while used != 0 {
        let j = used.trailing_zeros() as usize;
        used &= used - 1;
        let [p0, p1, p2] = p.lane_vertices(j);
        let v = [rp.permuted(p0), rp.permuted(p1), rp.permuted(p2)];
        let f = test(rp.o_perm, rp.shear, entry, v, lanes);
        if f.mask | f.redo == 0 {
            continue;
        }
        let keep = f.t.le(hits.t).bits() & f.mask;
        if keep != 0 {
            let m = M8::from_bits(keep);
            hits.t = F8::select(m, f.t, hits.t);
            hits.u = F8::select(m, f.b1, hits.u);
            hits.v = F8::select(m, f.b2, hits.v);
            let tri = id(j);
            let mut k = keep;
            while k != 0 {
                hits.id[k.trailing_zeros() as usize] = tri;
                k &= k - 1;
            }
            found_any |= keep;
        }
        let mut redo = f.redo;
        while redo != 0 {
            let k = redo.trailing_zeros() as usize;
            redo &= redo - 1;
            let r = Ray {
                t_max: hits.t.lane(k),
                ..rp.rays[k]
            };
            if let Some(h) = intersect_triangle_with(&r, &rp.pre[k], p0, p1, p2) {
                hits.set(k, id(j), h);
                found_any |= 1 << k;
            }
        }
    }
    found_any
}

/// The lanes of `lanes` whose ray hits a triangle of `p` with 0 < t ≤ its `t_max` (shadow
/// rays), as [`Packet::intersect_any`] decides for one ray.
#[inline(always)]
pub fn leaf_any<P: Packet>(p: &P, rp: &RayPacket, lanes: u32, t_max: F8) -> u32 {
    let mut hit = 0;
    let mut used = p.used();
    while used != 0 && lanes & !hit != 0 {
        let j = used.trailing_zeros() as usize;
        used &= used - 1;
        let [p0, p1, p2] = p.lane_vertices(j);
        let v = [rp.permuted(p0), rp.permuted(p1), rp.permuted(p2)];
        let f = test(rp.o_perm, rp.shear, t_max, v, lanes & !hit);
        hit |= f.mask;
        let mut redo = f.redo & !hit;
        while redo != 0 {
            let k = redo.trailing_zeros() as usize;
            redo &= redo - 1;
            let r = Ray {
                t_max: t_max.lane(k),
                ..rp.rays[k]
            };
            if intersect_triangle_with(&r, &rp.pre[k], p0, p1, p2).is_some() {
                hit |= 1 << k;
            }
        }
    }
    hit
}
