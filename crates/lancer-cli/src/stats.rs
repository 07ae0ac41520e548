//! `--stats`: a summary of a render, as text (a bare `--stats`, as pbrt's) or as one JSON
//! object (`--stats json`), and the memory estimate of a built scene that `lancer info`
//! reports too.

use lancer::Scene;
use serde_json::{Value, json};

/// Output formats of `--stats`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatsFormat {
    /// One JSON object on stdout when the render ends.
    Json,
    /// Lines of text on stdout when the render ends (what a bare `--stats` prints).
    Text,
}

/// Where a built scene's memory goes, in bytes (what the arrays hold, capacity included).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneMemory {
    /// Triangle meshes: positions, normals, uvs, indices.
    pub mesh_bytes: u64,
    /// Primitive records: shapes and material/emission records (a plain mesh's triangles
    /// share one record; see `lancer::scene::memory::SceneMemory::primitives`).
    pub primitive_bytes: u64,
    /// The acceleration structure.
    pub bvh_bytes: u64,
    /// Texture and environment images (each shared image once).
    pub texture_bytes: u64,
    /// Participating media (records and grids).
    pub media_bytes: u64,
    /// Lights, materials, texture records and instancing.
    pub other_bytes: u64,
    /// Triangles in the scene.
    pub triangles: u64,
    /// Primitives (triangles and other shapes).
    pub primitives: u64,
    /// Nodes of the acceleration structure.
    pub bvh_nodes: u64,
}

impl SceneMemory {
    /// Measures `scene` ([`Scene::memory`]; instancing counts with the other bytes).
    pub fn of(scene: &Scene) -> SceneMemory {
        let m = scene.memory();
        SceneMemory {
            mesh_bytes: m.meshes as u64,
            primitive_bytes: m.primitives as u64,
            bvh_bytes: m.bvh as u64,
            texture_bytes: m.images as u64,
            media_bytes: m.media as u64,
            other_bytes: (m.lights + m.materials + m.textures + m.instances) as u64,
            triangles: scene.triangle_count() as u64,
            primitives: scene.primitive_count() as u64,
            bvh_nodes: scene.bvh_node_count() as u64,
        }
    }

    /// Everything counted.
    pub fn total(&self) -> u64 {
        self.mesh_bytes
            + self.primitive_bytes
            + self.bvh_bytes
            + self.texture_bytes
            + self.media_bytes
            + self.other_bytes
    }

    /// Geometry memory per triangle: (mesh + primitive records + BVH) / triangles; `None`
    /// without triangles.
    pub fn bytes_per_triangle(&self) -> Option<f64> {
        (self.triangles > 0).then(|| {
            (self.mesh_bytes + self.primitive_bytes + self.bvh_bytes) as f64 / self.triangles as f64
        })
    }

    /// As a JSON object.
    pub fn to_json(self) -> Value {
        json!({
            "mesh_bytes": self.mesh_bytes,
            "primitive_bytes": self.primitive_bytes,
            "bvh_bytes": self.bvh_bytes,
            "texture_bytes": self.texture_bytes,
            "media_bytes": self.media_bytes,
            "other_bytes": self.other_bytes,
            "total_bytes": self.total(),
            "bytes_per_triangle": self.bytes_per_triangle(),
        })
    }
}

/// Seconds spent in each phase of a render.
#[derive(Clone, Copy, Debug, Default)]
pub struct Phases {
    /// Reading the scene files.
    pub parse: f64,
    /// Building the scene (BVH, lights).
    pub build: f64,
    /// Rendering.
    pub render: f64,
    /// Denoising (`--denoise`), if asked for.
    pub denoise: Option<f64>,
    /// Encoding and writing the image.
    pub write: f64,
    /// Wall-clock time of the whole command.
    pub total: f64,
}

/// What the summary reports about the render itself.
#[derive(Clone, Debug)]
pub struct RenderSummary {
    /// Scene file (`None`: the built-in scene).
    pub scene: Option<String>,
    /// Output image.
    pub output: String,
    /// Rendered width and height in pixels.
    pub size: (u32, u32),
    /// Samples per pixel.
    pub spp: u32,
    /// Worker threads.
    pub threads: usize,
    /// Camera samples taken.
    pub samples: u64,
    /// Camera samples whose radiance was NaN or infinite (dropped).
    pub nonfinite: u64,
    /// Rays traced (all kinds: the renderer counts them together).
    pub rays: u64,
    /// Rendered spectrally (`--spectral`) rather than in RGB.
    pub spectral: bool,
    /// The integrator, as pbrt-v4 names it.
    pub integrator: &'static str,
    /// Photons traced (`sppm`), light vertices stored for merging (`vcm`); zero for the
    /// other integrators.
    pub photons: u64,
    /// Light subpaths started (`bdpt`, `lightpath`, `mlt`; zero for the others).
    pub light_paths: u64,
    /// Connections tried between light and camera subpaths (`bdpt`, `lightpath`, `mlt`).
    pub connections: u64,
    /// Merges of a camera vertex with a light vertex (`vcm`).
    pub merges: u64,
}

