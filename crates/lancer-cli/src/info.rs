//! `lancer info SCENE`: what a scene holds, without rendering it — camera, film, sampler,
//! integrator, shapes and lights by kind, materials, triangles, world bounds, the loader's
//! warnings, what the reader made (displaced meshes), memory (mesh + BVH, bytes per triangle)
//! and, with `--files`, every file read.

use crate::cli_error::CliError;
use crate::input;
use crate::stats::{SceneMemory, human_bytes};
use clap::Args;
use lancer::Scene;
use lancer::integrator::Integrator;
use lancer::render::RenderSettings;
use lancer::scene::desc::Projection;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

/// Options of `lancer info`.
#[derive(Args, Debug)]
pub struct InfoArgs {
    /// Scene file (.pbrt), glTF model (.gltf, .glb) or bare mesh (.obj, .ply).
    pub scene: PathBuf,
    /// List every file the loader read (scene, includes, meshes, textures), absolute.
    #[arg(long)]
    pub files: bool,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Every warning of the scene reader is an error (exit status 2), as pbrt-v4 refuses
    /// parameters it does not use.
    #[arg(long)]
    pub strict: bool,
    /// What the reader makes of displaced meshes.
    #[command(flatten)]
    pub read: input::ReadArgs,
}

/// The integrator as pbrt-v4 names it and its parameters under pbrt-v4's names:
/// `{"name": "path", "maxdepth": 5, "regularize": false}`. A parameter the scene leaves to a
/// default that depends on the scene (sppm's `photonsperiteration`, one photon per pixel of
/// `settings`, and `seed`, the sampler's; vcm's `radius`, a fraction of `scene`'s bounding
/// sphere) is given as the value the render uses, and named in `"defaults"`: `{"name":
/// "vcm", "radius": 0.0052, …, "defaults": ["radius"]}`.
fn integrator_json(i: &Integrator, scene: &Scene, settings: &RenderSettings) -> Value {
    let mut v = json!({ "name": i.pbrt_name() });
    let mut defaults: Vec<&str> = Vec::new();
    // As written (0.3, not the f32's 0.30000001192092896).
    let short = |v: f32| v.to_string().parse::<f64>().unwrap_or(f64::NAN);
    match *i {
        Integrator::Whitted { max_depth } => v["maxdepth"] = json!(max_depth),
        Integrator::Path {
            max_depth,
            regularize,
        }
        | Integrator::VolPath {
            max_depth,
            regularize,
        } => {
            v["maxdepth"] = json!(max_depth);
            v["regularize"] = json!(regularize);
        }
        Integrator::PathCaustics { max_depth, paths } => {
            v["maxdepth"] = json!(max_depth);
            v["caustics"] = json!(true);
            v["causticpaths"] = json!(paths);
        }
        Integrator::AmbientOcclusion {
            cos_sample,
            max_distance,
        } => {
            v["cossample"] = json!(cos_sample);
            v["maxdistance"] = json!(max_distance);
        }
        Integrator::LightPath { max_depth }
        | Integrator::RandomWalk { max_depth }
        | Integrator::SimpleVolPath { max_depth } => v["maxdepth"] = json!(max_depth),
        Integrator::SimplePath {
            max_depth,
            sample_lights,
            sample_bsdf,
        } => {
            v["maxdepth"] = json!(max_depth);
            v["samplelights"] = json!(sample_lights);
            v["samplebsdf"] = json!(sample_bsdf);
        }
        Integrator::Bdpt {
            max_depth,
            regularize,
            visualize_strategies,
            visualize_weights,
        } => {
            v["maxdepth"] = json!(max_depth);
            v["regularize"] = json!(regularize);
            v["visualizestrategies"] = json!(visualize_strategies);
            v["visualizeweights"] = json!(visualize_weights);
        }
        Integrator::Mlt(o) => {
            v["maxdepth"] = json!(o.max_depth);
            v["bootstrapsamples"] = json!(o.bootstrap_samples);
            v["chains"] = json!(o.chains);
            v["mutationsperpixel"] = json!(o.mutations_per_pixel);
            v["largestepprobability"] = json!(short(o.large_step_probability));
            v["sigma"] = json!(short(o.sigma));
            v["regularize"] = json!(o.regularize);
        }
        Integrator::Sppm(o) => {
            v["maxdepth"] = json!(o.max_depth);
            // pbrt-v4's −1 (absent): one photon per pixel of the whole render.
            v["photonsperiteration"] =
                json!(lancer::render::sppm::photons_per_iteration(settings, &o));
            if o.photons_per_iteration.is_none() {
                defaults.push("photonsperiteration");
            }
            v["radius"] = json!(short(o.radius));
            // Absent: the sampler's seed.
            v["seed"] = json!(o.seed.unwrap_or(settings.seed));
            if o.seed.is_none() {
                defaults.push("seed");
            }
        }
        Integrator::Vcm(o) => {
            v["maxdepth"] = json!(o.max_depth);
            // Absent: DEFAULT_RADIUS_FRACTION × the scene's bounding-sphere radius.
            v["radius"] = json!(short(lancer::integrator::vcm::initial_radius(scene, &o)));
            if o.radius.is_none() {
                defaults.push("radius");
            }
            v["alpha"] = json!(short(o.alpha));
        }
        Integrator::Normals | Integrator::Depth => {}
    }
    if !defaults.is_empty() {
        v["defaults"] = json!(defaults);
    }
    v
}

