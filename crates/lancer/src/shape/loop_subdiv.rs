//! Loop subdivision (Loop 1987), as pbrt's `loopsubdiv` shape uses it: each level splits every
//! triangle in four and smooths the vertices; after the last level the vertices are moved to
//! the limit surface.
//!
//! The rules, for a vertex v with n neighbours (its one-ring):
//! - an old interior vertex becomes (1 − nβ)·v + β·Σ ring, β = 3/16 if n = 3 else 3/(8n);
//! - an old boundary vertex becomes ¾·v + ⅛·(a + b), a and b its two boundary neighbours;
//! - a new vertex on an interior edge (v₀, v₁) with opposite vertices v₂, v₃ is
//!   ⅜·(v₀ + v₁) + ⅛·(v₂ + v₃), on a boundary edge ½·(v₀ + v₁);
//! - on the limit surface an interior vertex is at (1 − nγ)·v + γ·Σ ring with
//!   γ = 1/(n + 3/(8β)), a boundary one at ⅗·v + ⅕·(a + b).
//!
//! Normals are the area-weighted averages of the faces around each vertex of the final mesh
//! (pbrt computes the limit surface's tangents instead; at three levels the two agree closely).
//! Non-manifold edges (more than two faces) are treated like boundary edges.

use super::mesh::TriangleMesh;
use crate::math::{PackedVec3, Vec3, cross};
use std::collections::HashMap;

/// Faces across an edge: its (up to two) opposite vertices and how many faces share it.
#[derive(Clone, Copy)]
struct EdgeFaces {
    opposite: [u32; 2],
    count: u32,
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// Loop's β for a vertex of valence n.
fn beta(n: usize) -> f32 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f32)
    }
}

/// The mesh's edges with the faces on them, and each vertex's one-ring and boundary
/// neighbours.
struct Topology {
    edges: HashMap<(u32, u32), EdgeFaces>,
    ring: Vec<Vec<u32>>,
    boundary: Vec<Vec<u32>>,
}

impl Topology {
    fn new(n_vertices: usize, indices: &[u32]) -> Topology {
        let mut edges: HashMap<(u32, u32), EdgeFaces> = HashMap::new();
        for f in indices.chunks_exact(3) {
            for k in 0..3 {
                let (a, b, c) = (f[k], f[(k + 1) % 3], f[(k + 2) % 3]);
                let e = edges.entry(key(a, b)).or_insert(EdgeFaces {
                    opposite: [c, c],
                    count: 0,
                });
                if e.count < 2 {
                    e.opposite[e.count as usize] = c;
                }
                e.count += 1;
            }
        }
        let mut ring = vec![Vec::new(); n_vertices];
        let mut boundary = vec![Vec::new(); n_vertices];
        for (&(a, b), e) in &edges {
            ring[a as usize].push(b);
            ring[b as usize].push(a);
            if e.count != 2 {
                boundary[a as usize].push(b);
                boundary[b as usize].push(a);
            }
        }
        // Hash-map order must not leak into the results: sums are taken in a fixed order.
        for r in ring.iter_mut().chain(boundary.iter_mut()) {
            r.sort_unstable();
        }
        Topology {
            edges,
            ring,
            boundary,
        }
    }

    /// Where vertex `v` goes: smoothed (`limit` false) or on the limit surface.
    fn even(&self, p: &[Vec3], v: usize, limit: bool) -> Vec3 {
        let bnd = &self.boundary[v];
        if !bnd.is_empty() {
            if bnd.len() != 2 {
                return p[v]; // a corner or a non-manifold vertex stays
            }
            let w = if limit { 0.2 } else { 0.125 };
            return (1.0 - 2.0 * w) * p[v] + w * (p[bnd[0] as usize] + p[bnd[1] as usize]);
        }
        let ring = &self.ring[v];
        let n = ring.len();
        if n == 0 {
            return p[v];
        }
        let b = beta(n);
        let w = if limit {
            1.0 / (n as f32 + 3.0 / (8.0 * b))
        } else {
            b
        };
        let sum: Vec3 = ring.iter().map(|&u| p[u as usize]).sum();
        (1.0 - n as f32 * w) * p[v] + w * sum
    }
}

