//! Triangles that share their vertices, in a BVH whose leaves name their triangles instead of
//! copying them: per triangle the three indices of its vertices (12 bytes) beside the tree,
//! where a packet of copied vertices takes 40. A leaf's triangles are gathered into vector
//! lanes when a ray reaches it and tested as a [`super::Tri4`] packet tests them, so that
//! every hit it finds is the packet's, bit for bit.

use super::packet::{self, PacketHits, RayPacket};
use super::tri4::{IndexedTri4, Packet};
use super::{Bvh, Leaf};
use crate::math::{Bounds3, PackedVec3, Vec3};
use crate::ray::Ray;
use crate::shape::{ShapeHit, TriangleRay};

/// Vertex positions and triangles (three vertex indices each) in a BVH. The triangles are kept
/// in the tree's leaf order: a triangle is named by its slot in that order.
#[derive(Clone, Debug, Default)]
pub struct IndexedTris {
    /// The tree; its leaf table gives each leaf's range of slots (its primitive indices are
    /// freed: slot k is the k-th in leaf order).
    bvh: Bvh,
    /// Vertex positions, and one more as padding: a packet loads each vertex as 16 bytes
    /// ([`IndexedTri4::new`]).
    positions: Vec<PackedVec3>,
    /// Per slot, the vertex indices of its triangle.
    tris: Vec<[u32; 3]>,
}

impl IndexedTris {
    /// Builds the tree (in parallel on the current rayon pool) over `tris`, triangles of
    /// `positions` none of which is degenerate, with every index in range. Returns the tree and
    /// for each slot the index of its triangle in `tris`.
    ///
    /// Panics if an index is out of range (the packets' loads rely on it).
    pub fn build(mut positions: Vec<PackedVec3>, tris: Vec<[u32; 3]>) -> (IndexedTris, Vec<u32>) {
        let n = positions.len();
        assert!(
            tris.iter().flatten().all(|&i| (i as usize) < n),
            "a triangle's vertex index is out of range"
        );
        if tris.is_empty() {
            // Nothing to test: no positions, nor their padding.
            positions = Vec::new();
        } else {
            positions.reserve_exact(1);
            positions.push(PackedVec3::ZERO);
        }
        let mut bvh = Bvh::build_with(tris.len(), |k| {
            let [a, b, c] = tris[k].map(|i| Vec3::from(positions[i as usize]));
            Bounds3::from_point(a).union_point(b).union_point(c)
        });
        // A leaf's id is then its first slot: its triangles come straight from the node.
        bvh.number_leaves_by_slot();
        let order = std::mem::take(&mut bvh.indices);
        let sorted: Vec<[u32; 3]> = order.iter().map(|&i| tris[i as usize]).collect();
        drop(tris);
        let accel = IndexedTris {
            bvh,
            positions,
            tris: sorted,
        };
        (accel, order)
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.tris.len()
    }

    /// True when there is no triangle.
    pub fn is_empty(&self) -> bool {
        self.tris.is_empty()
    }

    /// The vertex indices of the triangle in slot `slot`.
    #[inline]
    pub fn triangle(&self, slot: u32) -> [u32; 3] {
        self.tris[slot as usize]
    }

    /// The vertex positions of the triangle in slot `slot`.
    #[inline]
    pub fn vertices(&self, slot: u32) -> [Vec3; 3] {
        self.triangle(slot)
            .map(|i| Vec3::from(self.positions[i as usize]))
    }

    /// Nodes of the tree.
    pub fn node_count(&self) -> usize {
        self.bvh.node_count()
    }

    /// Bytes of the tree alone (its nodes: the leaves are numbered by their slots).
    pub fn tree_bytes(&self) -> usize {
        self.bvh.memory_bytes()
    }

    /// Bytes of the positions and of the triangles' vertex indices.
    pub fn geometry_bytes(&self) -> usize {
        self.positions.capacity() * std::mem::size_of::<PackedVec3>()
            + self.tris.capacity() * std::mem::size_of::<[u32; 3]>()
    }

    /// Bounds of all triangles.
    pub fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// Leaf `leaf`'s triangles as a packet, and the slot of its first (lane k holds slot
    /// `first + k`).
    #[inline(always)]
    fn packet(&self, leaf: Leaf) -> (IndexedTri4<'_>, u32) {
        let first = leaf.id;
        let range = first as usize..(first + leaf.count) as usize;
        debug_assert!(range.end <= self.tris.len());
        // SAFETY: the leaves (numbered by their first slots) split 0..tris.len(), each one
        // to four triangles: the tree and `tris` are built together (`build`) and never
        // changed. `build` checked every index against the positions, then added the padding
        // position after them.
        let p = unsafe { IndexedTri4::new(&self.positions, self.tris.get_unchecked(range)) };
        (p, first)
    }

