//! Voxel grids: the two-level DDA finds exactly the hits of a brute-force slab test against
//! every filled voxel (same t, same cell, same face normal) on random grids, placements and
//! rays; a 256³ grid costs about one byte per voxel; hits carry their voxel's colour; voxels
//! refuse to be area lights.

use crate::common;
use crate::common::shapes::random_unit;

use glam::DVec3;
use lancer::Scene;
use lancer::math::{Rgb, Transform, Vec3, normalize};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::scene::desc::{AreaLightDesc, Geometry, SceneDesc, ShapeDesc};
use lancer::shape::{Shape, VoxelGrid, Voxels};
use std::sync::Arc;

fn palette() -> [Rgb; 256] {
    std::array::from_fn(|i| {
        let f = i as f32 / 255.0;
        Rgb::new(f, 1.0 - f, (f * 7.0).fract())
    })
}

fn scene_of(grid: Arc<VoxelGrid>, to_world: Transform, reverse: bool) -> Scene {
    common::shapes::scene_of(Geometry::Voxels(grid), to_world, reverse)
}

fn voxels(scene: &Scene) -> &Voxels {
    match &scene.shapes()[0] {
        Shape::Voxels(v) => v,
        other => panic!("expected voxels, got {other:?}"),
    }
}

/// A random grid: random size (up to 27 cells, so several 8³ bricks), density and layout
/// (uniform noise, or a few solid blobs leaving whole bricks empty).
fn random_grid(rng: &mut Pcg32) -> VoxelGrid {
    let dims = [0; 3].map(|_| 1 + (rng.uniform() * 27.0) as u32);
    let n = (dims[0] * dims[1] * dims[2]) as usize;
    let mut cells = vec![0u8; n];
    let blobs = rng.uniform() < 0.5;
    let density = 0.02 + 0.4 * rng.uniform();
    let centres: Vec<Vec3> = (0..3)
        .map(|_| {
            Vec3::new(rng.uniform(), rng.uniform(), rng.uniform())
                * Vec3::new(dims[0] as f32, dims[1] as f32, dims[2] as f32)
        })
        .collect();
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let p = Vec3::new(x as f32, y as f32, z as f32) + 0.5;
                let filled = if blobs {
                    centres.iter().any(|c| c.distance(p) < 3.0)
                } else {
                    rng.uniform() < density
                };
                if filled {
                    cells[(x + dims[0] * (y + dims[1] * z)) as usize] =
                        1 + (rng.uniform() * 254.0) as u8;
                }
            }
        }
    }
    // Never empty: one cell at least.
    if cells.iter().all(|&c| c == 0) {
        cells[n / 2] = 9;
    }
    VoxelGrid::new(dims, cells, palette()).unwrap()
}

/// A random placement: rotation, translation, non-uniform scale, sometimes a mirror.
fn random_placement(rng: &mut Pcg32, i: usize) -> (Transform, bool) {
    if i.is_multiple_of(4) {
        return (Transform::IDENTITY, false);
    }
    let axis = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5;
    let mirror = if i % 4 == 3 { -1.0 } else { 1.0 };
    let t = Transform::translate(Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 10.0)
        * Transform::rotate(360.0 * rng.uniform(), axis).unwrap()
        * Transform::scale(Vec3::new(
            mirror * (0.3 + rng.uniform()),
            0.3 + rng.uniform(),
            0.3 + rng.uniform(),
        ))
        .unwrap();
    (t, i % 5 == 2)
}

