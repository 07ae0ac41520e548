use super::*;
use crate::math::Vec3;
use std::collections::HashMap;

/// A flat n × n grid over [0, 1]² at z = 0, (u, v) = (x, y), normals +z.
fn grid(n: u32) -> TriangleMesh {
    let mut m = TriangleMesh::default();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (i as f32 / n as f32, j as f32 / n as f32);
            m.positions.push(PackedVec3::new(x, y, 0.0));
            m.normals.push(PackedVec3::Z);
            m.uvs.push(Vec2::new(x, y));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            m.indices
                .extend([v, v + 1, v + n + 2, v, v + n + 2, v + n + 1]);
        }
    }
    m
}

/// A closed octahedron, no normals (they are computed), (u, v) from the position.
fn octahedron() -> TriangleMesh {
    let p = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let mut m = TriangleMesh::default();
    for q in p {
        m.positions.push(PackedVec3::from_array(q));
        m.uvs.push(Vec2::new(q[0], q[1]));
    }
    m.indices = vec![
        0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5,
    ];
    m
}

fn rule(to_render: Transform, edge_length: f32) -> Refinement {
    Refinement {
        to_render,
        edge_length,
        max_triangles: 10_000_000,
    }
}

fn area(m: &TriangleMesh, t: &Transform) -> f64 {
    m.indices
        .chunks_exact(3)
        .map(|f| {
            let p = |k: usize| t.point(m.position(f[k] as usize));
            0.5 * cross(p(1) - p(0), p(2) - p(0)).length() as f64
        })
        .sum()
}

/// Undirected edge → how many triangles use it.
fn edge_uses(m: &TriangleMesh) -> HashMap<(u32, u32), u32> {
    let mut uses = HashMap::new();
    for f in m.indices.chunks_exact(3) {
        for k in 0..3 {
            *uses.entry(key(f[k], f[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    uses
}

fn longest_edge(m: &TriangleMesh, t: &Transform) -> f32 {
    edge_uses(m)
        .keys()
        .map(|&(a, b)| (t.point(m.position(a as usize)) - t.point(m.position(b as usize))).length())
        .fold(0.0, f32::max)
}

fn scale(x: f32, y: f32, z: f32) -> Transform {
    Transform::scale(Vec3::new(x, y, z)).unwrap()
}

#[test]
fn every_edge_is_shorter_than_the_edge_length_in_render_space() {
    let m = grid(3);
    let t = scale(2.0, 0.5, 1.0);
    let r = refine(&m, &rule(t, 0.07)).unwrap();
    assert!(r.check().is_ok());
    assert!(longest_edge(&r, &t) < 0.07, "{}", longest_edge(&r, &t));
    // Measured in render space: object-space edges along x are under 0.035.
    assert!(longest_edge(&r, &Transform::IDENTITY) < 0.07 / 0.5);
    // The plane's area is kept, and shared by at least area / (√3/4 · l²) triangles (the
    // largest with every edge under l is equilateral).
    assert!((area(&r, &t) - 1.0).abs() < 1e-4, "{}", area(&r, &t));
    let at_least = 1.0 / (3f64.sqrt() / 4.0 * 0.07 * 0.07);
    assert!(r.face_count() as f64 > at_least, "{}", r.face_count());
}

#[test]
fn shared_edges_are_split_alike_so_the_mesh_stays_watertight() {
    // A closed mesh under a non-uniform scale: every edge has exactly two triangles.
    let m = octahedron();
    let t = scale(1.0, 2.5, 0.3);
    let r = refine(&m, &rule(t, 0.1)).unwrap();
    let uses = edge_uses(&r);
    assert!(uses.len() > 1000);
    assert!(uses.values().all(|&n| n == 2), "an edge with a crack");
    // An open grid: the edges with one triangle add up to the perimeter (a T-junction would
    // leave both a long edge and its halves on their own).
    let g = grid(4);
    let r = refine(&g, &rule(Transform::IDENTITY, 0.03)).unwrap();
    let uses = edge_uses(&r);
    assert!(uses.values().all(|&n| n <= 2));
    let boundary: f32 = uses
        .iter()
        .filter(|&(_, &n)| n == 1)
        .map(|(&(a, b), _)| (r.position(a as usize) - r.position(b as usize)).length())
        .sum();
    assert!((boundary - 4.0).abs() < 1e-4, "{boundary}");
    // No vertex is made twice.
    let mut seen = std::collections::HashSet::new();
    assert!(
        r.positions
            .iter()
            .all(|p| seen.insert(p.to_array().map(f32::to_bits)))
    );
}

#[test]
fn triangles_come_in_pbrt_v4_order() {
    // (0,0,0), (1,0,0), (0,1,0) at edge length 0.8: the hypotenuse, then each half's
    // unit leg.
    let mut m = TriangleMesh::default();
    for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        m.positions.push(PackedVec3::from_array(p));
        m.uvs.push(Vec2::new(p[0], p[1]));
    }
    m.indices = vec![0, 1, 2];
    let r = refine(&m, &rule(Transform::IDENTITY, 0.8)).unwrap();
    let tris: Vec<[[f32; 2]; 3]> = r
        .indices
        .chunks_exact(3)
        .map(|f| std::array::from_fn(|k| r.uvs[f[k] as usize].to_array()))
        .collect();
    let (a, b, c) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]);
    let (m, m2, m3) = ([0.5, 0.5], [0.5, 0.0], [0.0, 0.5]);
    assert_eq!(tris, vec![[a, m2, m], [m2, b, m], [c, m3, m], [m3, a, m]]);
    // Normals computed from the face (+z), interpolated as normalize(n₀ + n₁).
    assert!(r.normals.iter().all(|&n| n == PackedVec3::Z));
}

#[test]
fn the_refinement_does_not_depend_on_the_thread_count() {
    let mut m = octahedron();
    // Enough input triangles for several chunks.
    for _ in 0..3 {
        m = refine(&m, &rule(Transform::IDENTITY, 0.5)).unwrap();
    }
    let t = scale(1.0, 1.7, 0.6);
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| refine(&m, &rule(t, 0.03)).unwrap())
    };
    let one = run(1);
    assert!(one.face_count() > 10_000);
    assert!(one == run(3));
    assert!(one == run(8));
}

