//! `lancer bench scene SCENE`: one render, timed phase by phase (parse, build, render), with
//! its rays/s, samples/s, the process's peak memory and, given a reference image, the relMSE
//! of the image against it: the figures of lancer against pbrt-v4 on real scenes, repeatable
//! in one command.

use crate::cli_error::CliError;
use crate::render::{self, Outcome};
use crate::render_args::RenderArgs;
use clap::{Args, Parser};
use serde_json::{Value, json};
use std::path::PathBuf;
use std::time::Instant;

/// Options of `lancer bench scene`.
#[derive(Args, Debug)]
pub struct SceneArgs {
    /// The scene (anything `lancer render` reads).
    pub scene: PathBuf,
    /// Samples per pixel (overrides the scene).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Image size WIDTHxHEIGHT (overrides the scene).
    #[arg(long)]
    pub resolution: Option<String>,
    /// Worker threads (default: all cores).
    #[arg(long, visible_alias = "nthreads")]
    pub threads: Option<usize>,
    /// Seed of the samplers (overrides the scene).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Render in RGB rather than spectrally.
    #[arg(long)]
    pub rgb: bool,
    /// A reference image (.exr, .png) of the same size: the relMSE of the render against it,
    /// mean of (A−B)²/(B² + 0.01) over pixels and channels, is reported.
    #[arg(long)]
    pub reference: Option<PathBuf>,
    /// Where the image goes (.exr or .png; default: a temporary file, removed afterwards).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Print one JSON object instead of lines of text.
    #[arg(long)]
    pub json: bool,
}

/// `lancer render`'s options, to parse the bench's as that command would.
#[derive(Parser, Debug)]
struct AsRender {
    #[command(flatten)]
    args: RenderArgs,
}

/// Runs `lancer bench scene`.
pub fn run(a: SceneArgs) -> Result<(), CliError> {
    let temp = a.output.is_none();
    let output = a.output.clone().unwrap_or_else(|| {
        std::env::temp_dir().join(format!("lancer-bench-{}.exr", std::process::id()))
    });
    let result = bench(&a, &output);
    if temp {
        let _ = std::fs::remove_file(&output);
    }
    let v = result?;
    if a.json {
        println!("{v}");
    } else {
        print!("{}", text(&v));
    }
    Ok(())
}

/// The render's figures, as JSON.
fn bench(a: &SceneArgs, output: &std::path::Path) -> Result<Value, CliError> {
    let mut argv: Vec<String> = vec![
        "render".into(),
        a.scene.display().to_string(),
        "-o".into(),
        output.display().to_string(),
        "--quiet".into(),
    ];
    let mut opt = |name: &str, v: Option<String>| {
        if let Some(v) = v {
            argv.push(name.into());
            argv.push(v);
        }
    };
    opt("--spp", a.spp.map(|v| v.to_string()));
    opt("--resolution", a.resolution.clone());
    opt("--threads", a.threads.map(|v| v.to_string()));
    opt("--seed", a.seed.map(|v| v.to_string()));
    if a.rgb {
        argv.push("--rgb".into());
    }
    let args = AsRender::try_parse_from(&argv)
        .map_err(|e| CliError::input(e.to_string().trim_end().to_string()))?
        .args;

    let t0 = Instant::now();
    let loaded = render::load(args)?;
    let parse_s = t0.elapsed().as_secs_f64();
    let (args, desc) = (loaded.args, loaded.desc);
    let mut plan = render::plan(&args, &desc, loaded.resumed)?;
    let t_build = Instant::now();
    let scene = render::build(&desc)?;
    let build_s = t_build.elapsed().as_secs_f64();
    let settings = render::render_settings(&desc, &plan.pixels, args.spectral_mode());
    drop(desc);
    let rendered = match render::render(&scene, &settings, &args, &mut plan)? {
        Outcome::Done(r) => r,
        Outcome::Interrupted(message) => return Err(CliError::runtime(message)),
    };
    let render_s = rendered.seconds;
    render::write(&args, &plan, rendered.live, None)?;
    let per_s = |n: u64| {
        if render_s > 0.0 {
            n as f64 / render_s
        } else {
            0.0
        }
    };
    let mem = crate::stats::SceneMemory::of(&scene);
    let relmse = match &a.reference {
        Some(r) => Some(relmse(output, r)?),
        None => None,
    };
    let (w, h) = (plan.pixels.bounds.width(), plan.pixels.bounds.height());
    Ok(json!({
        "scene": a.scene.display().to_string(),
        "mode": if args.spectral_mode() { "spectral" } else { "rgb" },
        "width": w,
        "height": h,
        "spp": settings.spp,
        "threads": rendered.threads,
        "time_s": { "parse": parse_s, "build": build_s, "render": render_s },
        "samples": rendered.stats.samples,
        "samples_per_s": per_s(rendered.stats.samples),
        "rays": rendered.stats.rays,
        "rays_per_s": per_s(rendered.stats.rays),
        "peak_memory_bytes": peak_memory_bytes(),
        "bytes_per_triangle": mem.bytes_per_triangle(),
        "reference": a.reference.as_ref().map(|r| r.display().to_string()),
        "relmse": relmse,
    }))
}

/// relMSE of the image at `a` against the reference `b`.
fn relmse(a: &std::path::Path, b: &std::path::Path) -> Result<f64, CliError> {
    let (a, b) = (crate::img::read_picture(a)?, crate::img::read_picture(b)?);
    if (a.width, a.height) != (b.width, b.height) {
        return Err(CliError::input(format!(
            "the reference is {}x{}, the render {}x{}: give --resolution to match",
            b.width, b.height, a.width, a.height
        )));
    }
    Ok(crate::img::metrics::diff_metrics(&a.pixels, &b.pixels).relmse)
}

/// The process's peak resident memory so far, in bytes (`None` where the system does not
/// say).
fn peak_memory_bytes() -> Option<u64> {
    #[cfg(unix)]
    {
        // SAFETY: getrusage only writes the struct it is given.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) } == 0 {
            // Linux gives kilobytes; macOS gives bytes.
            let scale = if cfg!(target_os = "macos") { 1 } else { 1024 };
            return Some(u.ru_maxrss as u64 * scale);
        }
    }
    None
}

/// The figures as lines of text.
fn text(v: &Value) -> String {
    let f = |k: &str| v[k].as_f64().unwrap_or(0.0);
    let t = |k: &str| v["time_s"][k].as_f64().unwrap_or(0.0);
    let mut s = format!(
        "scene        {} ({}x{}, {} spp, {}, {} threads)\n",
        v["scene"].as_str().unwrap_or(""),
        v["width"],
        v["height"],
        v["spp"],
        v["mode"].as_str().unwrap_or(""),
        v["threads"]
    );
    s += &format!(
        "time         parse {:.3} s, build {:.3} s, render {:.3} s\n",
        t("parse"),
        t("build"),
        t("render")
    );
    s += &format!(
        "throughput   {:.3} M rays/s, {:.3} M samples/s\n",
        f("rays_per_s") / 1e6,
        f("samples_per_s") / 1e6
    );
    match v["peak_memory_bytes"].as_u64() {
        Some(b) => s += &format!("peak memory  {}\n", crate::stats::human_bytes(b)),
        None => s += "peak memory  unknown\n",
    }
    if let Some(b) = v["bytes_per_triangle"].as_f64() {
        s += &format!("per triangle {b:.1} bytes\n");
    }
    if let Some(r) = v["relmse"].as_f64() {
        s += &format!(
            "relmse       {r:.6} against {}\n",
            v["reference"].as_str().unwrap_or("")
        );
    }
    s
}
