//! Displaced meshes, as pbrt-v4 makes a `plymesh` with a `displacement` texture
//! (`TriQuadMesh::Displace`):
//!
//! 1. Each triangle is refined by longest-edge bisection: while one of its edges is at least
//!    `edge_length` long (measured in render space, i.e. after the shape's transform), its
//!    longest edge is split at its midpoint, giving the two triangles (v₀, m, v₂), (m, v₁, v₂)
//!    (v₀v₁ the longest edge). A new vertex takes the mean of the edge's positions and (u, v),
//!    and `normalize(n₀ + n₁)` as its normal (the mesh's normals, or pbrt-v4's
//!    `ComputeNormals` of the mesh when it has none).
//! 2. Every vertex moves along its normal by the texture: `p' = p + d(p, uv) · n`.
//! 3. The normals are recomputed on the displaced mesh (`ComputeNormals`: at each vertex the
//!    normalised sum of the unit normals `(p₁ − p₀) × (p₂ − p₁)` of the triangles around it).
//!
//! An edge is split exactly when it is at least `edge_length` long (the longest edge of a
//! triangle that has one that long is at least that long), and always at its midpoint, so how
//! an edge of the input mesh is cut depends on that edge alone, not on the triangles beside
//! it: shared edges are cut alike and the mesh stays watertight. That is what lets the work go
//! in parallel and stay deterministic: the input's edges are cut first (each one's new
//! vertices numbered by a prefix sum over the sorted edge list), then each input triangle is
//! refined on its own (its interior vertices and triangles numbered by a prefix sum over the
//! triangles, counted in a first pass so that the output is allocated once, at its final size).
//! The output's triangles are pbrt-v4's, in its order (input triangle by input triangle, each
//! in the order of its recursion); only the vertex numbering differs.

use super::mesh::TriangleMesh;
use crate::math::{PackedVec3, Transform, Vec2, Vec3, cross, normalize};
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// The most triangles a displaced mesh may have: its vertex indices are 32-bit, and a mesh has
/// at most three vertices per triangle.
pub const MAX_DISPLACED_TRIANGLES: u64 = 1 << 30;

/// Deeper than this, a refinement is not converging: the edge length is below what the
/// coordinates' precision can split (or a coordinate is not finite).
const MAX_DEPTH: u32 = 160;

/// Input edges per parallel task, and input triangles per parallel task.
const EDGE_CHUNK: usize = 4096;
const TRIANGLE_CHUNK: usize = 64;

/// How a mesh is refined before it is displaced.
#[derive(Clone, Copy, Debug)]
pub struct Refinement {
    /// Object space → render space, where edges are measured.
    pub to_render: Transform,
    /// Edges at least this long are split (pbrt-v4's `edgelength` times
    /// `--displacementedgescale`).
    pub edge_length: f32,
    /// The most triangles the refined mesh may have (at most [`MAX_DISPLACED_TRIANGLES`]).
    pub max_triangles: u64,
}

/// Why a mesh could not be refined.
#[derive(Clone, Debug, PartialEq)]
pub enum DisplaceError {
    /// The mesh has no per-vertex (u, v) (pbrt-v4 requires them too).
    NoUvs,
    /// The refined mesh would have more than `max` triangles (`at_least` of them, when known
    /// before refining: the input's area over the largest triangle whose edges are all shorter
    /// than the edge length).
    TooManyTriangles {
        /// A lower bound of the count, when known.
        at_least: Option<u64>,
        /// The limit.
        max: u64,
    },
    /// The edge length is not positive, or too small for the coordinates' precision.
    BadEdgeLength,
}

impl std::fmt::Display for DisplaceError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            DisplaceError::NoUvs => f.write_str("a displaced mesh needs per-vertex (u, v)"),
            DisplaceError::TooManyTriangles {
                at_least: Some(n),
                max,
            } => write!(f, "the displaced mesh would have at least {n} triangles (limit {max})"),
            DisplaceError::TooManyTriangles { at_least: None, max } => {
                write!(f, "the displaced mesh would have more than {max} triangles")
            }
            DisplaceError::BadEdgeLength => f.write_str(
                "the edge length is not positive or too small to split the mesh's edges at its coordinates' precision",
            ),
        }
    }
}