/// Brute force in grid space: the slab test against each filled voxel's box; the nearest t in
/// (0, t_max) with its cell and face (axis, + 3 for a max face), and the runner-up's t (to
/// recognise rays through an edge, where two voxels tie).
fn brute_force(
    grid: &VoxelGrid,
    o: DVec3,
    d: DVec3,
    t_max: f64,
) -> Option<(f64, [u32; 3], usize, f64)> {
    let [nx, ny, nz] = grid.dims();
    let mut best: Option<(f64, [u32; 3], usize)> = None;
    let mut second = f64::INFINITY;
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if grid.get(x, y, z) == 0 {
                    continue;
                }
                let lo = DVec3::new(x as f64, y as f64, z as f64);
                let hi = lo + 1.0;
                let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
                let (mut f0, mut f1) = (0, 0);
                let mut miss = false;
                for k in 0..3 {
                    if d[k] == 0.0 {
                        if o[k] < lo[k] || o[k] > hi[k] {
                            miss = true;
                        }
                        continue;
                    }
                    let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
                    let (near, fnear, far, ffar) = if d[k] > 0.0 {
                        (a, k, b, k + 3)
                    } else {
                        (b, k + 3, a, k)
                    };
                    if near > t0 {
                        t0 = near;
                        f0 = fnear;
                    }
                    if far < t1 {
                        t1 = far;
                        f1 = ffar;
                    }
                }
                if miss || t0 > t1 {
                    continue;
                }
                let (t, f) = if t0 > 0.0 { (t0, f0) } else { (t1, f1) };
                if t <= 0.0 || t >= t_max {
                    continue;
                }
                match best {
                    Some((bt, ..)) if bt <= t => second = second.min(t),
                    _ => {
                        if let Some((bt, ..)) = best {
                            second = second.min(bt);
                        }
                        best = Some((t, [x, y, z], f));
                    }
                }
            }
        }
    }
    best.map(|(t, c, f)| (t, c, f, second))
}

#[test]
fn dda_matches_brute_force_on_random_grids() {
    let mut rng = Pcg32::new(11, 3);
    let (mut hits, mut misses, mut ties, mut inside) = (0, 0, 0, 0);
    for gi in 0..40 {
        let grid = Arc::new(random_grid(&mut rng));
        let (to_world, reverse) = random_placement(&mut rng, gi);
        let scene = scene_of(grid.clone(), to_world, reverse);
        let vox = voxels(&scene);
        let dims = grid.dims().map(|d| d as f32);
        let offset = grid.grid_offset();
        let size = Vec3::from(dims).length();
        for ri in 0..300usize {
            // Grid space origin: around the grid, or inside it (in any cell), and a direction
            // that is sometimes parallel to an axis or a plane.
            let centre = Vec3::from(dims) * 0.5;
            let o_grid = if ri.is_multiple_of(3) {
                Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * Vec3::from(dims)
            } else {
                centre + random_unit(&mut rng) * size * (0.6 + rng.uniform())
            };
            let mut d_grid = match ri % 7 {
                0 => Vec3::AXES[(rng.uniform() * 3.0) as usize % 3] * -1.0,
                1 => {
                    let mut d = random_unit(&mut rng);
                    d[(rng.uniform() * 3.0) as usize % 3] = 0.0;
                    d
                }
                _ => (centre
                    + (Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5)
                        * Vec3::from(dims)
                    - o_grid)
                    .normalize_or(Vec3::Z),
            };
            if d_grid.length_squared() == 0.0 {
                d_grid = Vec3::X;
            }
            // To the world (directions by the linear part; rays keep whatever length results).
            let ray = Ray::new(to_world.point(o_grid - offset), to_world.vector(d_grid));
            let (o, d) = vox.placement.object_ray(&ray);
            let o = o + offset.as_dvec3();
            let expected = brute_force(&grid, o, d, ray.t_max as f64);
            let found = scene.shapes()[0].intersect(&ray);
            // Did the ray start inside a filled cell? Then only t is compared (the exit face
            // it finds ties with the entry face of a filled neighbour).
            let start = o.floor();
            let start_filled = (0..3).all(|k| start[k] >= 0.0 && start[k] < dims[k] as f64)
                && grid.get(start.x as u32, start.y as u32, start.z as u32) != 0;
            match (expected, found) {
                (None, None) => misses += 1,
                (Some((t, cell, face, second)), Some(h)) => {
                    let tol = 1e-4 * t.max(1.0);
                    assert!(
                        (h.t as f64 - t).abs() <= tol,
                        "grid {gi} ray {ri}: t {} vs brute force {t}",
                        h.t
                    );
                    if start_filled {
                        inside += 1;
                        continue;
                    }
                    if second - t < 1e-7 * t.max(1.0) {
                        ties += 1;
                        continue;
                    }
                    assert_eq!(vox.hit_cell(&h), cell, "grid {gi} ray {ri}: cell");
                    let si = scene.shapes()[0].interaction(&ray, &h, scene.meshes());
                    let k = face % 3;
                    let n_obj = if face >= 3 {
                        Vec3::AXES[k]
                    } else {
                        -Vec3::AXES[k]
                    };
                    let flip = reverse ^ to_world.swaps_handedness();
                    let mut n = normalize(to_world.normal(n_obj));
                    if flip {
                        n = -n;
                    }
                    assert!(
                        si.n.dot(n) > 0.9999,
                        "grid {gi} ray {ri}: normal {} vs {n}",
                        si.n
                    );
                    // The point is on the ray, and the uv on the face.
                    assert!(si.p.distance(ray.at(h.t)) <= 1e-3 * (1.0 + si.p.length()));
                    assert!((0.0..=1.0).contains(&si.uv.x) && (0.0..=1.0).contains(&si.uv.y));
                    hits += 1;
                }
                (e, f) => panic!(
                    "grid {gi} ray {ri}: brute force {e:?}, DDA {f:?} (origin {o}, direction {d})"
                ),
            }
        }
    }
    println!("{hits} hits, {misses} misses, {inside} from inside, {ties} ties");
    assert!(hits > 4000 && misses > 1000, "{hits} hits, {misses} misses");
    assert!(ties < hits / 100, "{ties} ties");
}