/// Everything `lancer info` reports, as JSON.
pub fn describe(args: &InfoArgs) -> Result<Value, CliError> {
    let t0 = Instant::now();
    // The warnings are part of the report: read quietly, not to print them twice.
    let loaded = input::read(Some(&args.scene), &args.read.options())?;
    if args.strict {
        input::refuse_warnings(&loaded)?;
    }
    let parse_s = t0.elapsed().as_secs_f64();
    let desc = &loaded.desc;
    let t1 = Instant::now();
    let scene = Scene::build(desc).map_err(|e| CliError::input(format!("scene: {e}")))?;
    let build_s = t1.elapsed().as_secs_f64();
    let mem = SceneMemory::of(&scene);
    let c = desc.counts();

    let world_from_camera = desc.camera.camera_from_world.inverse();
    let eye = world_from_camera.point(lancer::math::Vec3::ZERO);
    let forward = world_from_camera.vector(lancer::math::Vec3::new(0.0, 0.0, 1.0));
    let projection = match &desc.camera.projection {
        Projection::Perspective { fov } => json!({ "kind": "perspective", "fov": fov }),
        Projection::Orthographic => json!({ "kind": "orthographic" }),
        Projection::Spherical { mapping } => {
            json!({ "kind": "spherical", "mapping": format!("{mapping:?}").to_lowercase() })
        }
        Projection::Realistic(lens) => json!({
            "kind": "realistic",
            "interfaces": lens.interfaces.len(),
            "aperture_diameter": lens.aperture_diameter,
            "focus_distance": lens.focus_distance,
        }),
    };
    let mut lights = c.lights.clone();
    if c.area_lights > 0 {
        lights.insert("area (shapes)", c.area_lights);
    }
    let mut materials: BTreeMap<String, u64> = BTreeMap::new();
    for m in &desc.materials {
        *materials.entry(m.pbrt_name().to_string()).or_default() += 1;
    }
    // Media by pbrt-v4's kind, with the bytes each kind holds (grids, majorants).
    let mut media: BTreeMap<&str, (u64, u64)> = BTreeMap::new();
    for m in scene.media() {
        let e = media.entry(m.kind()).or_default();
        e.0 += 1;
        e.1 += (size_of_val(m) + m.heap_bytes()) as u64;
    }
    let media_json: serde_json::Map<String, Value> = media
        .iter()
        .map(|(k, (n, bytes))| (k.to_string(), json!({ "count": n, "bytes": bytes })))
        .collect();
    let b = scene.bounds();
    let bounds = if b.is_empty() {
        Value::Null
    } else {
        json!({ "min": [b.min.x, b.min.y, b.min.z], "max": [b.max.x, b.max.y, b.max.z] })
    };
    let crop = crate::render::pixel_bounds(desc);
    let mut v = json!({
        "scene": args.scene.display().to_string(),
        "camera": {
            "projection": projection,
            "position": [eye.x, eye.y, eye.z],
            "direction": [forward.x, forward.y, forward.z],
            "lens_radius": desc.camera.lens_radius,
            "focal_distance": desc.camera.focal_distance,
        },
        "film": {
            "width": desc.film.xresolution,
            "height": desc.film.yresolution,
            "pixel_bounds": [crop.x0, crop.x1, crop.y0, crop.y1],
            "filename": desc.film.filename,
        },
        "sampler": {
            "kind": desc.sampler.kind.pbrt_name(),
            "spp": desc.sampler.spp,
            "seed": desc.sampler.seed,
        },
        "integrator": integrator_json(&desc.integrator, &scene, &RenderSettings::from_desc(desc)),
        // The mode `lancer render` uses by default (spectral, as pbrt-v4; `--rgb` for RGB);
        // the debug integrators output RGB quantities in either.
        "mode": if RenderSettings::from_desc(desc).spectral
            && desc.integrator.computes_radiance()
        {
            "spectral"
        } else {
            "rgb"
        },
        "shapes": c.shapes,
        "objects": desc.objects.len(),
        "object_shapes": c.object_shapes,
        "instances": desc.instances.len(),
        "triangles": c.triangles,
        "instanced_triangles": c.instanced_triangles,
        "scene_triangles": mem.triangles,
        "primitives": mem.primitives,
        "lights": lights,
        "materials": { "count": desc.materials.len(), "by_kind": materials },
        "textures": desc.float_textures.len() + desc.spectrum_textures.len(),
        "media": { "count": scene.media().len(), "by_kind": media_json },
        "world_bounds": bounds,
        "warnings": loaded.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
        "notes": loaded.notes.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
        "memory": mem.to_json(),
        "bvh": { "nodes": mem.bvh_nodes, "bytes": mem.bvh_bytes },
        "time_s": { "parse": parse_s, "build": build_s },
        // What `lancer render --denoise` would run on this scene.
        "denoiser": {
            "available": desc.film.gbuffer.is_none() && desc.film.spectral.is_none(),
            "network": format!("Open Image Denoise {} rt_hdr_alb_nrm", lancer_denoise::OIDN_VERSION),
            "inputs": ["color", "albedo", "normal"],
        },
    });
    if args.files {
        v["files"] = json!(
            loaded
                .files
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
        );
    }
    Ok(v)
}