/// `mesh` subdivided `levels` times and moved to the limit surface, with smooth normals.
/// Per-vertex normals and (u, v) of the input are not carried over (pbrt does the same).
pub fn loop_subdivide(mesh: &TriangleMesh, levels: u32) -> TriangleMesh {
    let mut p: Vec<Vec3> = mesh.positions.iter().map(|&q| q.into()).collect();
    let mut idx = mesh.indices.clone();
    for _ in 0..levels {
        let topo = Topology::new(p.len(), &idx);
        let mut next: Vec<Vec3> = (0..p.len()).map(|v| topo.even(&p, v, false)).collect();
        // One new vertex per edge, numbered in sorted edge order so the result is the same
        // whatever the hash map's order.
        let mut edges: Vec<(&(u32, u32), &EdgeFaces)> = topo.edges.iter().collect();
        edges.sort_unstable_by_key(|(k, _)| **k);
        let mut edge_vertex: HashMap<(u32, u32), u32> = HashMap::with_capacity(edges.len());
        for (&(a, b), e) in edges {
            let (pa, pb) = (p[a as usize], p[b as usize]);
            let q = if e.count == 2 {
                0.375 * (pa + pb) + 0.125 * (p[e.opposite[0] as usize] + p[e.opposite[1] as usize])
            } else {
                0.5 * (pa + pb)
            };
            edge_vertex.insert((a, b), next.len() as u32);
            next.push(q);
        }
        let mut next_idx = Vec::with_capacity(idx.len() * 4);
        for f in idx.chunks_exact(3) {
            let (a, b, c) = (f[0], f[1], f[2]);
            let ab = edge_vertex[&key(a, b)];
            let bc = edge_vertex[&key(b, c)];
            let ca = edge_vertex[&key(c, a)];
            next_idx.extend_from_slice(&[a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca]);
        }
        p = next;
        idx = next_idx;
    }
    let topo = Topology::new(p.len(), &idx);
    let limit: Vec<Vec3> = (0..p.len()).map(|v| topo.even(&p, v, true)).collect();
    // Area-weighted vertex normals: the cross product's length is twice the face's area.
    let mut normals = vec![Vec3::ZERO; limit.len()];
    for f in idx.chunks_exact(3) {
        let [a, b, c] = [f[0] as usize, f[1] as usize, f[2] as usize];
        let n = cross(limit[b] - limit[a], limit[c] - limit[a]);
        normals[a] += n;
        normals[b] += n;
        normals[c] += n;
    }
    for n in &mut normals {
        *n = n.normalize_or_zero();
    }
    // A vertex whose faces cancel out gets no normal; then the mesh has none at all.
    let normals = if normals.iter().all(|n| *n != Vec3::ZERO) {
        normals.into_iter().map(PackedVec3::from).collect()
    } else {
        Vec::new()
    };
    TriangleMesh {
        positions: limit.into_iter().map(PackedVec3::from).collect(),
        normals,
        uvs: Vec::new(),
        indices: idx,
        flip_normal: mesh.flip_normal,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetrahedron() -> TriangleMesh {
        TriangleMesh {
            positions: vec![
                PackedVec3::new(1.0, 1.0, 1.0),
                PackedVec3::new(1.0, -1.0, -1.0),
                PackedVec3::new(-1.0, 1.0, -1.0),
                PackedVec3::new(-1.0, -1.0, 1.0),
            ],
            normals: vec![],
            uvs: vec![],
            // Outward-facing winding.
            indices: vec![0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2],
            flip_normal: false,
        }
    }

    #[test]
    fn each_level_quadruples_the_faces_and_the_mesh_stays_closed() {
        let m = tetrahedron();
        for levels in 0..4 {
            let s = loop_subdivide(&m, levels);
            assert_eq!(s.indices.len(), m.indices.len() * 4usize.pow(levels));
            s.validate().unwrap();
            // Euler characteristic of a closed genus-0 surface: V − E + F = 2.
            let f = s.indices.len() / 3;
            let e = 3 * f / 2;
            assert_eq!(s.positions.len() as i64 - e as i64 + f as i64, 2);
            assert!(
                Topology::new(s.positions.len(), &s.indices)
                    .edges
                    .values()
                    .all(|e| e.count == 2)
            );
        }
    }

    #[test]
    fn a_closed_surface_shrinks_smoothly_inside_its_control_mesh() {
        // Loop surfaces lie inside the convex hull of their control points, and a regular
        // tetrahedron's limit surface is symmetric about its centre and rounder than it
        // (one level already pulls each corner to v/4: 7/16·v + 3/16·(−v)).
        let s = loop_subdivide(&tetrahedron(), 3);
        let r: Vec<f32> = s.positions.iter().map(|p| p.length()).collect();
        let (lo, hi) = r
            .iter()
            .fold((f32::MAX, 0.0f32), |(l, h), &x| (l.min(x), h.max(x)));
        assert!(hi < 3f32.sqrt(), "outside the hull: {hi}");
        assert!(lo > 0.2 && hi / lo < 1.5, "radii {lo}..{hi}");
        let centre = s.positions.iter().sum::<PackedVec3>() / s.positions.len() as f32;
        assert!(centre.length() < 1e-4, "{centre}");
        // Normals point outwards, as the faces do.
        for (p, n) in s.positions.iter().zip(&s.normals) {
            assert!(p.normalize().dot(*n) > 0.5, "{p} {n}");
        }
    }

    #[test]
    fn a_flat_patch_stays_flat_and_keeps_its_boundary_on_its_edges() {
        // Two triangles in z = 0: every rule is an affine combination, so z stays 0; boundary
        // vertices only mix with boundary neighbours, so the square's corners stay and its
        // edges stay straight.
        let quad = TriangleMesh {
            positions: vec![
                PackedVec3::new(0.0, 0.0, 0.0),
                PackedVec3::new(1.0, 0.0, 0.0),
                PackedVec3::new(1.0, 1.0, 0.0),
                PackedVec3::new(0.0, 1.0, 0.0),
            ],
            normals: vec![],
            uvs: vec![],
            indices: vec![0, 1, 2, 0, 2, 3],
            flip_normal: false,
        };
        let s = loop_subdivide(&quad, 2);
        s.validate().unwrap();
        for p in &s.positions {
            assert_eq!(p.z, 0.0);
            assert!((-1e-6..=1.0 + 1e-6).contains(&p.x) && (-1e-6..=1.0 + 1e-6).contains(&p.y));
        }
        for n in &s.normals {
            assert!((n.z - 1.0).abs() < 1e-6, "{n}");
        }
    }

    #[test]
    fn the_result_does_not_depend_on_hash_order() {
        let a = loop_subdivide(&tetrahedron(), 2);
        let b = loop_subdivide(&tetrahedron(), 2);
        assert_eq!(a, b);
    }
}