#[test]
fn rays_respect_t_max() {
    // One voxel at the centre of a 3³ grid: cell (1, 1, 1) = object [−0.5, 0.5]² × [1, 2].
    let mut cells = vec![0u8; 27];
    cells[13] = 5;
    let grid = Arc::new(VoxelGrid::new([3, 3, 3], cells, palette()).unwrap());
    let scene = scene_of(grid, Transform::IDENTITY, false);
    let mut ray = Ray::new(Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.0, 0.0, -1.0));
    let h = scene.shapes()[0].intersect(&ray).unwrap();
    assert!((h.t - 8.0).abs() < 1e-6, "{}", h.t);
    ray.t_max = 7.99;
    assert!(scene.shapes()[0].intersect(&ray).is_none());
    // Spawned from the top face going up: nothing; going down through the cell from just
    // inside: the bottom face from inside.
    let si = scene.intersect(&Ray::new(Vec3::new(0.1, 0.2, 10.0), -Vec3::Z));
    let si = si.unwrap().si;
    assert_eq!(si.n, Vec3::Z);
    assert!(
        scene
            .intersect(&si.spawn_ray(Vec3::new(0.3, 0.1, 1.0)))
            .is_none()
    );
    let down = scene
        .intersect(&si.spawn_ray(Vec3::new(0.3, 0.1, -1.0)))
        .unwrap();
    assert!((down.si.t - 1.0).abs() < 1e-4, "{}", down.si.t);
    assert_eq!(down.si.n, -Vec3::Z);
}

