//! The world's plain triangle meshes (neither emitting nor alpha-tested): their vertices in
//! shared arrays and their triangles in an [`IndexedTris`] tree, with no record per triangle.
//! A triangle costs its three vertex indices and its share of the tree and of the vertices;
//! its material, media and orientation are its mesh's, kept once per mesh.

use crate::accel::IndexedTris;
use crate::math::{Bounds3, PackedVec3, Vec2, Vec3};
use crate::ray::Ray;
use crate::shape::{
    ShadingDerivatives, ShapeHit, SurfaceInteraction, TriangleMesh, TriangleRay, is_degenerate,
    triangle_shading_derivatives,
};

/// Marks a mesh without per-vertex normals or (u, v).
const NONE: u32 = u32::MAX;

/// What a mesh keeps of its own: where its vertices start, where its normals and (u, v) start
/// in the shared arrays (or [`NONE`]), its orientation and its primitive record.
#[derive(Clone, Copy, Debug)]
struct MeshRecord {
    first_vertex: u32,
    normals: u32,
    uvs: u32,
    flip_normal: bool,
    prim: u32,
}

/// The plain triangle meshes of a scene, world space.
#[derive(Debug, Default)]
pub struct SceneTris {
    accel: IndexedTris,
    /// Per-vertex shading normals of the meshes that have them, one mesh after another.
    normals: Vec<PackedVec3>,
    /// Per-vertex (u, v) of the meshes that have them, one mesh after another.
    uvs: Vec<Vec2>,
    /// By first vertex.
    meshes: Vec<MeshRecord>,
}

/// Gathers meshes for a [`SceneTris`].
#[derive(Debug, Default)]
pub(crate) struct SceneTrisBuilder {
    positions: Vec<PackedVec3>,
    tris: Vec<[u32; 3]>,
    normals: Vec<PackedVec3>,
    uvs: Vec<Vec2>,
    meshes: Vec<MeshRecord>,
}

impl SceneTrisBuilder {
    /// Adds `mesh` (world space, checked), whose triangles are primitive record `prim`'s; its
    /// degenerate triangles, which no ray can hit, are left out.
    pub(crate) fn add(&mut self, mesh: TriangleMesh, prim: u32) {
        let mesh = by_first_use(mesh);
        let base = self.positions.len() as u32;
        let record = MeshRecord {
            first_vertex: base,
            normals: if mesh.normals.is_empty() {
                NONE
            } else {
                self.normals.len() as u32
            },
            uvs: if mesh.uvs.is_empty() {
                NONE
            } else {
                self.uvs.len() as u32
            },
            flip_normal: mesh.flip_normal,
            prim,
        };
        for f in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [f[0], f[1], f[2]].map(|i| Vec3::from(mesh.positions[i as usize]));
            if !is_degenerate(a, b, c) {
                self.tris.push([f[0] + base, f[1] + base, f[2] + base]);
            }
        }
        self.positions.extend_from_slice(&mesh.positions);
        self.normals.extend_from_slice(&mesh.normals);
        self.uvs.extend_from_slice(&mesh.uvs);
        self.meshes.push(record);
    }

    /// The tree over every triangle added.
    pub(crate) fn build(mut self) -> SceneTris {
        self.positions.shrink_to_fit();
        self.normals.shrink_to_fit();
        self.uvs.shrink_to_fit();
        self.meshes.shrink_to_fit();
        let (accel, _) = IndexedTris::build(self.positions, self.tris);
        SceneTris {
            accel,
            normals: self.normals,
            uvs: self.uvs,
            meshes: self.meshes,
        }
    }
}

/// `mesh` with its vertices renumbered in the order its faces first use them (those no face
/// uses last, in their order): the same triangles, corner for corner. Neighbouring faces in
/// the list (a coarse face's children after loop subdivision, a strip of a scanned mesh)
/// then read neighbouring vertices, so that a triangle's corners, and those of a BVH leaf's
/// triangles, come from a few cache lines rather than from wherever the file or the
/// subdivision levels put them.
fn by_first_use(mut mesh: TriangleMesh) -> TriangleMesh {
    let n = mesh.positions.len();
    let mut new_of = vec![u32::MAX; n];
    let mut order: Vec<u32> = Vec::with_capacity(n);
    for i in &mut mesh.indices {
        let v = *i as usize;
        if new_of[v] == u32::MAX {
            new_of[v] = order.len() as u32;
            order.push(*i);
        }
        *i = new_of[v];
    }
    order.extend((0..n as u32).filter(|&v| new_of[v as usize] == u32::MAX));
    fn permute<T: Copy>(a: &mut Vec<T>, order: &[u32]) {
        if !a.is_empty() {
            *a = order.iter().map(|&v| a[v as usize]).collect();
        }
    }
    permute(&mut mesh.positions, &order);
    permute(&mut mesh.normals, &order);
    permute(&mut mesh.uvs, &order);
    mesh
}

impl SceneTris {
    /// Number of triangles (degenerate ones left out).
    pub fn len(&self) -> usize {
        self.accel.len()
    }

    /// True when there is no triangle.
    pub fn is_empty(&self) -> bool {
        self.accel.is_empty()
    }

    /// Bounds of all triangles.
    pub fn bounds(&self) -> Bounds3 {
        self.accel.bounds()
    }

    /// Nodes of the tree.
    pub fn node_count(&self) -> usize {
        self.accel.node_count()
    }

