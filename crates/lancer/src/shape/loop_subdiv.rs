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
use rayon::prelude::*;

/// Faces across an edge: its (up to two) opposite vertices and how many faces share it.
#[derive(Clone, Copy, Debug, PartialEq)]
struct EdgeFaces {
    opposite: [u32; 2],
    count: u32,
}

/// An edge's vertices, smaller first, packed so that the packed keys sort as the pairs do.
fn key(a: u32, b: u32) -> u64 {
    ((a.min(b) as u64) << 32) | a.max(b) as u64
}

/// Loop's β for a vertex of valence n.
fn beta(n: usize) -> f32 {
    if n == 3 {
        3.0 / 16.0
    } else {
        3.0 / (8.0 * n as f32)
    }
}

/// Rows of neighbours per vertex, stored one after another: row v is
/// `items[start[v]..start[v + 1]]`.
struct Rows {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Rows {
    /// The rows of `n` vertices holding, for each edge (a, b) that `keep` accepts, b in row a
    /// and a in row b. With the edges in ascending order each row comes out ascending: row v
    /// receives the smaller neighbours (edges (x, v), ascending x) before the larger ones
    /// (edges (v, y), ascending y), and every (x, v) sorts before every (v, y).
    fn new(n: usize, edges: impl Iterator<Item = (u32, u32)> + Clone) -> Rows {
        let mut start = vec![0u32; n + 1];
        for (a, b) in edges.clone() {
            start[a as usize + 1] += 1;
            start[b as usize + 1] += 1;
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[n] as usize];
        for (a, b) in edges {
            items[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            items[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        Rows { start, items }
    }

    #[inline]
    fn row(&self, v: usize) -> &[u32] {
        &self.items[self.start[v] as usize..self.start[v + 1] as usize]
    }
}

/// The mesh's edges with the faces on them, and each vertex's one-ring and boundary
/// neighbours (ascending, so that sums over them are taken in a fixed order). Built by sorting
/// the faces' half-edges rather than hashing them: the same edges in the same order, without a
/// hash map or a list per vertex.
struct Topology {
    /// The edges (a < b) in ascending order, with the faces across them.
    edges: Vec<((u32, u32), EdgeFaces)>,
    /// Per half-edge (edge k of face f, from its vertex k to vertex k + 1, at 3f + k), the
    /// index of its edge in `edges`.
    edge_of: Vec<u32>,
    ring: Rows,
    boundary: Rows,
}

impl Topology {
    fn new(n_vertices: usize, indices: &[u32]) -> Topology {
        // (edge, half-edge): sorted, the half-edges of each edge are together, in face order.
        let mut half: Vec<(u64, u32)> = indices
            .par_chunks_exact(3)
            .enumerate()
            .flat_map_iter(|(f, t)| {
                (0..3).map(move |k| (key(t[k], t[(k + 1) % 3]), (3 * f + k) as u32))
            })
            .collect();
        half.par_sort_unstable();
        let opposite = |h: u32| {
            let (f, k) = (h as usize / 3, h as usize % 3);
            indices[3 * f + (k + 2) % 3]
        };
        let mut edges = Vec::with_capacity(half.len() / 2 + 1);
        let mut edge_of = vec![0u32; half.len()];
        for run in half.chunk_by(|x, y| x.0 == y.0) {
            let e = edges.len() as u32;
            let first = opposite(run[0].1);
            let second = run.get(1).map_or(first, |h| opposite(h.1));
            let (a, b) = ((run[0].0 >> 32) as u32, run[0].0 as u32);
            edges.push((
                (a, b),
                EdgeFaces {
                    opposite: [first, second],
                    count: run.len() as u32,
                },
            ));
            for h in run {
                edge_of[h.1 as usize] = e;
            }
        }
        let ring = Rows::new(n_vertices, edges.iter().map(|e| e.0));
        let boundary = Rows::new(
            n_vertices,
            edges.iter().filter(|e| e.1.count != 2).map(|e| e.0),
        );
        Topology {
            edges,
            edge_of,
            ring,
            boundary,
        }
    }

    /// Where vertex `v` goes: smoothed (`limit` false) or on the limit surface.
    fn even(&self, p: &[Vec3], v: usize, limit: bool) -> Vec3 {
        let bnd = self.boundary.row(v);
        if !bnd.is_empty() {
            if bnd.len() != 2 {
                return p[v]; // a corner or a non-manifold vertex stays
            }
            let w = if limit { 0.2 } else { 0.125 };
            return (1.0 - 2.0 * w) * p[v] + w * (p[bnd[0] as usize] + p[bnd[1] as usize]);
        }
        let ring = self.ring.row(v);
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

    /// Every vertex moved by [`Topology::even`] (in parallel: each on its own).
    fn evens(&self, p: &[Vec3], limit: bool) -> Vec<Vec3> {
        (0..p.len())
            .into_par_iter()
            .map(|v| self.even(p, v, limit))
            .collect()
    }
}

/// `mesh` subdivided `levels` times and moved to the limit surface, with smooth normals.
/// Per-vertex normals and (u, v) of the input are not carried over (pbrt does the same).
pub fn loop_subdivide(mesh: &TriangleMesh, levels: u32) -> TriangleMesh {
    let mut p: Vec<Vec3> = mesh.positions.iter().map(|&q| q.into()).collect();
    let mut idx = mesh.indices.clone();
    for _ in 0..levels {
        let topo = Topology::new(p.len(), &idx);
        let mut next = topo.evens(&p, false);
        // One new vertex per edge, numbered in sorted edge order (edge e is vertex
        // p.len() + e).
        let base = next.len() as u32;
        next.par_extend(topo.edges.par_iter().map(|&((a, b), e)| {
            let (pa, pb) = (p[a as usize], p[b as usize]);
            if e.count == 2 {
                0.375 * (pa + pb) + 0.125 * (p[e.opposite[0] as usize] + p[e.opposite[1] as usize])
            } else {
                0.5 * (pa + pb)
            }
        }));
        let next_idx: Vec<u32> = idx
            .par_chunks_exact(3)
            .zip(topo.edge_of.par_chunks_exact(3))
            .flat_map_iter(|(f, e)| {
                let (a, b, c) = (f[0], f[1], f[2]);
                let [ab, bc, ca] = [e[0], e[1], e[2]].map(|e| base + e);
                [a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca]
            })
            .collect();
        p = next;
        idx = next_idx;
    }
    let limit = Topology::new(p.len(), &idx).evens(&p, true);
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
                    .iter()
                    .all(|e| e.1.count == 2)
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
    fn the_topology_matches_a_direct_count_of_the_faces() {
        // A strip of two quads, a fan closing on vertex 0, and an edge (0, 1) shared by
        // three faces (non-manifold), with a vertex (9) on no face.
        let idx: Vec<u32> = vec![
            0, 1, 2, 1, 3, 2, 2, 3, 4, 3, 5, 4, 0, 6, 1, 1, 0, 7, 0, 8, 6, 0, 2, 8,
        ];
        let n = 10;
        let topo = Topology::new(n, &idx);
        // Each edge's faces, by brute force over every face.
        let mut expected: Vec<((u32, u32), Vec<u32>)> = Vec::new();
        for (f, t) in idx.chunks_exact(3).enumerate() {
            for k in 0..3 {
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let e = (a.min(b), a.max(b));
                match expected.iter_mut().find(|x| x.0 == e) {
                    Some(x) => x.1.push(c),
                    None => expected.push((e, vec![c])),
                }
                // The half-edge names its edge.
                assert_eq!(topo.edges[topo.edge_of[3 * f + k] as usize].0, e);
            }
        }
        expected.sort();
        assert_eq!(topo.edges.len(), expected.len());
        for ((e, faces), (want, opp)) in topo.edges.iter().zip(&expected) {
            assert_eq!(e, want);
            assert_eq!(faces.count as usize, opp.len());
            assert_eq!(faces.opposite[0], opp[0]);
            assert_eq!(faces.opposite[1], *opp.get(1).unwrap_or(&opp[0]));
        }
        for v in 0..n as u32 {
            let mut ring: Vec<u32> = Vec::new();
            let mut bnd: Vec<u32> = Vec::new();
            for (e, opp) in &expected {
                let other = if e.0 == v {
                    e.1
                } else if e.1 == v {
                    e.0
                } else {
                    continue;
                };
                ring.push(other);
                if opp.len() != 2 {
                    bnd.push(other);
                }
            }
            ring.sort_unstable();
            bnd.sort_unstable();
            assert_eq!(topo.ring.row(v as usize), ring, "ring of {v}");
            assert_eq!(topo.boundary.row(v as usize), bnd, "boundary of {v}");
        }
        assert!(topo.ring.row(9).is_empty());
        assert_eq!(
            topo.edges[topo.edge_of[0] as usize].1.count, 3,
            "edge (0, 1)"
        );
    }

    #[test]
    fn the_result_is_the_same_on_every_run() {
        // The half-edges are sorted in parallel: ties cannot reorder them (each is unique).
        let a = loop_subdivide(&tetrahedron(), 2);
        let b = loop_subdivide(&tetrahedron(), 2);
        assert_eq!(a, b);
    }
}
