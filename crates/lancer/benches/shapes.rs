//! Rays per second for each shape kind (acceptance 4 of issue 4): 1 000 randomly placed and
//! oriented copies of the shape in a BVH (through `Scene::build`), then 1 M seeded random rays
//! (origins in the instances' cube, uniform directions) traced for their closest hit with its
//! full interaction, on one thread.
//!
//! Run: `cargo bench -p lancer --bench shapes` (plain `main`, no harness: it times one pass per
//! kind and prints a table). `LANCER_BENCH_RAYS` changes the ray count. Adding a shape kind is
//! one line in [`kinds`]. Two rates are printed: by wall-clock time, and by the time the thread
//! actually ran (Linux's /proc/thread-self/schedstat), which stays meaningful on a busy machine.

use lancer::Scene;
use lancer::math::{PackedVec3, Rgb, Transform, Vec3};
use lancer::ray::Ray;
use lancer::sampling::Pcg32;
use lancer::scene::desc::{Geometry, SceneDesc, ShapeDesc};
use lancer::shape::{
    BilinearMesh, BoxDesc, ConeDesc, CurveBasis, CurveDesc, CurveType, CylinderDesc, DiskDesc,
    HyperboloidDesc, ParaboloidDesc, SdfDesc, SdfFunction, SphereDesc, TriangleMesh, VoxelGrid,
};
use std::sync::Arc;
use std::time::Instant;

/// Every shape kind benchmarked: a name and its object-space geometry, about one unit across.
fn kinds() -> Vec<(&'static str, Geometry)> {
    vec![
        ("sphere", sphere()),
        ("sphere (partial)", partial_sphere()),
        ("disk", disk()),
        ("cylinder", cylinder()),
        ("cone", cone()),
        ("paraboloid", paraboloid()),
        ("hyperboloid", hyperboloid()),
        ("box", cuboid()),
        ("triangle", triangle()),
        ("voxels 16³ ball", voxel_ball(16)),
        ("bilinear patch", bilinear_patch()),
        ("curve (cylinder)", curve()),
        ("sdf smooth union", sdf()),
    ]
}

fn sphere() -> Geometry {
    Geometry::Sphere(SphereDesc {
        radius: 0.5,
        z_min: -0.5,
        z_max: 0.5,
        phi_max: 360.0,
    })
}

fn partial_sphere() -> Geometry {
    Geometry::Sphere(SphereDesc {
        radius: 0.5,
        z_min: -0.3,
        z_max: 0.4,
        phi_max: 270.0,
    })
}

fn disk() -> Geometry {
    Geometry::Disk(DiskDesc {
        height: 0.0,
        radius: 0.5,
        inner_radius: 0.1,
        phi_max: 360.0,
    })
}

fn cylinder() -> Geometry {
    Geometry::Cylinder(CylinderDesc {
        radius: 0.4,
        z_min: -0.5,
        z_max: 0.5,
        phi_max: 360.0,
    })
}

fn cone() -> Geometry {
    Geometry::Cone(ConeDesc {
        radius: 0.5,
        height: 1.0,
        phi_max: 360.0,
    })
}

fn paraboloid() -> Geometry {
    Geometry::Paraboloid(ParaboloidDesc {
        radius: 0.5,
        z_min: 0.0,
        z_max: 1.0,
        phi_max: 360.0,
    })
}

fn hyperboloid() -> Geometry {
    Geometry::Hyperboloid(HyperboloidDesc {
        p1: Vec3::new(0.5, -0.3, -0.5),
        p2: Vec3::new(0.3, 0.4, 0.5),
        phi_max: 360.0,
    })
}

fn cuboid() -> Geometry {
    Geometry::Box(BoxDesc {
        min: Vec3::splat(-0.4),
        max: Vec3::splat(0.4),
    })
}

fn triangle() -> Geometry {
    Geometry::TriangleMesh(Arc::new(TriangleMesh {
        positions: vec![
            PackedVec3::new(-0.5, -0.4, 0.0),
            PackedVec3::new(0.5, -0.4, 0.0),
            PackedVec3::new(0.0, 0.6, 0.0),
        ],
        indices: vec![0, 1, 2],
        ..TriangleMesh::default()
    }))
}

/// A twisted bilinear patch (a saddle).
fn bilinear_patch() -> Geometry {
    Geometry::BilinearMesh(Arc::new(BilinearMesh {
        positions: vec![
            PackedVec3::new(-0.5, -0.5, 0.2),
            PackedVec3::new(0.5, -0.5, -0.2),
            PackedVec3::new(-0.5, 0.5, -0.2),
            PackedVec3::new(0.5, 0.5, 0.2),
        ],
        indices: vec![0, 1, 2, 3],
        ..BilinearMesh::default()
    }))
}