/// The `--stats json` object.
pub fn render_json(r: &RenderSummary, t: &Phases, mem: &SceneMemory) -> Value {
    let per_s = |n: u64| {
        if t.render > 0.0 {
            n as f64 / t.render
        } else {
            0.0
        }
    };
    json!({
        "scene": r.scene,
        "output": r.output,
        "width": r.size.0,
        "height": r.size.1,
        "spp": r.spp,
        "threads": r.threads,
        "mode": if r.spectral { "spectral" } else { "rgb" },
        "time_s": {
            "total": t.total,
            "parse": t.parse,
            "build": t.build,
            "render": t.render,
            "denoise": t.denoise,
            "write": t.write,
        },
        "samples": r.samples,
        "nonfinite_samples": r.nonfinite,
        "samples_per_s": per_s(r.samples),
        "rays": { "total": r.rays },
        "rays_per_s": per_s(r.rays),
        "integrator": r.integrator,
        "photons": r.photons,
        "light_paths": r.light_paths,
        "connections": r.connections,
        "merges": r.merges,
        "primitives": mem.primitives,
        "triangles": mem.triangles,
        "bvh": { "nodes": mem.bvh_nodes, "bytes": mem.bvh_bytes },
        "memory": mem.to_json(),
    })
}

/// A byte count for people: B, KiB, MiB or GiB.
pub fn human_bytes(n: u64) -> String {
    if n >= 1 << 30 {
        format!("{:.2} GiB", n as f64 / (1u64 << 30) as f64)
    } else if n >= 1 << 20 {
        format!("{:.2} MiB", n as f64 / (1u64 << 20) as f64)
    } else if n >= 1 << 10 {
        format!("{:.1} KiB", n as f64 / 1024.0)
    } else {
        format!("{n} B")
    }
}

/// The `--stats` (text) summary: what [`render_json`] holds, one topic per line.
pub fn render_text(r: &RenderSummary, t: &Phases, mem: &SceneMemory) -> String {
    let per_s = |n: u64| {
        if t.render > 0.0 {
            n as f64 / t.render / 1e6
        } else {
            0.0
        }
    };
    let lines = [
        (
            "time",
            format!(
                "{:.3} s in all: parse {:.3} s, build {:.3} s, render {:.3} s, {}write {:.3} s",
                t.total,
                t.parse,
                t.build,
                t.render,
                t.denoise
                    .map_or(String::new(), |d| format!("denoise {d:.3} s, ")),
                t.write
            ),
        ),
        (
            "image",
            format!(
                "{}, {}x{} pixels, {} spp, {}, {} threads",
                r.output,
                r.size.0,
                r.size.1,
                r.spp,
                if r.spectral { "spectral" } else { "rgb" },
                r.threads
            ),
        ),
        (
            "samples",
            format!(
                "{} ({:.2} M/s), {} NaN or infinite",
                r.samples,
                per_s(r.samples),
                r.nonfinite
            ),
        ),
        (
            "rays",
            format!(
                "{} ({:.2} M/s){}",
                r.rays,
                per_s(r.rays),
                match (r.photons, r.light_paths) {
                    (0, 0) => String::new(),
                    (0, l) => format!(
                        "; {l} light paths, {} connections ({})",
                        r.connections, r.integrator
                    ),
                    (p, 0) => format!("; {p} photons ({})", r.integrator),
                    (p, l) => format!(
                        "; {l} light paths, {} connections, {p} light vertices, {} merges ({})",
                        r.connections, r.merges, r.integrator
                    ),
                }
            ),
        ),
        (
            "geometry",
            format!(
                "{} primitives, {} triangles, BVH of {} nodes",
                mem.primitives, mem.triangles, mem.bvh_nodes
            ),
        ),
        (
            "memory",
            format!(
                "meshes {}, primitive records {}, BVH {}, textures {}, other {}, total {}",
                human_bytes(mem.mesh_bytes),
                human_bytes(mem.primitive_bytes),
                human_bytes(mem.bvh_bytes),
                human_bytes(mem.texture_bytes),
                human_bytes(mem.other_bytes),
                human_bytes(mem.total())
            ),
        ),
    ];
    let mut out = format!(
        "statistics of {}\n",
        r.scene
            .as_deref()
            .unwrap_or(crate::input::DEFAULT_SCENE_NAME)
    );
    for (k, v) in lines {
        out.push_str(&format!("  {k:<10}{v}\n"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_per_triangle_counts_mesh_records_and_bvh() {
        let m = SceneMemory {
            mesh_bytes: 1000,
            primitive_bytes: 500,
            bvh_bytes: 500,
            texture_bytes: 7,
            media_bytes: 4,
            other_bytes: 3,
            triangles: 40,
            primitives: 40,
            bvh_nodes: 5,
        };
        assert_eq!(m.bytes_per_triangle(), Some(50.0));
        assert_eq!(m.total(), 2014);
        assert_eq!(SceneMemory::default().bytes_per_triangle(), None);
        assert_eq!(m.to_json()["bytes_per_triangle"].as_f64(), Some(50.0));
    }

    #[test]
    fn human_sizes() {
        assert_eq!(human_bytes(512), "512 B");
        assert_eq!(human_bytes(2048), "2.0 KiB");
        assert_eq!(human_bytes(3 << 20), "3.00 MiB");
    }
}