impl std::error::Error for DisplaceError {}

/// A vertex while refining: position, normal, (u, v).
#[derive(Clone, Copy)]
struct Vtx {
    p: Vec3,
    n: Vec3,
    uv: Vec2,
}

/// The midpoint of edge (a, b): mean position and (u, v), `normalize(n_a + n_b)` (left as it is
/// when zero).
fn midpoint(a: &Vtx, b: &Vtx) -> Vtx {
    let n = a.n + b.n;
    Vtx {
        p: (a.p + b.p) / 2.0,
        n: if n.length_squared() > 0.0 {
            normalize(n)
        } else {
            n
        },
        uv: (a.uv + b.uv) / 2.0,
    }
}

/// An edge's key: its vertices, the smaller first.
fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// Vertex arrays read while refining.
#[derive(Clone, Copy)]
struct Verts<'a> {
    p: &'a [PackedVec3],
    n: &'a [PackedVec3],
    uv: &'a [Vec2],
}

impl Verts<'_> {
    fn get(&self, i: usize) -> Vtx {
        Vtx {
            p: self.p[i].into(),
            n: self.n[i].into(),
            uv: self.uv[i],
        }
    }
}

/// What is shared by every task of a refinement.
struct Rule {
    to_render: Transform,
    edge_length: f32,
    max_triangles: u64,
}

impl Rule {
    /// The render-space distance of two object-space points (symmetric to the bit: the
    /// difference only changes sign).
    fn distance(&self, a: Vec3, b: Vec3) -> f32 {
        (self.to_render.point(a) - self.to_render.point(b)).length()
    }

    /// Whether edge (a, b) is split: it is not shorter than the edge length (NaN is split, and
    /// stopped by the depth limit).
    fn splits(&self, a: Vec3, b: Vec3) -> bool {
        self.distance(a, b).partial_cmp(&self.edge_length) != Some(std::cmp::Ordering::Less)
    }

    /// How many vertices cutting the edge (a, b) makes: each piece not shorter than the edge
    /// length is halved, recursively. `left` is what the budget allows.
    fn count_splits(
        &self,
        a: &Vtx,
        b: &Vtx,
        depth: u32,
        left: &mut u64,
    ) -> Result<u64, DisplaceError> {
        if !self.splits(a.p, b.p) {
            return Ok(0);
        }
        if depth > MAX_DEPTH {
            return Err(DisplaceError::BadEdgeLength);
        }
        if *left == 0 {
            return Err(self.too_many(None));
        }
        *left -= 1;
        let m = midpoint(a, b);
        Ok(1 + self.count_splits(a, &m, depth + 1, left)?
            + self.count_splits(&m, b, depth + 1, left)?)
    }

    fn too_many(&self, at_least: Option<u64>) -> DisplaceError {
        DisplaceError::TooManyTriangles {
            at_least,
            max: self.max_triangles,
        }
    }
}

/// Vertex arrays written while refining: a piece of the output's.
struct VertsMut<'a> {
    p: &'a mut [PackedVec3],
    n: &'a mut [PackedVec3],
    uv: &'a mut [Vec2],
}

impl VertsMut<'_> {
    fn set(&mut self, i: usize, v: &Vtx) {
        self.p[i] = v.p.into();
        self.n[i] = v.n.into();
        self.uv[i] = v.uv;
    }

    /// The arrays cut into consecutive pieces of the given lengths.
    fn pieces(self, lens: &[usize]) -> Vec<Self> {
        let (p, n, uv) = (
            pieces(self.p, lens),
            pieces(self.n, lens),
            pieces(self.uv, lens),
        );
        p.into_iter()
            .zip(n)
            .zip(uv)
            .map(|((p, n), uv)| VertsMut { p, n, uv })
            .collect()
    }
}

