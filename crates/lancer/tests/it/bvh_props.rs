//! Property tests of the BVH: over thousands of random meshes and rays (a seeded generator),
//! the tree's closest hit is brute force's closest hit (same triangle, or one at exactly the
//! same t when triangles coincide; t equal bit for bit) and its any-hit answer is brute
//! force's. Brute force runs the scalar watertight test, which the BVH's 4-triangle packets
//! must reproduce exactly. A scene mixing every kind of shape is checked the same way.

use lancer::accel::MeshBvh;
use lancer::math::{PackedVec3, Transform, Vec3};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::scene::desc::{Geometry, ShapeDesc};
use lancer::shape::{
    BoxDesc, ConeDesc, CylinderDesc, DiskDesc, HyperboloidDesc, ParaboloidDesc, PlaneDesc,
    ShapeHit, SphereDesc, TriangleMesh, TriangleRay, intersect_triangle,
};
use lancer::{Scene, SceneDesc};

fn v3(rng: &mut Pcg32) -> Vec3 {
    Vec3::new(rng.uniform(), rng.uniform(), rng.uniform())
}

/// A random mesh of one of several kinds: uniform triangles, tight clusters, degenerate
/// (zero-area) triangles mixed in, exact duplicates, a single triangle, none.
fn random_mesh(rng: &mut Pcg32, case: u32) -> Vec<[Vec3; 3]> {
    let kind = case % 6;
    let n = match kind {
        4 => 1,
        5 => 0,
        _ => 1 + (rng.next_u32() % 300) as usize,
    };
    let mut tris = Vec::with_capacity(n);
    let centres: Vec<Vec3> = (0..4).map(|_| v3(rng) * 10.0 - 5.0).collect();
    while tris.len() < n {
        let size = if rng.uniform() < 0.2 { 3.0 } else { 0.4 };
        let c = match kind {
            1 => centres[(rng.next_u32() % 4) as usize] + (v3(rng) - 0.5) * 0.5,
            _ => v3(rng) * 10.0 - 5.0,
        };
        let a = c + (v3(rng) - 0.5) * size;
        let b = c + (v3(rng) - 0.5) * size;
        let mut t = [a, b, c + (v3(rng) - 0.5) * size];
        if kind == 2 && rng.uniform() < 0.3 {
            // Zero area: a repeated vertex or three collinear points.
            t[2] = if rng.uniform() < 0.5 {
                a
            } else {
                a + 2.0 * (b - a)
            };
        }
        tris.push(t);
        if kind == 3 && rng.uniform() < 0.4 && tris.len() < n {
            tris.push(t);
        }
    }
    tris
}

/// Rays from around the mesh towards it (mostly) or anywhere, some with a short `t_max`.
fn random_ray(rng: &mut Pcg32) -> Ray {
    let o = v3(rng) * 16.0 - 8.0;
    let d = if rng.uniform() < 0.7 {
        (v3(rng) * 8.0 - 4.0) - o
    } else {
        v3(rng) - 0.5
    };
    let t_max = if rng.uniform() < 0.3 {
        rng.uniform() * 1.5
    } else {
        f32::INFINITY
    };
    Ray {
        t_max,
        ..Ray::new(o, d)
    }
}

/// Brute force: every triangle in turn with the scalar test, the ray shortened by each hit.
fn brute(tris: &[[Vec3; 3]], ray: &Ray) -> Option<(u32, ShapeHit)> {
    let mut r = *ray;
    let mut best = None;
    for (i, [a, b, c]) in tris.iter().enumerate() {
        if let Some(h) = intersect_triangle(&r, *a, *b, *c) {
            r.t_max = h.t;
            best = Some((i as u32, h));
        }
    }
    best
}