/// `path (maxdepth 5, regularize false)` from [`integrator_json`]'s object; a parameter named
/// in its `"defaults"` is followed by `(default)`: `radius 0.0052 (default)`.
fn integrator_text(v: &Value) -> String {
    let name = v["name"].as_str().unwrap_or("");
    let defaults = v["defaults"].as_array().cloned().unwrap_or_default();
    let params: Vec<String> = v
        .as_object()
        .into_iter()
        .flatten()
        .filter(|(k, _)| *k != "name" && *k != "defaults")
        .map(|(k, x)| {
            if defaults.iter().any(|d| d.as_str() == Some(k)) {
                format!("{k} {x} (default)")
            } else {
                format!("{k} {x}")
            }
        })
        .collect();
    if params.is_empty() {
        name.to_string()
    } else {
        format!("{name} ({})", params.join(", "))
    }
}

fn kinds(v: &Value) -> String {
    match v.as_object() {
        Some(m) if !m.is_empty() => m
            .iter()
            .map(|(k, n)| format!("{n} {k}"))
            .collect::<Vec<_>>()
            .join(", "),
        _ => "none".to_string(),
    }
}

/// The report as text, one fact per line.
pub fn text(v: &Value) -> String {
    let mut out = String::new();
    let mut line = |k: &str, s: String| out.push_str(&format!("{k:<14}{s}\n"));
    let f = |x: &Value| x.as_f64().unwrap_or(0.0);
    let u = |x: &Value| x.as_u64().unwrap_or(0);
    line("scene", v["scene"].as_str().unwrap_or("").to_string());
    let cam = &v["camera"];
    let proj = match cam["projection"]["kind"].as_str() {
        Some("perspective") => format!("perspective, fov {:.2}°", f(&cam["projection"]["fov"])),
        Some(k) => k.to_string(),
        None => String::new(),
    };
    let vec3 = |x: &Value| {
        let a: Vec<String> = (0..3).map(|i| format!("{:.4}", f(&x[i]))).collect();
        format!("({})", a.join(", "))
    };
    line(
        "camera",
        format!(
            "{proj} at {} looking along {}",
            vec3(&cam["position"]),
            vec3(&cam["direction"])
        ),
    );
    let film = &v["film"];
    let pb = &film["pixel_bounds"];
    line(
        "film",
        format!(
            "{}x{}, pixels [{}, {}) x [{}, {}){}",
            u(&film["width"]),
            u(&film["height"]),
            pb[0],
            pb[1],
            pb[2],
            pb[3],
            film["filename"]
                .as_str()
                .map(|n| format!(", file {n}"))
                .unwrap_or_default()
        ),
    );
    line(
        "sampler",
        format!(
            "{}, {} spp, seed {}",
            v["sampler"]["kind"].as_str().unwrap_or(""),
            u(&v["sampler"]["spp"]),
            u(&v["sampler"]["seed"])
        ),
    );
    line("integrator", integrator_text(&v["integrator"]));
    line(
        "mode",
        match v["mode"].as_str() {
            Some("spectral") => "spectral (the default; lancer render --rgb renders in RGB)".into(),
            m => m.unwrap_or("").into(),
        },
    );
    line("shapes", kinds(&v["shapes"]));
    if u(&v["objects"]) > 0 {
        line(
            "objects",
            format!(
                "{} ({}), {} instances",
                u(&v["objects"]),
                kinds(&v["object_shapes"]),
                u(&v["instances"])
            ),
        );
    }
    line(
        "triangles",
        format!(
            "{} in world shapes, {} in instances, {} built",
            u(&v["triangles"]),
            u(&v["instanced_triangles"]),
            u(&v["scene_triangles"])
        ),
    );
    line("primitives", u(&v["primitives"]).to_string());
    line("lights", kinds(&v["lights"]));
    line(
        "materials",
        format!(
            "{} ({})",
            u(&v["materials"]["count"]),
            kinds(&v["materials"]["by_kind"])
        ),
    );
    line("textures", u(&v["textures"]).to_string());
    if u(&v["media"]["count"]) > 0 {
        let by_kind = v["media"]["by_kind"]
            .as_object()
            .cloned()
            .unwrap_or_default();
        let kinds: Vec<String> = by_kind
            .iter()
            .map(|(k, e)| format!("{} {k} ({})", u(&e["count"]), human_bytes(u(&e["bytes"]))))
            .collect();
        line("media", kinds.join(", "));
    }
    let wb = &v["world_bounds"];
    line(
        "bounds",
        if wb.is_null() {
            "empty".into()
        } else {
            format!("{} to {}", vec3(&wb["min"]), vec3(&wb["max"]))
        },
    );
    let m = &v["memory"];
    line(
        "memory",
        format!(
            "meshes {}, primitive records {}, BVH {} ({} nodes), textures {}, media {}, total {}",
            human_bytes(u(&m["mesh_bytes"])),
            human_bytes(u(&m["primitive_bytes"])),
            human_bytes(u(&m["bvh_bytes"])),
            u(&v["bvh"]["nodes"]),
            human_bytes(u(&m["texture_bytes"])),
            human_bytes(u(&m["media_bytes"])),
            human_bytes(u(&m["total_bytes"]))
        ),
    );
    if let Some(bpt) = m["bytes_per_triangle"].as_f64() {
        line(
            "per triangle",
            format!("{bpt:.1} bytes (mesh + primitive records + BVH)"),
        );
    }
    let dn = &v["denoiser"];
    line(
        "denoiser",
        if dn["available"].as_bool().unwrap_or(false) {
            format!(
                "--denoise runs {} (colour + albedo + normal, lancer's CPU inference)",
                dn["network"].as_str().unwrap_or("")
            )
        } else {
            "--denoise: not with this film (gbuffer or spectral); use Film \"rgb\"".to_string()
        },
    );
    for n in v["notes"].as_array().into_iter().flatten() {
        line("made", n.as_str().unwrap_or("").to_string());
    }
    let warnings = v["warnings"].as_array().cloned().unwrap_or_default();
    line("warnings", warnings.len().to_string());
    for w in &warnings {
        out.push_str(&format!("  {}\n", w.as_str().unwrap_or("")));
    }
    if let Some(files) = v["files"].as_array() {
        out.push_str(&format!("files read ({}):\n", files.len()));
        for p in files {
            out.push_str(&format!("  {}\n", p.as_str().unwrap_or("")));
        }
    }
    out
}