/// The new vertices of the edge (lo, hi) written to `out` from `at` on, in pre-order (the
/// midpoint, then those of its first half, then of its second); `input` holds the input's
/// vertices. Returns where the next edge's start.
fn cut_edge(
    rule: &Rule,
    input: Verts<'_>,
    (lo, hi): (u32, u32),
    out: &mut VertsMut<'_>,
    at: usize,
) -> usize {
    fn go(rule: &Rule, a: Vtx, b: Vtx, out: &mut VertsMut<'_>, next: &mut usize) {
        if !rule.splits(a.p, b.p) {
            return;
        }
        let m = midpoint(&a, &b);
        out.set(*next, &m);
        *next += 1;
        go(rule, a, m, out, next);
        go(rule, m, b, out, next);
    }
    let mut next = at;
    go(
        rule,
        input.get(lo as usize),
        input.get(hi as usize),
        out,
        &mut next,
    );
    next
}

/// One input triangle's refinement: its interior vertices (numbered from `first_local` on)
/// and its triangles, with a map of the edges already split.
struct Local<'a> {
    rule: &'a Rule,
    /// The input's vertices and the edges' new vertices (`first_local` of them).
    head: Verts<'a>,
    first_local: u32,
    edges: &'a [(u32, u32)],
    edge_first: &'a [u32],
    split: HashMap<(u32, u32), u32>,
    verts: Vec<Vtx>,
    tris: Vec<u32>,
}

impl<'a> Local<'a> {
    fn new(
        rule: &'a Rule,
        head: Verts<'a>,
        first_local: u32,
        edges: &'a [(u32, u32)],
        edge_first: &'a [u32],
    ) -> Local<'a> {
        Local {
            rule,
            head,
            first_local,
            edges,
            edge_first,
            split: HashMap::new(),
            verts: Vec::new(),
            tris: Vec::new(),
        }
    }

    fn vertex(&self, h: u32) -> Vtx {
        if h < self.first_local {
            self.head.get(h as usize)
        } else {
            self.verts[(h - self.first_local) as usize]
        }
    }

    /// Refines triangle (a, b, c) of the input, from a clean state.
    fn triangle(&mut self, [a, b, c]: [u32; 3]) -> Result<(), DisplaceError> {
        self.split.clear();
        self.verts.clear();
        self.tris.clear();
        for (x, y) in [(a, b), (b, c), (c, a)] {
            let (lo, hi) = key(x, y);
            let e = self
                .edges
                .binary_search(&(lo, hi))
                .expect("every edge of the input is listed");
            let mut next = self.edge_first[e];
            self.seed(lo, hi, &mut next);
        }
        self.refine(a, b, c, 0)
    }

    /// Records the splits of the input's edge (x, y) made by [`cut_edge`] (the same pre-order,
    /// numbered from `next`).
    fn seed(&mut self, x: u32, y: u32, next: &mut u32) {
        if !self.rule.splits(self.vertex(x).p, self.vertex(y).p) {
            return;
        }
        let m = *next;
        *next += 1;
        self.split.insert(key(x, y), m);
        self.seed(x, m, next);
        self.seed(m, y, next);
    }

    /// pbrt-v4's `Refine`: keeps (v0, v1, v2) when its three edges are shorter than the edge
    /// length, else halves its longest edge and refines both halves.
    fn refine(&mut self, v0: u32, v1: u32, v2: u32, depth: u32) -> Result<(), DisplaceError> {
        let (p0, p1, p2) = (self.vertex(v0).p, self.vertex(v1).p, self.vertex(v2).p);
        let rule = self.rule;
        let (d01, d12, d20) = (
            rule.distance(p0, p1),
            rule.distance(p1, p2),
            rule.distance(p2, p0),
        );
        let l = rule.edge_length;
        if d01 < l && d12 < l && d20 < l {
            if self.tris.len() as u64 >= 3 * rule.max_triangles {
                return Err(rule.too_many(None));
            }
            self.tris.extend([v0, v1, v2]);
            return Ok(());
        }
        if depth > MAX_DEPTH {
            return Err(DisplaceError::BadEdgeLength);
        }
        // The longest edge first (pbrt-v4's order, ties included).
        let v = if d01 > d12 {
            if d01 > d20 {
                [v0, v1, v2]
            } else {
                [v2, v0, v1]
            }
        } else if d12 > d20 {
            [v1, v2, v0]
        } else {
            [v2, v0, v1]
        };
        let k = key(v[0], v[1]);
        let mid = match self.split.get(&k) {
            Some(&m) => m,
            None => {
                let m = self.first_local + self.verts.len() as u32;
                let vm = midpoint(&self.vertex(v[0]), &self.vertex(v[1]));
                self.verts.push(vm);
                self.split.insert(k, m);
                m
            }
        };
        self.refine(v[0], mid, v[2], depth + 1)?;
        self.refine(mid, v[1], v[2], depth + 1)
    }
}