#[test]
fn mesh_bvh_equals_brute_force() {
    let mut rng = Pcg32::new(7, 0);
    let (mut hits, mut rays) = (0, 0);
    for case in 0..600 {
        let tris = random_mesh(&mut rng, case);
        let packed: Vec<[PackedVec3; 3]> = tris.iter().map(|t| t.map(PackedVec3::from)).collect();
        let bvh = MeshBvh::build(&packed);
        for _ in 0..40 {
            let ray = random_ray(&mut rng);
            let pre = TriangleRay::new(&ray);
            let want = brute(&tris, &ray);
            let got = bvh.intersect(&ray, &pre);
            rays += 1;
            match (want, got) {
                (None, None) => {}
                (Some((wi, wh)), Some((gi, gh))) => {
                    hits += 1;
                    assert_eq!(
                        wh.t.to_bits(),
                        gh.t.to_bits(),
                        "case {case}: t {} vs brute force {}",
                        gh.t,
                        wh.t
                    );
                    if wi != gi {
                        // Only a coincident triangle may stand in for brute force's.
                        let [a, b, c] = tris[gi as usize];
                        let alone = intersect_triangle(&ray, a, b, c).map(|h| h.t);
                        assert_eq!(alone, Some(wh.t), "case {case}: triangle {gi} vs {wi}");
                    } else {
                        assert_eq!((wh.u, wh.v), (gh.u, gh.v), "case {case}: barycentrics");
                    }
                }
                (w, g) => panic!("case {case}: brute force {w:?}, BVH {g:?}"),
            }
            assert_eq!(
                bvh.intersect_any(&ray, &pre),
                want.is_some(),
                "case {case}: any-hit"
            );
        }
    }
    // The generator must actually exercise hits and misses.
    assert!(
        hits > rays / 20 && hits < rays * 19 / 20,
        "{hits} hits of {rays}"
    );
}

fn shape(geometry: Geometry, at: Vec3) -> ShapeDesc {
    ShapeDesc {
        medium_interface: None,
        geometry,
        object_to_world: Transform::translate(at),
        reverse_orientation: false,
        material: 0,
        area_light: None,
        alpha: None,
    }
}

/// A scene of every kind of shape, scattered.
fn mixed_scene(rng: &mut Pcg32) -> SceneDesc {
    let mut desc = SceneDesc::default();
    for k in 0..120 {
        let at = v3(rng) * 10.0 - 5.0;
        let r = 0.2 + rng.uniform();
        let g = match k % 8 {
            0 => Geometry::Sphere(SphereDesc {
                radius: r,
                z_min: -r,
                z_max: r * 0.5,
                phi_max: 300.0,
            }),
            1 => Geometry::Disk(DiskDesc {
                height: 0.1,
                radius: r,
                inner_radius: 0.1,
                phi_max: 360.0,
            }),
            2 => Geometry::Cylinder(CylinderDesc {
                radius: r,
                z_min: -0.3,
                z_max: 0.4,
                phi_max: 360.0,
            }),
            3 => Geometry::Cone(ConeDesc {
                radius: r,
                height: 0.7,
                phi_max: 360.0,
            }),
            4 => Geometry::Paraboloid(ParaboloidDesc {
                radius: r,
                z_min: 0.0,
                z_max: 0.8,
                phi_max: 360.0,
            }),
            5 => Geometry::Hyperboloid(HyperboloidDesc {
                p1: Vec3::new(r, 0.0, -0.3),
                p2: Vec3::new(0.2, r, 0.4),
                phi_max: 360.0,
            }),
            6 => Geometry::Box(BoxDesc {
                min: Vec3::splat(-0.3 * r),
                max: Vec3::splat(0.3 * r),
            }),
            _ => {
                let tris = random_mesh(rng, 0);
                let tris = &tris[..tris.len().min(20)];
                Geometry::TriangleMesh(std::sync::Arc::new(TriangleMesh {
                    positions: tris.iter().flatten().map(|p| (*p * 0.3).into()).collect(),
                    indices: (0..3 * tris.len() as u32).collect(),
                    ..TriangleMesh::default()
                }))
            }
        };
        desc.shapes.push(shape(g, at));
    }
    desc.shapes.push(shape(
        Geometry::Plane(PlaneDesc {
            p: Vec3::new(0.0, 0.0, -7.0),
            n: Vec3::Z,
        }),
        Vec3::ZERO,
    ));
    desc
}