#[test]
fn hits_carry_the_voxel_colour() {
    let mut rng = Pcg32::new(5, 1);
    let grid = Arc::new(random_grid(&mut rng));
    let scene = scene_of(
        grid.clone(),
        Transform::scale(Vec3::splat(0.1)).unwrap(),
        false,
    );
    let vox = voxels(&scene);
    let b = scene.shapes()[0].bounds();
    let mut checked = 0;
    for _ in 0..500 {
        let o = 0.5 * (b.min + b.max) + random_unit(&mut rng) * 10.0;
        let target = b.min + (b.max - b.min) * Vec3::new(rng.uniform(), rng.uniform(), 0.5);
        let ray = Ray::new(o, target - o);
        if let Some(hit) = scene.intersect(&ray) {
            let h = scene.shapes()[0].intersect(&ray).unwrap();
            let [x, y, z] = vox.hit_cell(&h);
            let index = grid.get(x, y, z);
            assert_ne!(index, 0);
            assert_eq!(hit.albedo(), Some(grid.palette()[index as usize]));
            checked += 1;
        }
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn a_256_cubed_grid_costs_a_byte_per_voxel() {
    // A ball of radius 100 voxels centred in a 256³ grid: 4.2 million filled voxels, one
    // primitive, no triangles.
    let n = 256u32;
    let mut cells = vec![0u8; (n * n * n) as usize];
    let c = 128.0f32;
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = Vec3::new(x as f32, y as f32, z as f32) + 0.5 - c;
                if p.length() < 100.0 {
                    cells[(x + n * (y + n * z)) as usize] = 1 + (z % 200) as u8;
                }
            }
        }
    }
    let grid = Arc::new(VoxelGrid::new([n; 3], cells, palette()).unwrap());
    let scene = scene_of(grid, Transform::IDENTITY, false);
    assert_eq!(scene.shapes().len(), 1);
    assert!(scene.meshes().is_empty());
    let bytes = voxels(&scene).heap_bytes() as f64;
    let per_voxel = bytes / (n as f64).powi(3);
    println!("256³ grid: {bytes} bytes, {per_voxel:.4} per voxel");
    assert!(per_voxel < 1.01, "{per_voxel} bytes per voxel");
    // Object space: the ball's centre is (0, 0, 128); rays from 1000 away along each axis
    // meet it at 1000 − 100 (within the staircase, ≤ 1).
    for dir in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
        let centre = Vec3::new(0.0, 0.0, 128.0);
        let hit = scene
            .intersect(&Ray::new(centre - 1000.0 * dir, dir))
            .unwrap();
        assert!((hit.si.t - 900.0).abs() <= 1.0, "{dir}: t = {}", hit.si.t);
        assert!(hit.si.n.dot(-dir) > 0.999, "{dir}: n = {}", hit.si.n);
    }
}

#[test]
fn voxels_refuse_to_emit_and_empty_grids_vanish() {
    let grid = Arc::new(VoxelGrid::new([2, 2, 2], vec![1; 8], palette()).unwrap());
    let err = Scene::build(&SceneDesc {
        shapes: vec![ShapeDesc {
            medium_interface: None,
            geometry: Geometry::Voxels(grid),
            object_to_world: Transform::IDENTITY,
            reverse_orientation: false,
            material: 0,
            area_light: Some(AreaLightDesc {
                l: Rgb::ONE,
                two_sided: false,
                spectrum: None,
                power: None,
                image: None,
            }),
            alpha: None,
        }],
        ..SceneDesc::default()
    })
    .unwrap_err();
    assert!(err.to_string().contains("voxel"), "{err}");
    let empty = Arc::new(VoxelGrid::new([4, 4, 4], vec![0; 64], palette()).unwrap());
    assert!(
        scene_of(empty, Transform::IDENTITY, false)
            .shapes()
            .is_empty()
    );
    assert!(VoxelGrid::new([2, 2, 2], vec![1; 7], palette()).is_err());
    assert!(VoxelGrid::new([0, 2, 2], vec![], palette()).is_err());
}

#[test]
fn spawned_rays_never_find_their_own_face_again() {
    let mut rng = Pcg32::new(17, 2);
    let mut checked = 0;
    for gi in 0..12 {
        let grid = Arc::new(random_grid(&mut rng));
        let (to_world, reverse) = random_placement(&mut rng, gi + 1);
        let scene = scene_of(grid, to_world, reverse);
        let b = scene.shapes()[0].bounds();
        let (centre, size) = (0.5 * (b.min + b.max), (b.max - b.min).length());
        for _ in 0..400 {
            let o = centre + random_unit(&mut rng) * size;
            let target =
                b.min + (b.max - b.min) * Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            let Some(hit) = scene.intersect(&Ray::new(o, target - o)) else {
                continue;
            };
            let si = hit.si;
            // The side the ray came from: the normal as seen by the incoming ray.
            let side = if si.n.dot(si.wo) > 0.0 { si.n } else { -si.n };
            for _ in 0..4 {
                let mut d = random_unit(&mut rng);
                if d.dot(side) < 0.0 {
                    d = -d;
                }
                if let Some(next) = scene.intersect(&si.spawn_ray(d)) {
                    // Another voxel may be hit, never this face at a tiny distance.
                    let moved = next.si.p.distance(si.p);
                    assert!(
                        moved > 1e-3 * size.min(1.0),
                        "grid {gi}: a ray leaving {} found the surface again {moved} away",
                        si.p
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(checked > 4000, "{checked}");
}