/// `data` cut into consecutive pieces of the given lengths.
fn pieces<'a, T>(mut data: &'a mut [T], lens: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::new();
    for &n in lens {
        let (a, b) = std::mem::take(&mut data).split_at_mut(n);
        out.push(a);
        data = b;
    }
    out
}

/// Exclusive prefix sums of `counts`, and their total.
fn prefix(counts: impl IntoIterator<Item = u64>) -> (Vec<u64>, u64) {
    let mut total = 0;
    let firsts = counts
        .into_iter()
        .map(|c| {
            let f = total;
            total += c;
            f
        })
        .collect();
    (firsts, total)
}

/// pbrt-v4's `ComputeNormals`: at each vertex, the normalised sum of the unit normals
/// `(p₁ − p₀) × (p₂ − p₁)` of the triangles around it (zero where there are none). Summed in
/// triangle order, so the result does not depend on threads.
pub fn vertex_normals(positions: &[PackedVec3], indices: &[u32]) -> Vec<PackedVec3> {
    let mut n = vec![PackedVec3::ZERO; positions.len()];
    for t in indices.chunks_exact(3) {
        let p = |k: usize| Vec3::from(positions[t[k] as usize]);
        let c = cross(p(1) - p(0), p(2) - p(1));
        if c.length_squared() > 0.0 {
            let c = PackedVec3::from(normalize(c));
            for &v in t {
                n[v as usize] += c;
            }
        }
    }
    n.par_iter_mut().for_each(|v| {
        if v.length_squared() > 0.0 {
            *v = normalize(Vec3::from(*v)).into();
        }
    });
    n
}