    /// The nearest hit with 0 < t ≤ `t_max`: (slot of the triangle, hit).
    #[inline]
    pub fn intersect_to(
        &self,
        ray: &Ray,
        t_max: f32,
        pre: &TriangleRay,
    ) -> Option<(u32, ShapeHit)> {
        let mut best = None;
        let prefetch = |leaf| self.prefetch(leaf);
        self.bvh
            .traverse_prefetching(ray, t_max, prefetch, |leaf, t_max| {
                let (p, first) = self.packet(leaf);
                let (lane, h) = p.intersect_to(ray, t_max, pre)?;
                best = Some((first + lane as u32, h));
                Some(h.t)
            });
        best
    }

    /// Asks for the lines of leaf `leaf`'s vertex indices (12 bytes a triangle, so at most
    /// two lines), which its test will read first.
    #[inline(always)]
    fn prefetch(&self, leaf: Leaf) {
        let p = self.tris.as_ptr().wrapping_add(leaf.id as usize) as *const u8;
        super::prefetch(p);
        super::prefetch(p.wrapping_add(12 * leaf.count as usize - 1));
    }

    /// [`IndexedTris::intersect_to`] for the rays of a packet, each ending at its `hits.t`:
    /// each lane's nearest hit is kept in `hits`, its id the triangle's slot.
    #[inline]
    pub fn intersect_packet(&self, rp: &RayPacket, hits: &mut PacketHits) {
        self.bvh.traverse_packet(rp, hits, |leaf, lanes, hits| {
            let (p, first) = self.packet(leaf);
            packet::leaf_nearest(&p, rp, lanes, hits, |j| first + j as u32);
        });
    }

    /// True if any triangle is hit with 0 < t ≤ `ray.t_max`.
    #[inline]
    pub fn intersect_any(&self, ray: &Ray, pre: &TriangleRay) -> bool {
        let prefetch = |leaf| self.prefetch(leaf);
        self.bvh
            .intersect_any_leaves_prefetching(ray, prefetch, |leaf, r| {
                self.packet(leaf).0.intersect_any(r, pre)
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::normalize;
    use crate::sampling::{hash_u64, u32_to_unit_f32};
    use crate::shape::intersect_triangle;

    fn rnd(i: u64) -> f32 {
        u32_to_unit_f32(hash_u64(&[i]) as u32)
    }

    /// A grid of `n`×`n` quads (two triangles each) on a bumpy height field: shared vertices.
    fn grid(n: u32) -> (Vec<PackedVec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let z = rnd((j * (n + 1) + i) as u64);
                p.push(PackedVec3::new(i as f32, j as f32, z));
            }
        }
        let mut t = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let v = j * (n + 1) + i;
                t.push([v, v + 1, v + n + 2]);
                t.push([v, v + n + 2, v + n + 1]);
            }
        }
        (p, t)
    }

    #[test]
    fn finds_what_brute_force_finds_bit_for_bit() {
        for n in [0, 1, 3, 40] {
            let (p, t) = grid(n);
            let (accel, order) = IndexedTris::build(p.clone(), t.clone());
            assert_eq!(accel.len(), t.len());
            // The positions and one padding position after them (the packets' loads read
            // into it); nothing without a triangle.
            let bytes = if t.is_empty() {
                0
            } else {
                12 * (p.len() + 1) + 12 * t.len()
            };
            assert_eq!(accel.geometry_bytes(), bytes);
            // Each input triangle in one slot, with its vertices.
            let mut seen = order.clone();
            seen.sort_unstable();
            assert_eq!(seen, (0..t.len() as u32).collect::<Vec<_>>());
            for (slot, &i) in order.iter().enumerate() {
                assert_eq!(accel.triangle(slot as u32), t[i as usize]);
            }
            for k in 0..400u64 {
                let o = Vec3::new(rnd(10_000 + k), rnd(20_000 + k), 3.0) * n as f32;
                let d = normalize(Vec3::new(
                    rnd(40_000 + k) - 0.5,
                    rnd(50_000 + k) - 0.5,
                    -1.0 - rnd(60_000 + k),
                ));
                let ray = Ray::new(o + Vec3::new(0.0, 0.0, 2.0), d);
                let mut r = ray;
                let mut want = None;
                for (i, tri) in t.iter().enumerate() {
                    let [a, b, c] = tri.map(|v| Vec3::from(p[v as usize]));
                    if let Some(h) = intersect_triangle(&r, a, b, c) {
                        r.t_max = h.t;
                        want = Some((i as u32, h.t.to_bits(), h.u.to_bits(), h.v.to_bits()));
                    }
                }
                let pre = TriangleRay::new(&ray);
                let got = accel.intersect_to(&ray, ray.t_max, &pre).map(|(slot, h)| {
                    let i = order[slot as usize];
                    (i, h.t.to_bits(), h.u.to_bits(), h.v.to_bits())
                });
                assert_eq!(got, want, "n {n} ray {k}");
                assert_eq!(accel.intersect_any(&ray, &pre), want.is_some());
            }
        }
    }
}