/// Runs `lancer info`.
pub fn run(args: InfoArgs) -> Result<(), CliError> {
    let v = describe(&args)?;
    if args.json {
        println!("{v}");
    } else {
        print!("{}", text(&v));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use lancer::integrator::sppm::SppmOptions;
    use lancer::scene::desc::SceneDesc;

    #[test]
    fn integrators_are_named_as_pbrt_names_them() {
        // An empty scene: its bounding sphere has radius 0.
        let desc = SceneDesc::default();
        let scene = Scene::build(&desc).unwrap();
        let settings = RenderSettings::from_desc(&desc);
        let integrator_json = |i: &Integrator| integrator_json(i, &scene, &settings);
        let v = integrator_json(&Integrator::Path {
            max_depth: 5,
            regularize: false,
        });
        assert_eq!(
            v,
            json!({ "name": "path", "maxdepth": 5, "regularize": false })
        );
        assert_eq!(integrator_text(&v), "path (maxdepth 5, regularize false)");
        let v = integrator_json(&Integrator::Whitted { max_depth: 6 });
        assert_eq!(integrator_text(&v), "whitted (maxdepth 6)");
        assert_eq!(
            integrator_text(&integrator_json(&Integrator::Normals)),
            "normals"
        );
        let v = integrator_json(&Integrator::Bdpt {
            max_depth: 8,
            regularize: false,
            visualize_strategies: true,
            visualize_weights: false,
        });
        assert_eq!(
            v,
            json!({ "name": "bdpt", "maxdepth": 8, "regularize": false,
                    "visualizestrategies": true, "visualizeweights": false })
        );
        let v = integrator_json(&Integrator::LightPath { max_depth: 5 });
        assert_eq!(integrator_text(&v), "lightpath (maxdepth 5)");
        let v = integrator_json(&Integrator::Mlt(lancer::integrator::mlt::MltOptions {
            max_depth: 7,
            bootstrap_samples: 100_000,
            chains: 1000,
            mutations_per_pixel: 64,
            large_step_probability: 0.3,
            sigma: 0.01,
            regularize: false,
        }));
        assert_eq!(
            integrator_text(&v),
            "mlt (bootstrapsamples 100000, chains 1000, largestepprobability 0.3, maxdepth 7, \
             mutationsperpixel 64, regularize false, sigma 0.01)"
        );
        let v = integrator_json(&Integrator::Sppm(SppmOptions {
            max_depth: 8,
            photons_per_iteration: Some(1000),
            radius: 0.25,
            seed: Some(3),
        }));
        assert_eq!(
            v,
            json!({ "name": "sppm", "maxdepth": 8, "photonsperiteration": 1000,
                    "radius": 0.25, "seed": 3 })
        );
        // One photon per pixel of the film when the scene leaves photonsperiteration out.
        let v = integrator_json(&Integrator::Sppm(SppmOptions {
            max_depth: 8,
            photons_per_iteration: None,
            radius: 0.25,
            seed: None,
        }));
        let pixels = settings.splat_bounds.area();
        assert!(pixels > 1);
        assert_eq!(v["photonsperiteration"], json!(pixels));
        assert_eq!(v["seed"], json!(settings.seed));
        assert_eq!(v["defaults"], json!(["photonsperiteration", "seed"]));
        assert_eq!(
            integrator_text(&v),
            format!(
                "sppm (maxdepth 8, photonsperiteration {pixels} (default), radius 0.25, seed {} \
                 (default))",
                settings.seed
            )
        );
        let v = integrator_json(&Integrator::Vcm(lancer::integrator::vcm::VcmOptions {
            max_depth: 6,
            radius: Some(0.05),
            alpha: 0.75,
        }));
        assert_eq!(
            v,
            json!({ "name": "vcm", "maxdepth": 6, "radius": 0.05, "alpha": 0.75 })
        );
        assert_eq!(
            integrator_text(&v),
            "vcm (alpha 0.75, maxdepth 6, radius 0.05)"
        );
    }
}