/// The mesh refined until every edge is shorter than `r.edge_length` in render space (step 1
/// of the module's description), in object space, with interpolated normals and (u, v); not
/// displaced yet. Runs on all threads; the result does not depend on their number.
pub fn refine(mesh: &TriangleMesh, r: &Refinement) -> Result<TriangleMesh, DisplaceError> {
    if mesh.uvs.is_empty() && !mesh.positions.is_empty() {
        return Err(DisplaceError::NoUvs);
    }
    if r.edge_length.is_nan() || r.edge_length <= 0.0 {
        return Err(DisplaceError::BadEdgeLength);
    }
    let rule = Rule {
        to_render: r.to_render,
        edge_length: r.edge_length,
        max_triangles: r.max_triangles.min(MAX_DISPLACED_TRIANGLES),
    };
    lower_bound_check(mesh, &rule)?;
    let normals = if mesh.normals.is_empty() {
        vertex_normals(&mesh.positions, &mesh.indices)
    } else {
        mesh.normals.clone()
    };
    let input = Verts {
        p: &mesh.positions,
        n: &normals,
        uv: &mesh.uvs,
    };
    let n_input = mesh.positions.len();

    // The input's edges, sorted, and how many vertices cutting each one makes.
    let mut edges: Vec<(u32, u32)> = mesh
        .indices
        .par_chunks_exact(3)
        .flat_map_iter(|t| [key(t[0], t[1]), key(t[1], t[2]), key(t[2], t[0])])
        .collect();
    edges.par_sort_unstable();
    edges.dedup();
    let vertex_budget = 3 * rule.max_triangles;
    let spent = AtomicU64::new(0);
    let edge_counts = edges
        .par_iter()
        .map(|&(a, b)| {
            let mut left = vertex_budget;
            let n =
                rule.count_splits(&input.get(a as usize), &input.get(b as usize), 0, &mut left)?;
            if spent.fetch_add(n, Ordering::Relaxed) + n > vertex_budget {
                return Err(rule.too_many(None));
            }
            Ok(n)
        })
        .collect::<Result<Vec<u64>, DisplaceError>>()?;
    let (edge_firsts, n_edge_verts) = prefix(edge_counts.iter().copied());
    let first_local = n_input as u64 + n_edge_verts;
    if first_local > u32::MAX as u64 {
        return Err(rule.too_many(None));
    }
    let edge_first: Vec<u32> = edge_firsts
        .iter()
        .map(|&f| (n_input as u64 + f) as u32)
        .collect();
    drop(edge_firsts);

    // The output's vertices: the input's, then the edges' (cut chunk by chunk).
    let head_len = first_local as usize;
    let mut positions = Vec::with_capacity(head_len);
    let mut out_normals = Vec::with_capacity(head_len);
    let mut uvs = Vec::with_capacity(head_len);
    positions.extend_from_slice(&mesh.positions);
    out_normals.extend_from_slice(&normals);
    uvs.extend_from_slice(&mesh.uvs);
    drop(normals);
    positions.resize(head_len, PackedVec3::ZERO);
    out_normals.resize(head_len, PackedVec3::ZERO);
    uvs.resize(head_len, Vec2::ZERO);
    {
        let (input, edge_part) = split_verts(&mut positions, &mut out_normals, &mut uvs, n_input);
        let chunk_lens: Vec<usize> = edge_counts
            .chunks(EDGE_CHUNK)
            .map(|c| c.iter().sum::<u64>() as usize)
            .collect();
        edge_part
            .pieces(&chunk_lens)
            .into_par_iter()
            .zip(edges.par_chunks(EDGE_CHUNK))
            .for_each(|(mut out, es)| {
                let mut at = 0;
                for &e in es {
                    at = cut_edge(&rule, input, e, &mut out, at);
                }
                debug_assert_eq!(at, out.p.len());
            });
    }
    drop(edge_counts);

    // Pass 1: each input triangle's count of triangles and interior vertices.
    let tris: Vec<[u32; 3]> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let (edges, edge_first) = (&edges[..], &edge_first[..]);
    let made = AtomicU64::new(0);
    let over = AtomicBool::new(false);
    let head = Verts {
        p: &positions,
        n: &out_normals,
        uv: &uvs,
    };
    let counts = tris
        .par_chunks(TRIANGLE_CHUNK)
        .map(|chunk| {
            let mut l = Local::new(&rule, head, first_local as u32, edges, edge_first);
            let (mut n_tris, mut n_verts) = (0u64, 0u64);
            for &t in chunk {
                if over.load(Ordering::Relaxed) {
                    return Err(rule.too_many(None));
                }
                l.triangle(t)?;
                let n = (l.tris.len() / 3) as u64;
                if made.fetch_add(n, Ordering::Relaxed) + n > rule.max_triangles {
                    over.store(true, Ordering::Relaxed);
                    return Err(rule.too_many(None));
                }
                n_tris += n;
                n_verts += l.verts.len() as u64;
            }
            Ok((n_tris, n_verts))
        })
        .collect::<Result<Vec<(u64, u64)>, DisplaceError>>()?;
    let (_, n_tris) = prefix(counts.iter().map(|c| c.0));
    let (chunk_first, n_interior) = prefix(counts.iter().map(|c| c.1));
    let n_vertices = first_local + n_interior;
    if n_vertices > u32::MAX as u64 {
        return Err(rule.too_many(None));
    }

    // Pass 2: the same refinement, written to the output at its place.
    let n_vertices = n_vertices as usize;
    positions.reserve_exact(n_vertices - head_len);
    out_normals.reserve_exact(n_vertices - head_len);
    uvs.reserve_exact(n_vertices - head_len);
    positions.resize(n_vertices, PackedVec3::ZERO);
    out_normals.resize(n_vertices, PackedVec3::ZERO);
    uvs.resize(n_vertices, Vec2::ZERO);
    let mut indices = vec![0u32; 3 * n_tris as usize];
    {
        let (head, interior) = split_verts(&mut positions, &mut out_normals, &mut uvs, head_len);
        let vert_lens: Vec<usize> = counts.iter().map(|c| c.1 as usize).collect();
        let index_lens: Vec<usize> = counts.iter().map(|c| 3 * c.0 as usize).collect();
        interior
            .pieces(&vert_lens)
            .into_par_iter()
            .zip(pieces(&mut indices, &index_lens))
            .zip(tris.par_chunks(TRIANGLE_CHUNK))
            .zip(chunk_first)
            .for_each(|(((mut vout, iout), chunk), first)| {
                let mut l = Local::new(&rule, head, first_local as u32, edges, edge_first);
                let (mut va, mut ia) = (0, 0);
                for &t in chunk {
                    l.triangle(t).expect("the first pass refined it");
                    // Interior handle h is vertex first_local + (this triangle's first) + h − first_local.
                    let base = first_local + first + va as u64;
                    for &h in &l.tris {
                        iout[ia] = if h < l.first_local {
                            h
                        } else {
                            (base + (h - l.first_local) as u64) as u32
                        };
                        ia += 1;
                    }
                    for v in &l.verts {
                        vout.set(va, v);
                        va += 1;
                    }
                }
            });
    }
    Ok(TriangleMesh {
        positions,
        normals: out_normals,
        uvs,
        indices,
        flip_normal: mesh.flip_normal,
    })
}