#[test]
fn scene_of_mixed_shapes_equals_brute_force() {
    let mut rng = Pcg32::new(11, 0);
    let mut hits = 0;
    for case in 0..10 {
        let scene = Scene::build(&mixed_scene(&mut rng)).expect("valid scene");
        for _ in 0..2000 {
            let ray = random_ray(&mut rng);
            let mut r = ray;
            let mut want = None;
            for (i, s) in scene.shapes().iter().enumerate() {
                if let Some(h) = s.intersect(&r) {
                    r.t_max = h.t;
                    want = Some((i as u32, h.t));
                }
            }
            // The plain meshes' triangles, which share their mesh's record.
            for slot in 0..scene.tris().len() as u32 {
                let [a, b, c] = scene.tris().vertices(slot);
                if let Some(h) = lancer::shape::intersect_triangle(&r, a, b, c) {
                    r.t_max = h.t;
                    want = Some((scene.tris().prim(slot), h.t));
                }
            }
            let got = scene.intersect(&ray).map(|h| (h.prim, h.si.t));
            if let (Some((wi, wt)), Some((gi, gt))) = (want, got) {
                hits += 1;
                assert_eq!(wt.to_bits(), gt.to_bits(), "case {case}: t");
                assert_eq!(wi, gi, "case {case}: primitive");
            } else {
                assert_eq!(want, got, "case {case}");
            }
            assert_eq!(scene.intersect_p(&ray), want.is_some(), "case {case}");
        }
    }
    assert!(hits > 2000, "{hits} hits");
}

/// A grid of `n`×`n` quads, two triangles each, vertex (i, j) at `point(i/n, j/n)` (shared
/// vertices: a plain mesh, kept in the scene's indexed triangles when large).
fn grid(n: u32, mut point: impl FnMut(f32, f32) -> Vec3) -> ShapeDesc {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            positions.push(PackedVec3::from(point(
                i as f32 / n as f32,
                j as f32 / n as f32,
            )));
        }
    }
    let mut indices = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let v = j * (n + 1) + i;
            indices.extend_from_slice(&[v, v + 1, v + n + 2, v, v + n + 2, v + n + 1]);
        }
    }
    shape(
        Geometry::TriangleMesh(std::sync::Arc::new(TriangleMesh {
            positions,
            indices,
            ..TriangleMesh::default()
        })),
        Vec3::ZERO,
    )
}

/// Eight rays traced as a packet find what each finds alone: the same primitive, t, point and
/// barycentric coordinates, bit for bit. Packets of rays from one point (a pixel's camera
/// rays, the case packets are for) and of unrelated rays, some lanes empty, over every kind of
/// shape, the indexed triangles of a large mesh and an infinite plane.
#[test]
fn packets_find_what_single_rays_find() {
    let mut rng = Pcg32::new(12, 0);
    let mut hits = 0;
    for case in 0..6 {
        let mut desc = mixed_scene(&mut rng);
        // A height field over [−6, 6]².
        desc.shapes.push(grid(60, |x, y| {
            Vec3::new(12.0 * x - 6.0, 12.0 * y - 6.0, rng.uniform() - 6.0)
        }));
        let scene = Scene::build(&desc).expect("valid scene");
        assert!(scene.tris().len() > 4096, "the large mesh is indexed");
        for p in 0..300 {
            let coherent = p % 2 == 0;
            let base = random_ray(&mut rng);
            let rays: [Ray; 8] = std::array::from_fn(|_| {
                if coherent {
                    let jitter = (v3(&mut rng) - 0.5) * 0.02;
                    Ray {
                        d: base.d + jitter * base.d.length(),
                        ..base
                    }
                } else {
                    random_ray(&mut rng)
                }
            });
            let active = match p % 5 {
                0 => 0xff,
                1 => 1,
                2 => 0x80,
                _ => 1 + rng.next_u32() % 255,
            };
            let got = scene.intersect_packet(&rays, active, base.d);
            for (k, n) in got.iter().enumerate() {
                if active >> k & 1 == 0 {
                    continue;
                }
                let g = scene.intersect_from(&rays[k], n);
                let key = |h: &lancer::scene::SceneHit| {
                    (
                        h.prim,
                        h.si.t.to_bits(),
                        h.si.p.to_array().map(f32::to_bits),
                        h.si.uv.to_array().map(f32::to_bits),
                    )
                };
                let want = scene.intersect(&rays[k]);
                hits += want.is_some() as u32;
                assert_eq!(
                    g.as_ref().map(key),
                    want.as_ref().map(key),
                    "case {case} packet {p} lane {k} (coherent {coherent})"
                );
            }
        }
    }
    assert!(hits > 4000, "{hits} hits");
}