#[test]
fn an_absurd_edge_length_is_an_error_not_an_allocation() {
    let g = grid(2);
    let small = Refinement {
        max_triangles: 1_000_000,
        ..rule(Transform::IDENTITY, 1e-6)
    };
    match refine(&g, &small) {
        Err(DisplaceError::TooManyTriangles {
            at_least: Some(n),
            max: 1_000_000,
        }) => assert!(n > 1_000_000_000_000),
        other => panic!("{other:?}"),
    }
    // A sliver has no area to warn early: its count stops the refinement.
    let mut sliver = TriangleMesh::default();
    for p in [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]] {
        sliver.positions.push(PackedVec3::from_array(p));
        sliver.uvs.push(Vec2::ZERO);
    }
    sliver.indices = vec![0, 1, 2];
    let r = Refinement {
        max_triangles: 1000,
        ..rule(Transform::IDENTITY, 1e-5)
    };
    assert!(matches!(
        refine(&sliver, &r),
        Err(DisplaceError::TooManyTriangles { at_least: None, .. })
    ));
    for bad in [0.0, -1.0, f32::NAN] {
        assert_eq!(
            refine(&g, &rule(Transform::IDENTITY, bad)),
            Err(DisplaceError::BadEdgeLength)
        );
    }
    // Below the coordinates' precision the bisection cannot converge.
    let r = Refinement {
        max_triangles: MAX_DISPLACED_TRIANGLES,
        ..rule(Transform::IDENTITY, 1e-30)
    };
    let mut far = sliver.clone();
    far.positions[1] = PackedVec3::new(1e6, 0.0, 0.0);
    far.positions[2] = PackedVec3::new(1e6 + 0.125, 0.0, 0.0);
    assert!(refine(&far, &r).is_err());
    let mut no_uv = g;
    no_uv.uvs.clear();
    assert_eq!(
        refine(&no_uv, &rule(Transform::IDENTITY, 0.1)),
        Err(DisplaceError::NoUvs)
    );
}

#[test]
fn zero_displacement_keeps_a_flat_mesh_and_a_constant_one_lifts_it() {
    let g = grid(2);
    let mut r = refine(&g, &rule(Transform::IDENTITY, 0.05)).unwrap();
    let before = r.positions.clone();
    displace(&mut r, |_, _| 0.0);
    assert_eq!(r.positions, before);
    assert!((area(&r, &Transform::IDENTITY) - 1.0).abs() < 1e-5);
    assert!(
        r.normals
            .iter()
            .all(|n| (*n - PackedVec3::Z).length() < 1e-6)
    );
    // d = 0.25 + u/4 along +z: each vertex's height is that of its own (u, v).
    displace(&mut r, |_, uv| 0.25 + uv.x / 4.0);
    for (p, uv) in r.positions.iter().zip(&r.uvs) {
        assert_eq!(p.z, 0.25 + uv.x / 4.0);
        assert_eq!((p.x, p.y), (uv.x, uv.y));
    }
    // The recomputed normals lean against the slope: n ∝ (−1/4, 0, 1).
    let want = crate::math::normalize(Vec3::new(-0.25, 0.0, 1.0));
    assert!(
        r.normals
            .iter()
            .all(|&n| (Vec3::from(n) - want).length() < 1e-4)
    );
}

#[test]
fn normals_are_pbrt_v4s_compute_normals() {
    // Two triangles folded at a right angle: the shared vertices get the mean of the two
    // faces' unit normals, whatever their areas.
    let p = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 5.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let pos: Vec<PackedVec3> = p.iter().map(|&q| PackedVec3::from_array(q)).collect();
    let n = vertex_normals(&pos, &[0, 1, 2, 0, 3, 1]);
    let s = std::f32::consts::FRAC_1_SQRT_2;
    assert!(
        (n[0] - PackedVec3::new(0.0, s, s)).length() < 1e-6,
        "{:?}",
        n[0]
    );
    assert_eq!(n[2], PackedVec3::Z);
    assert_eq!(n[3], PackedVec3::Y);
}