/// The vertex arrays split at `at`: the part before it to read, the rest to write.
fn split_verts<'a>(
    p: &'a mut [PackedVec3],
    n: &'a mut [PackedVec3],
    uv: &'a mut [Vec2],
    at: usize,
) -> (Verts<'a>, VertsMut<'a>) {
    let (p0, p1) = p.split_at_mut(at);
    let (n0, n1) = n.split_at_mut(at);
    let (uv0, uv1) = uv.split_at_mut(at);
    (
        Verts {
            p: p0,
            n: n0,
            uv: uv0,
        },
        VertsMut {
            p: p1,
            n: n1,
            uv: uv1,
        },
    )
}

/// Fails early when the input's render-space area alone needs more triangles than allowed: a
/// triangle whose edges are all shorter than l has an area below √3/4·l² (the equilateral
/// one's), and refining keeps the area.
fn lower_bound_check(mesh: &TriangleMesh, rule: &Rule) -> Result<(), DisplaceError> {
    let area: f64 = mesh
        .indices
        .par_chunks_exact(3)
        .map(|t| {
            let p = |k: usize| rule.to_render.point(mesh.positions[t[k] as usize].into());
            0.5 * cross(p(1) - p(0), p(2) - p(0)).length() as f64
        })
        .sum();
    let l = rule.edge_length as f64;
    let at_least = (area / (3f64.sqrt() / 4.0 * l * l)).floor();
    if at_least > rule.max_triangles as f64 {
        let n = if at_least < u64::MAX as f64 {
            at_least as u64
        } else {
            u64::MAX
        };
        return Err(rule.too_many(Some(n)));
    }
    Ok(())
}

/// Steps 2 and 3 of the module's description on a refined mesh: each vertex moved by
/// `p' = p + d(p, uv) · n` (on all threads; `d` is the displacement texture looked up at the
/// object-space position and (u, v) before the move), then the normals recomputed
/// ([`vertex_normals`]).
pub fn displace(mesh: &mut TriangleMesh, d: impl Fn(Vec3, Vec2) -> f32 + Sync) {
    mesh.positions
        .par_iter_mut()
        .zip(mesh.normals.par_iter())
        .zip(mesh.uvs.par_iter())
        .for_each(|((p, &n), &uv)| {
            let pv = Vec3::from(*p);
            *p = (pv + d(pv, uv) * Vec3::from(n)).into();
        });
    mesh.normals = vertex_normals(&mesh.positions, &mesh.indices);
}

#[cfg(test)]
mod tests;