/// Where a ray meets two surfaces at exactly the same t (a wall and a ceiling along their
/// common edge), the packet keeps the same one whichever other rays share it and whichever
/// lane it is in: a sample's hit depends on its own ray and the packet's order direction alone.
#[test]
fn a_packet_ray_keeps_the_same_surface_whatever_shares_its_packet() {
    let mut desc = SceneDesc::default();
    // The wall x = −1 and the ceiling y = 2, meeting along the line x = −1, y = 2, each as
    // 8 × 8 quads (so that the two sit in different leaves, which the packet visits in some
    // order).
    desc.shapes.push(grid(8, |a, b| {
        Vec3::new(-1.0, 4.0 * a - 2.0, 8.0 * b - 4.0)
    }));
    desc.shapes
        .push(grid(8, |a, b| Vec3::new(2.0 * a - 3.0, 2.0, 8.0 * b - 4.0)));
    let scene = Scene::build(&desc).expect("valid scene");
    let mut rng = Pcg32::new(3, 0);
    // Rays from the origin at points of the edge: both surfaces at t = 1.
    let edge_ray = |z: f32| Ray::new(Vec3::ZERO, Vec3::new(-1.0, 2.0, z));
    let order = Vec3::new(-1.0, 2.0, 0.0);
    let key = |h: Option<lancer::scene::SceneHit>| h.map(|h| (h.prim, h.si.t.to_bits()));
    let mut ties = 0;
    for _ in 0..200 {
        let rays: [Ray; 8] = std::array::from_fn(|_| {
            if rng.uniform() < 0.6 {
                edge_ray((rng.next_u32() % 64) as f32 / 16.0 - 2.0)
            } else {
                // From elsewhere in the room: these cross the two surfaces' boxes in either
                // order.
                let o = Vec3::new(-2.0 * rng.uniform(), 4.0 * rng.uniform() - 2.0, 0.0);
                let to = Vec3::new(-1.0 - 2.0 * rng.uniform(), 2.0 - 4.0 * rng.uniform(), 0.0);
                let to = if rng.uniform() < 0.5 {
                    Vec3::new(-1.0, to.y, 0.0)
                } else {
                    Vec3::new(to.x, 2.0, 0.0)
                };
                Ray::new(o, to - o)
            }
        });
        let active = 1 + rng.next_u32() % 255;
        let got = scene.intersect_packet(&rays, active, order);
        for k in 0..8 {
            if active >> k & 1 == 0 {
                continue;
            }
            let here = key(scene.intersect_from(&rays[k], &got[k]));
            // Alone, in lane 7 - k.
            let mut alone = [rays[k]; 8];
            alone[7 - k] = rays[k];
            let single = scene.intersect_packet(&alone, 1 << (7 - k), order);
            assert_eq!(
                here,
                key(scene.intersect_from(&rays[k], &single[7 - k])),
                "lane {k}"
            );
            // A tie: a triangle of each surface hit at the same t (the wall's come first).
            let t_of = |range: std::ops::Range<usize>| {
                range
                    .filter_map(|i| scene.shapes()[i].intersect(&rays[k]).map(|h| h.t))
                    .next()
            };
            let wall = t_of(0..128);
            ties += (wall.is_some() && wall == t_of(128..256)) as u32;
        }
    }
    assert!(ties > 100, "{ties} rays at the edge");
}