/// A bent hair-like cubic Bézier curve, tapering, shaded as a tube (pbrt's default split
/// depth: 8 BVH primitives).
fn curve() -> Geometry {
    Geometry::Curve(Arc::new(CurveDesc {
        points: vec![
            PackedVec3::new(0.0, -0.5, 0.0),
            PackedVec3::new(0.3, -0.1, 0.1),
            PackedVec3::new(-0.3, 0.2, -0.1),
            PackedVec3::new(0.1, 0.5, 0.0),
        ],
        basis: CurveBasis::Bezier,
        degree: 3,
        kind: CurveType::Cylinder,
        width0: 0.1,
        width1: 0.03,
        normals: Vec::new(),
        split_depth: 3,
    }))
}

/// The shapes scene's signed-distance object: a sphere smoothly joined to a torus.
fn sdf() -> Geometry {
    let function = SdfFunction::parse(
        "scale(0.4, smooth_union(sphere(0.6), translate([0, 0.5, 0], torus(0.7, 0.18)), 0.25))",
    )
    .expect("a valid expression");
    Geometry::Sdf(SdfDesc {
        function: Arc::new(function),
        bounds: None,
    })
}

/// A ball of voxels `n` cells across, scaled to one unit by its placement's share (the grid
/// is n units in object space, so the instances scale it by 1/n).
fn voxel_ball(n: u32) -> Geometry {
    let c = n as f32 / 2.0;
    let mut cells = vec![0u8; (n * n * n) as usize];
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                if (Vec3::new(x as f32, y as f32, z as f32) + 0.5 - c).length() < c {
                    cells[(x + n * (y + n * z)) as usize] = 1 + (z % 200) as u8;
                }
            }
        }
    }
    let grid = VoxelGrid::new([n; 3], cells, [Rgb::splat(0.5); 256]).expect("valid grid");
    Geometry::Voxels(Arc::new(grid))
}

/// The object-space size of a geometry (voxel grids are one unit per cell).
fn object_scale(g: &Geometry) -> f32 {
    match g {
        Geometry::Voxels(grid) => 1.0 / grid.dims()[0] as f32,
        _ => 1.0,
    }
}

/// Side of the cube the instances and ray origins are spread in.
const CUBE: f32 = 20.0;

fn unit_vector(rng: &mut Pcg32) -> Vec3 {
    loop {
        let v = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 2.0 - 1.0;
        let l = v.length_squared();
        if l > 1e-6 && l <= 1.0 {
            return v / l.sqrt();
        }
    }
}

fn random_point(rng: &mut Pcg32) -> Vec3 {
    (Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5) * CUBE
}

fn scene_of(geometry: &Geometry, rng: &mut Pcg32) -> Scene {
    let s = object_scale(geometry);
    let shapes = (0..1000)
        .map(|_| ShapeDesc {
            medium_interface: None,
            geometry: geometry.clone(),
            object_to_world: Transform::translate(random_point(rng))
                * Transform::rotate(360.0 * rng.uniform(), unit_vector(rng)).expect("axis")
                * Transform::scale(Vec3::splat(s)).expect("scale"),
            reverse_orientation: false,
            material: 0,
            area_light: None,
            alpha: None,
        })
        .collect();
    Scene::build(&SceneDesc {
        shapes,
        ..SceneDesc::default()
    })
    .expect("bench scene")
}

/// Nanoseconds this thread has spent on a CPU (first field of /proc/thread-self/schedstat),
/// when the system tells.
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

fn main() {
    let rays: usize = std::env::var("LANCER_BENCH_RAYS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1_000_000);
    println!("{rays} random rays against 1000 instances, closest hit, one thread");
    println!(
        "{:<18} {:>14} {:>14} {:>8}",
        "shape", "Mrays/s (wall)", "Mrays/s (cpu)", "hits"
    );
    for (name, geometry) in kinds() {
        let mut rng = Pcg32::new(1, 0);
        let scene = scene_of(&geometry, &mut rng);
        let batch: Vec<Ray> = (0..rays)
            .map(|_| Ray::new(random_point(&mut rng), unit_vector(&mut rng)))
            .collect();
        let (start, cpu_start) = (Instant::now(), thread_cpu_ns());
        let mut hits = 0usize;
        for ray in &batch {
            if let Some(h) = scene.intersect(ray) {
                hits += 1;
                std::hint::black_box(h);
            }
        }
        let seconds = start.elapsed().as_secs_f64();
        let cpu = match (cpu_start, thread_cpu_ns()) {
            (Some(a), Some(b)) if b > a => {
                format!("{:.2}", rays as f64 / ((b - a) as f64 * 1e-9) / 1e6)
            }
            _ => "-".into(),
        };
        println!(
            "{name:<18} {:>14.2} {cpu:>14} {:>7.1}%",
            rays as f64 / seconds / 1e6,
            100.0 * hits as f64 / rays as f64
        );
    }
}