    /// Bytes of the vertices (positions, normals, (u, v)), the triangles' vertex indices and
    /// the mesh records.
    pub fn mesh_bytes(&self) -> usize {
        self.accel.geometry_bytes()
            + self.normals.capacity() * std::mem::size_of::<PackedVec3>()
            + self.uvs.capacity() * std::mem::size_of::<Vec2>()
            + self.meshes.capacity() * std::mem::size_of::<MeshRecord>()
    }

    /// Bytes of the tree.
    pub fn tree_bytes(&self) -> usize {
        self.accel.tree_bytes()
    }

    /// Adds `base` to the meshes' primitive record indices.
    pub(crate) fn offset_prims(&mut self, base: u32) {
        for m in &mut self.meshes {
            m.prim += base;
        }
    }

    /// The vertex positions of triangle `slot` (0 ≤ slot < [`SceneTris::len`]).
    pub fn vertices(&self, slot: u32) -> [Vec3; 3] {
        self.accel.vertices(slot)
    }

    /// The primitive record of triangle `slot`: its mesh's.
    pub fn prim(&self, slot: u32) -> u32 {
        self.mesh_of(self.accel.triangle(slot)[0]).prim
    }

    /// The mesh that vertex `v` belongs to.
    #[inline]
    fn mesh_of(&self, v: u32) -> &MeshRecord {
        let k = self.meshes.partition_point(|m| m.first_vertex <= v);
        &self.meshes[k - 1]
    }

    /// The nearest hit with 0 < t ≤ `t_max` (the ray's own end is not read): (triangle
    /// slot, hit).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32, pre: &TriangleRay) -> Option<(u32, ShapeHit)> {
        self.accel.intersect_to(ray, t_max, pre)
    }

    /// [`SceneTris::intersect`] for the rays of a packet, each ending at its `hits.t`: each
    /// lane's nearest hit is kept in `hits`, its id the triangle's slot.
    #[inline]
    pub fn intersect_packet(
        &self,
        rp: &crate::accel::packet::RayPacket,
        hits: &mut crate::accel::packet::PacketHits,
    ) {
        self.accel.intersect_packet(rp, hits)
    }

    /// True if any triangle is hit with 0 < t < `ray.t_max`.
    #[inline]
    pub fn intersect_any(&self, ray: &Ray, pre: &TriangleRay) -> bool {
        self.accel.intersect_any(ray, pre)
    }

    /// The full interaction of a hit on triangle `slot` found by [`SceneTris::intersect`] on
    /// the same ray, and the triangle's primitive record.
    pub fn interaction(&self, ray: &Ray, slot: u32, hit: &ShapeHit) -> (SurfaceInteraction, u32) {
        let (m, normals, uvs) = self.attributes(slot);
        let si = crate::shape::triangle_interaction(
            ray,
            hit,
            self.accel.vertices(slot),
            normals,
            uvs,
            m.flip_normal,
        );
        (si, m.prim)
    }

    /// pbrt-v4's shading derivatives of a hit on triangle `slot` whose interaction is `si`
    /// ([`triangle_shading_derivatives`]), for a bump map.
    pub fn shading_derivatives(&self, slot: u32, si: &SurfaceInteraction) -> ShadingDerivatives {
        let (_, normals, uvs) = self.attributes(slot);
        triangle_shading_derivatives(si, normals, uvs)
    }

    /// Triangle `slot`'s mesh, and its vertex normals and (u, v) when the mesh has them.
    #[inline(always)]
    #[allow(clippy::type_complexity)]
    fn attributes(&self, slot: u32) -> (&MeshRecord, Option<[Vec3; 3]>, Option<[Vec2; 3]>) {
        let v = self.accel.triangle(slot);
        let m = self.mesh_of(v[0]);
        let local = v.map(|i| (i - m.first_vertex) as usize);
        let normals =
            (m.normals != NONE).then(|| local.map(|i| self.normals[m.normals as usize + i].into()));
        let uvs = (m.uvs != NONE).then(|| local.map(|i| self.uvs[m.uvs as usize + i]));
        (m, normals, uvs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn renumbering_keeps_every_corner_and_follows_first_use() {
        // Six vertices, one unused (4), faces naming them out of order.
        let v = |i: u32| PackedVec3::new(i as f32, (i * i) as f32, -(i as f32));
        let mesh = TriangleMesh {
            positions: (0..6).map(v).collect(),
            normals: (0..6).map(|i| v(i + 10)).collect(),
            uvs: (0..6).map(|i| Vec2::new(i as f32, 0.5)).collect(),
            indices: vec![5, 2, 3, 3, 2, 0, 0, 1, 5],
            flip_normal: true,
        };
        let r = by_first_use(mesh.clone());
        assert_eq!(r.indices, vec![0, 1, 2, 2, 1, 3, 3, 4, 0]);
        // The unused vertex comes last.
        assert_eq!(r.positions[5], mesh.positions[4]);
        assert!(r.flip_normal);
        for (old, new) in mesh.indices.iter().zip(&r.indices) {
            let (o, n) = (*old as usize, *new as usize);
            assert_eq!(r.positions[n], mesh.positions[o]);
            assert_eq!(r.normals[n], mesh.normals[o]);
            assert_eq!(r.uvs[n], mesh.uvs[o]);
        }
        // Meshes without normals or (u, v) keep none.
        let bare = TriangleMesh {
            normals: vec![],
            uvs: vec![],
            ..mesh
        };
        let r = by_first_use(bare);
        assert!(r.normals.is_empty() && r.uvs.is_empty());
        assert_eq!(r.positions.len(), 6);
    }
}
