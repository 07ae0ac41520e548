//! `lancer bench rays MESH`: the BVH's build time and ray throughput on one mesh, with rays
//! generated as `embree_rays.py` (the Embree peer) generates them, so that the two can be
//! compared line by line; `lancer bench scene SCENE` is in `bench_scene.rs`.

use crate::cli_error::CliError;
use clap::{Args, Subcommand};
use lancer::accel::MeshBvh;
use lancer::math::{Bounds3, PackedVec3, Vec2, Vec3, normalize};
use lancer::ray::Ray;
use lancer::sampling::{Pcg32, sample_uniform_sphere};
use lancer::shape::{TriangleMesh, TriangleRay};
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `lancer bench` measures.
#[derive(Subcommand, Debug)]
pub enum BenchCommand {
    /// Build a BVH over a mesh and time primary, incoherent and shadow rays.
    Rays(RaysArgs),
    /// Render a scene and report time per phase, rays/s, samples/s, peak memory and the
    /// relMSE against a reference image.
    Scene(crate::bench_scene::SceneArgs),
}

/// Options of `lancer bench rays`.
#[derive(Args, Debug)]
pub struct RaysArgs {
    /// The mesh: .ply (also .ply.gz) or .obj.
    pub mesh: PathBuf,
    /// Worker threads (default: all cores); 1 runs everything on this thread.
    #[arg(long, visible_alias = "nthreads")]
    pub threads: Option<usize>,
    /// Rays per kind.
    #[arg(long, default_value_t = 4_000_000)]
    pub rays: usize,
    /// Seed of the ray generator.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs a `lancer bench` command.
pub fn run(cmd: BenchCommand) -> Result<(), CliError> {
    match cmd {
        BenchCommand::Rays(args) => rays(args),
        BenchCommand::Scene(args) => crate::bench_scene::run(args),
    }
}

/// Reads the mesh named on the command line.
fn load_mesh(path: &Path) -> Result<TriangleMesh, CliError> {
    let name = path.to_string_lossy().to_ascii_lowercase();
    if name.ends_with(".obj") {
        let obj = lancer_scene::obj::read_obj(path).map_err(|e| CliError::input(e.to_string()))?;
        Ok(obj.merged_mesh())
    } else if name.ends_with(".ply") || name.ends_with(".ply.gz") {
        let ply = lancer_scene::ply::read_ply(path).map_err(|e| CliError::input(e.to_string()))?;
        Ok(ply.mesh)
    } else {
        Err(CliError::input(format!(
            "{}: bench rays reads .ply, .ply.gz and .obj meshes",
            path.display()
        )))
    }
}

fn rays(args: RaysArgs) -> Result<(), CliError> {
    let mesh = load_mesh(&args.mesh)?;
    mesh.validate()
        .map_err(|m| CliError::input(format!("{}: {m}", args.mesh.display())))?;
    let tris: Vec<[PackedVec3; 3]> = (0..mesh.triangle_count() as u32)
        .map(|i| mesh.vertices(i).map(|v| mesh.positions[v]))
        .collect();
    let threads = args.threads.unwrap_or(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| CliError::runtime(format!("cannot start the worker threads: {e}")))?;
    let threads = pool.current_num_threads();

    let start = Instant::now();
    let accel = pool.install(|| MeshBvh::build(&tris));
    let build_s = start.elapsed().as_secs_f64();
    drop(tris);
    let n = mesh.triangle_count().max(1);
    let mesh_bytes = mesh.positions.len() * 12 + mesh.indices.len() * 4;
    let bvh_bytes = accel.memory_bytes();
    println!(
        "lancer triangles={} threads={threads} build_s={build_s:.3}",
        mesh.triangle_count()
    );
    println!(
        "memory mesh_bytes={mesh_bytes} bvh_bytes={bvh_bytes} bytes_per_triangle={:.1}",
        (mesh_bytes + bvh_bytes) as f64 / n as f64
    );

    let bounds = mesh
        .positions
        .iter()
        .fold(Bounds3::EMPTY, |b, &p| b.union_point(p.into()));
    if bounds.is_empty() {
        return Err(CliError::input(format!(
            "{}: the mesh has no vertices",
            args.mesh.display()
        )));
    }
    let kinds = [
        ("primary", primary_rays(&bounds, args.rays), false),
        (
            "incoherent",
            incoherent_rays(&bounds, args.rays, args.seed, f32::INFINITY),
            false,
        ),
        (
            "shadow",
            incoherent_rays(
                &bounds,
                args.rays,
                args.seed,
                0.5 * bounds.diagonal().length(),
            ),
            true,
        ),
    ];
    for (name, rays, any) in kinds {
        let start = Instant::now();
        let cpu0 = pool.install(thread_cpu_ns);
        let hits: usize = pool.install(|| {
            rays.par_chunks(4096)
                .map(|chunk| {
                    chunk
                        .iter()
                        .filter(|r| {
                            let pre = TriangleRay::new(r);
                            if any {
                                accel.intersect_any(r, &pre)
                            } else {
                                accel.intersect(r, &pre).is_some()
                            }
                        })
                        .count()
                })
                .sum()
        });
        let dt = start.elapsed().as_secs_f64();
        let cpu1 = pool.install(thread_cpu_ns);
        let kind = if any { "any-hit" } else { "closest" };
        // On a busy machine wall time includes waiting for a core; with one thread, the
        // worker's own CPU time says what the code costs.
        let cpu = match (cpu0, cpu1) {
            (Some(a), Some(b)) if threads == 1 && b > a => format!(
                " cpu_mrays_s={:.2}",
                rays.len() as f64 / ((b - a) as f64 * 1e-9) / 1e6
            ),
            _ => String::new(),
        };
        println!(
            "{name} rays={} hit={:.3} time_s={dt:.3} mrays_s={:.2}{cpu} ({kind})",
            rays.len(),
            hits as f64 / rays.len().max(1) as f64,
            rays.len() as f64 / dt / 1e6
        );
    }
    Ok(())
}

/// A pinhole camera's rays through a `side × side` grid (side = ⌊√n⌋), from
/// eye = centre + (0, 0, 1.5·max extent), direction (0.45·u, 0.45·v, −1) for u, v the pixel
/// centres in [−1, 1] — the geometry of `embree_rays.py`.
fn primary_rays(b: &Bounds3, n: usize) -> Vec<Ray> {
    let side = (n as f64).sqrt() as usize;
    let ext = b.diagonal();
    let eye = b.centroid() + Vec3::new(0.0, 0.0, 1.5 * ext.max_element());
    let mut out = Vec::with_capacity(side * side);
    let coord = |i: usize| ((i as f64 + 0.5) / side as f64 * 2.0 - 1.0) as f32;
    for j in 0..side {
        for i in 0..side {
            let d = normalize(Vec3::new(coord(i) * 0.45, coord(j) * 0.45, -1.0));
            out.push(Ray::new(eye, d));
        }
    }
    out
}

/// `n` rays with origins uniform in the bounds grown by 50 % (25 % on each side) and
/// directions uniform on the sphere, from a PCG32 stream seeded by `seed`; `t_max` bounds them.
fn incoherent_rays(b: &Bounds3, n: usize, seed: u64, t_max: f32) -> Vec<Ray> {
    let mut rng = Pcg32::new(seed, 0);
    let ext = b.diagonal();
    let lo = b.min - 0.25 * ext;
    (0..n)
        .map(|_| {
            let u = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform());
            let o = lo + u * 1.5 * ext;
            let d = sample_uniform_sphere(Vec2::new(rng.uniform(), rng.uniform()));
            Ray {
                t_max,
                ..Ray::new(o, d)
            }
        })
        .collect()
}

/// Nanoseconds the calling thread has spent on a CPU (Linux: the first field of
/// `/proc/thread-self/schedstat`); `None` elsewhere.
fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}
