//! A BVH over the triangles of one mesh: the accelerator of `lancer bench rays` and of
//! instanced objects.

use super::Bvh;
use crate::math::Vec3;
use crate::ray::Ray;
use crate::shape::{ShapeHit, TriangleRay, intersect_triangle_with, is_degenerate};

/// Triangles (by their three vertex positions) in a BVH. Degenerate triangles are kept out of
/// the tree (they can never be hit); hits name the triangle by its index in the input.
#[derive(Clone, Debug, Default)]
pub struct MeshBvh {
    bvh: Bvh,
    /// Vertex positions of the triangles in the tree, in leaf order.
    tris: Vec<[Vec3; 3]>,
    /// Index in the input of each triangle of `tris`.
    ids: Vec<u32>,
}

impl MeshBvh {
    /// Builds the tree over `tris`.
    pub fn build(tris: &[[Vec3; 3]]) -> MeshBvh {
        let kept: Vec<u32> = (0..tris.len() as u32)
            .filter(|&i| {
                let [a, b, c] = tris[i as usize];
                !is_degenerate(a, b, c)
            })
            .collect();
        let bounds: Vec<_> = kept
            .iter()
            .map(|&i| {
                let [a, b, c] = tris[i as usize];
                crate::math::Bounds3::from_point(a)
                    .union_point(b)
                    .union_point(c)
            })
            .collect();
        let mut bvh = Bvh::build(&bounds);
        let ids: Vec<u32> = bvh.indices.iter().map(|&k| kept[k as usize]).collect();
        let tris = ids.iter().map(|&i| tris[i as usize]).collect();
        for (k, idx) in bvh.indices.iter_mut().enumerate() {
            *idx = k as u32;
        }
        MeshBvh { bvh, tris, ids }
    }

    /// Bytes of the tree and of its triangle copies.
    pub fn memory_bytes(&self) -> usize {
        self.bvh.memory_bytes()
            + self.tris.capacity() * std::mem::size_of::<[Vec3; 3]>()
            + self.ids.capacity() * 4
    }

    /// Bounds of all triangles.
    pub fn bounds(&self) -> crate::math::Bounds3 {
        self.bvh.bounds()
    }

    /// The nearest hit with 0 < t < `ray.t_max`: (input index of the triangle, hit).
    pub fn intersect(&self, ray: &Ray, pre: &TriangleRay) -> Option<(u32, ShapeHit)> {
        let mut best = None;
        self.bvh.intersect(ray, |i, r| {
            let [a, b, c] = self.tris[i as usize];
            let h = intersect_triangle_with(r, pre, a, b, c)?;
            best = Some((self.ids[i as usize], h));
            Some(h.t)
        });
        best
    }

    /// True if any triangle is hit with 0 < t < `ray.t_max`.
    pub fn intersect_any(&self, ray: &Ray, pre: &TriangleRay) -> bool {
        self.bvh.intersect_any(ray, |i, r| {
            let [a, b, c] = self.tris[i as usize];
            intersect_triangle_with(r, pre, a, b, c).is_some()
        })
    }
}
