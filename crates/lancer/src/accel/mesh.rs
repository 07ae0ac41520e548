//! A BVH over the triangles of one mesh, its leaves stored as 4-triangle packets: the
//! accelerator of `lancer bench rays` and of instanced objects.

use super::{Bvh, Leaf, Packet, Tri4};
use crate::math::{Bounds3, PackedVec3, Vec3};
use crate::ray::Ray;
use crate::shape::{ShapeHit, TriangleRay, is_degenerate};
use rayon::prelude::*;

/// Triangles (by their three vertex positions) in a BVH whose leaves are [`Tri4`] packets.
/// Degenerate triangles are kept out of the tree (they can never be hit); hits name the
/// triangle by its index in the input.
#[derive(Clone, Debug, Default)]
pub struct MeshBvh {
    bvh: Bvh,
    /// One packet per leaf of `bvh`.
    packets: Vec<Tri4>,
}

impl MeshBvh {
    /// Builds the tree over `tris` (in parallel on the current rayon pool).
    pub fn build(tris: &[[PackedVec3; 3]]) -> MeshBvh {
        let kept: Vec<u32> = (0..tris.len() as u32)
            .filter(|&i| {
                let [a, b, c] = tris[i as usize].map(Vec3::from);
                !is_degenerate(a, b, c)
            })
            .collect();
        let bounds: Vec<Bounds3> = kept
            .par_iter()
            .map(|&i| {
                let [a, b, c] = tris[i as usize].map(Vec3::from);
                Bounds3::from_point(a).union_point(b).union_point(c)
            })
            .collect();
        let mut bvh = Bvh::build(&bounds);
        let packets = (0..bvh.leaf_count() as u32)
            .into_par_iter()
            .map(|leaf| {
                let mut lanes = [([PackedVec3::ZERO; 3], 0u32); 4];
                let range = bvh.leaf_range(leaf);
                let n = range.len();
                for (lane, k) in range.enumerate() {
                    let id = kept[bvh.indices[k] as usize];
                    lanes[lane] = (tris[id as usize], id);
                }
                Tri4::new(&lanes[..n])
            })
            .collect();
        bvh.drop_leaf_table();
        MeshBvh { bvh, packets }
    }

    /// Bytes of the tree and of its packets.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes() + self.packets.capacity() * std::mem::size_of::<Tri4>()
    }

    /// Bounds of all triangles.
    pub fn bounds(&self) -> Bounds3 {
        self.bvh.bounds()
    }

    /// The nearest hit with 0 < t ≤ `ray.t_max`: (input index of the triangle, hit).
    #[inline]
    pub fn intersect(&self, ray: &Ray, pre: &TriangleRay) -> Option<(u32, ShapeHit)> {
        let mut best = None;
        let prefetch = |leaf| self.prefetch(leaf);
        self.bvh
            .traverse_prefetching(ray, ray.t_max, prefetch, |leaf, t_max| {
                let p = &self.packets[leaf.id as usize];
                let (lane, h) = p.intersect_to(ray, t_max, pre)?;
                best = Some((p.ids[lane], h));
                Some(h.t)
            });
        best
    }

    /// True if any triangle is hit with 0 < t ≤ `ray.t_max`.
    #[inline]
    pub fn intersect_any(&self, ray: &Ray, pre: &TriangleRay) -> bool {
        let prefetch = |leaf| self.prefetch(leaf);
        self.bvh
            .intersect_any_leaves_prefetching(ray, prefetch, |leaf, r| {
                self.packets[leaf.id as usize].intersect_any(r, pre)
            })
    }

    /// Asks for the lines of leaf `leaf`'s packet (160 bytes: three lines at most).
    #[inline(always)]
    fn prefetch(&self, leaf: Leaf) {
        let p = self.packets.as_ptr().wrapping_add(leaf.id as usize) as *const u8;
        for offset in [0, 64, std::mem::size_of::<Tri4>() - 1] {
            super::prefetch(p.wrapping_add(offset));
        }
    }
}
