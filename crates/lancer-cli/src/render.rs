//! `lancer render`: load, build, render in parallel tiles, write the image atomically.

use crate::checkpoint::{self, Checkpoint};
use crate::cli_error::CliError;
use crate::split::{self, SAMPLES_PER_PASS, TILE_SIZE};
use crate::{input, preview, progress, stats};
use clap::Args;
use lancer::film::{Film, PixelBounds, PixelSum};
use lancer::image_io::{ImageFormat, PartMeta, write_image, write_part};
use lancer::render::{RenderSettings, RenderStats, WorkUnit, render_units, work_units};
use lancer::{Scene, SceneDesc};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Options of `lancer render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (.pbrt), glTF model (.gltf, .glb) or bare mesh (.obj, .ply), framed and lit
    /// when it has no camera or light; without it, the built-in default scene.
    pub scene: Option<PathBuf>,
    /// Output image (.png or .exr); defaults to the scene's Film filename, else lancer.png.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Samples per pixel (overrides the scene).
    #[arg(long, conflicts_with = "resume")]
    pub spp: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Seed of the samplers (overrides the scene).
    #[arg(long, conflicts_with = "resume")]
    pub seed: Option<u64>,
    /// Image size WIDTHxHEIGHT (overrides the scene).
    #[arg(long, value_parser = parse_resolution, conflicts_with = "resume")]
    pub resolution: Option<(u32, u32)>,
    /// Render only the crop window x0,x1,y0,y1 (fractions of the image, pbrt's `cropwindow`).
    #[arg(long, value_name = "X0,X1,Y0,Y1", value_parser = split::parse_crop, conflicts_with = "resume")]
    pub crop: Option<[f32; 4]>,
    /// Take only the sample indices a..b of each pixel; writes a part (.exr) for `lancer merge`.
    #[arg(long, value_name = "A..B", value_parser = split::parse_samples, conflicts_with = "resume")]
    pub samples: Option<std::ops::Range<u32>>,
    /// Render part i of N (0-based) and write it as a part (.exr) for `lancer merge`.
    #[arg(long, value_name = "I/N", value_parser = split::parse_split, conflicts_with = "resume")]
    pub split: Option<split::Split>,
    /// How --split divides the render: bands of tiles, or ranges of samples.
    #[arg(long, value_enum, default_value_t, conflicts_with = "resume")]
    pub split_by: split::SplitBy,
    /// Write the image so far and a checkpoint every MINUTES (a checkpoint is also written on
    /// SIGINT/SIGTERM).
    #[arg(long, value_name = "MINUTES", value_parser = parse_minutes)]
    pub checkpoint_every: Option<f64>,
    /// Checkpoint file (default: the output path followed by .ckpt).
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Continue the render saved in this checkpoint, with its scene and options.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// No progress bar, no summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// Largest film memory accepted, in GiB: a bigger image is refused before rendering.
    #[arg(long, value_name = "GIB", default_value_t = MAX_FILM_GIB)]
    pub max_film_gib: u64,
    /// Where to save the image if writing the output fails after rendering (the folder was
    /// removed, the disk filled up): the render is never lost. Default: the system's
    /// temporary folder.
    #[arg(long, value_name = "DIR")]
    pub on_write_error: Option<PathBuf>,
    /// Debugging: report the first camera sample whose radiance is NaN or infinite (in row,
    /// column, sample order) with every vertex of its path, and exit with status 1 if there is
    /// one. Without it such samples are dropped (they add black) with a one-line warning.
    #[arg(long)]
    pub check_nan: bool,
    /// Stream the image as it converges to the tev viewer listening at HOST:PORT (tev's
    /// default port is 14158); an unreachable viewer is only a warning.
    #[arg(long, value_name = "HOST:PORT")]
    pub display_server: Option<String>,
    /// Rewrite this PNG with the image so far every --preview-every seconds, and at the end.
    #[arg(long, value_name = "FILE.png")]
    pub preview: Option<PathBuf>,
    /// Seconds between two rewrites of the --preview image.
    #[arg(long, value_name = "SECS", default_value_t = 5.0)]
    pub preview_every: f64,
    /// Print a summary on stdout at the end: times per phase, samples, rays, memory.
    #[arg(long, value_enum, value_name = "FORMAT")]
    pub stats: Option<stats::StatsFormat>,
    /// Render spectrally, as pbrt-v4 does: each sample carries three wavelengths and RGB
    /// colours are uplifted to spectra; to agree with pbrt-v4's images on saturated colours.
    /// The default (RGB) agrees with Mitsuba 3's RGB variants.
    #[arg(long, conflicts_with = "resume")]
    pub spectral: bool,
}

/// Largest image side accepted, in pixels: the scene reader's limit.
pub const MAX_RESOLUTION: u32 = lancer_scene::pbrt::convert::MAX_RESOLUTION as u32;

/// Largest film accepted by default, in GiB of accumulators and output pixels: a render that
/// could not fit in memory is refused before it starts rather than killed by the allocator
/// (`--max-film-gib` raises it on a bigger machine).
pub const MAX_FILM_GIB: u64 = 16;

/// Memory a film over `bounds` needs: the accumulators and the finished image.
pub fn film_bytes(bounds: &PixelBounds) -> u64 {
    let per_pixel =
        std::mem::size_of::<lancer::film::PixelSum>() + std::mem::size_of::<lancer::math::Rgb>();
    bounds.area() * per_pixel as u64
}

fn parse_minutes(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(m) if m > 0.0 && m < 1e9 => Ok(m),
        _ => Err(format!("'{s}' is not a positive number of minutes")),
    }
}

fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT"))?;
    let parse = |v: &str| -> Result<u32, String> {
        let n: u32 = v
            .trim()
            .parse()
            .map_err(|_| format!("'{v}' is not a positive integer"))?;
        if n == 0 || n > MAX_RESOLUTION {
            return Err(format!("{n} is outside 1..={MAX_RESOLUTION}"));
        }
        Ok(n)
    };
    Ok((parse(w)?, parse(h)?))
}

/// Applies the command line's overrides to the scene.
fn apply_overrides(desc: &mut SceneDesc, args: &RenderArgs) {
    if let Some(spp) = args.spp {
        desc.sampler.spp = spp;
    }
    if let Some(seed) = args.seed {
        desc.sampler.seed = seed;
    }
    if let Some((w, h)) = args.resolution {
        desc.film.xresolution = w;
        desc.film.yresolution = h;
        desc.film.pixel_bounds = None;
    }
    if let Some(c) = args.crop {
        desc.film.crop_window = c;
        desc.film.pixel_bounds = None;
    }
}

/// The pixels to render: pbrt's `pixelbounds`, else its crop window rounded as pbrt does
/// (⌈res·min⌉ to ⌈res·max⌉).
pub fn pixel_bounds(desc: &SceneDesc) -> PixelBounds {
    let (w, h) = (desc.film.xresolution as i32, desc.film.yresolution as i32);
    let full = PixelBounds {
        x0: 0,
        x1: w,
        y0: 0,
        y1: h,
    };
    if let Some([x0, x1, y0, y1]) = desc.film.pixel_bounds {
        return PixelBounds { x0, x1, y0, y1 }.intersect(&full);
    }
    let [cx0, cx1, cy0, cy1] = desc.film.crop_window;
    PixelBounds {
        x0: (w as f32 * cx0).ceil() as i32,
        x1: (w as f32 * cx1).ceil() as i32,
        y0: (h as f32 * cy0).ceil() as i32,
        y1: (h as f32 * cy1).ceil() as i32,
    }
    .intersect(&full)
}

/// Refuses an output that cannot be written, before any rendering: unknown extension, missing
/// folder, or a folder where files cannot be created.
pub fn check_output(path: &Path) -> Result<(), CliError> {
    if ImageFormat::from_path(path).is_none() {
        return Err(CliError::input(format!(
            "{}: unknown image format (use .png or .exr)",
            path.display()
        )));
    }
    if path.is_dir() {
        return Err(CliError::input(format!(
            "{}: cannot write: it is a folder",
            path.display()
        )));
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !dir.is_dir() {
        return Err(CliError::input(format!(
            "{}: cannot write: folder {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    let probe = dir.join(format!(".lancer-write-test-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(CliError::input(format!(
            "{}: cannot write in {}: {e}",
            path.display(),
            dir.display()
        ))),
    }
}

/// The checkpoint a render resumes from, with where it was read.
struct Resumed {
    path: PathBuf,
    ckpt: Checkpoint,
}

/// `lancer render --resume FILE`: the checkpoint's options, with this command line's scene
/// (if given, e.g. after moving it), output, checkpoint settings, threads and quietness.
fn resume_args(args: RenderArgs, path: &Path) -> Result<(RenderArgs, Resumed), CliError> {
    #[derive(clap::Parser)]
    #[command(no_binary_name = true)]
    struct Saved {
        #[command(flatten)]
        args: RenderArgs,
    }
    let ckpt = Checkpoint::read(path).map_err(|e| CliError::input(e.to_string()))?;
    let saved = <Saved as clap::Parser>::try_parse_from(&ckpt.args).map_err(|e| {
        CliError::input(format!(
            "{}: the saved options do not parse: {}",
            path.display(),
            e.to_string().lines().next().unwrap_or_default()
        ))
    })?;
    let mut a = saved.args;
    a.scene = args.scene.or(a.scene.map(|p| ckpt.cwd.join(p)));
    a.output = args.output.or(a.output.map(|p| ckpt.cwd.join(p)));
    a.checkpoint = args.checkpoint.or_else(|| Some(path.to_path_buf()));
    a.checkpoint_every = args.checkpoint_every.or(a.checkpoint_every);
    a.threads = args.threads;
    a.quiet = args.quiet;
    a.resume = None;
    let resumed = Resumed {
        path: path.to_path_buf(),
        ckpt,
    };
    Ok((a, resumed))
}

/// The default checkpoint path: the output's with `.ckpt` appended.
pub fn default_checkpoint_path(output: &Path) -> PathBuf {
    let mut p = output.as_os_str().to_os_string();
    p.push(".ckpt");
    PathBuf::from(p)
}

/// Runs `lancer render`.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    let (args, resumed) = match args.resume.clone() {
        Some(path) => {
            let (a, r) = resume_args(args, &path)?;
            (a, Some(r))
        }
        None => (args, None),
    };
    let loaded = input::load(args.scene.as_deref())?;
    let parse_s = t0.elapsed().as_secs_f64();
    let mut desc = loaded.desc;
    apply_overrides(&mut desc, &args);
    let output = args
        .output
        .clone()
        .or_else(|| desc.film.filename.as_ref().map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from("lancer.png"));
    check_output(&output)?;
    if let Some(p) = &args.preview {
        if ImageFormat::from_path(p) != Some(ImageFormat::Png) {
            return Err(CliError::input(format!(
                "{}: the preview is written as PNG; name it .png",
                p.display()
            )));
        }
        check_output(p)?;
        if !(args.preview_every.is_finite() && args.preview_every > 0.0) {
            return Err(CliError::input(
                "--preview-every must be a positive number of seconds",
            ));
        }
    }
    let render_bounds = pixel_bounds(&desc);
    if render_bounds.is_empty() {
        return Err(CliError::input("the crop window selects no pixel"));
    }
    if desc.sampler.spp == 0 {
        return Err(CliError::input("samples per pixel must be at least 1"));
    }
    let plan = split::plan(
        render_bounds,
        desc.sampler.spp,
        args.samples.clone(),
        args.split.map(|s| (s, args.split_by)),
    )?;
    if plan.is_part && ImageFormat::from_path(&output) != Some(ImageFormat::Exr) {
        return Err(CliError::input(format!(
            "{}: a part of a split render (--split, --samples) is written as .exr",
            output.display()
        )));
    }
    let bounds = plan.bounds;
    if film_bytes(&bounds) > args.max_film_gib.saturating_mul(1 << 30) {
        return Err(CliError::input(format!(
            "a {}x{} image would need {:.1} GiB of memory for its film (the limit is {} GiB, \
             --max-film-gib to change it); render it in parts with --split or --crop",
            bounds.width(),
            bounds.height(),
            film_bytes(&bounds) as f64 / (1u64 << 30) as f64,
            args.max_film_gib
        )));
    }
    let scene_hash = split::scene_hash_in_mode(&desc, args.spectral);
    let units = work_units(&bounds, TILE_SIZE, plan.samples.clone(), SAMPLES_PER_PASS);
    let ckpt_path = args
        .checkpoint
        .clone()
        .unwrap_or_else(|| default_checkpoint_path(&output));
    // A checkpoint this render resumed from or wrote is removed once the render is done.
    let mut wrote_ckpt = resumed.is_some();
    if resumed.is_none() && ckpt_path.exists() && !args.quiet {
        eprintln!(
            "warning: {} exists (an interrupted render?); this new render will replace it if it \
             is interrupted; to continue the old one instead, use --resume {}",
            ckpt_path.display(),
            ckpt_path.display()
        );
    }
    let (ckpt_cwd, ckpt_args, mut film, mut done) = match resumed {
        Some(Resumed { path, ckpt }) => {
            if ckpt.scene_hash != scene_hash {
                return Err(CliError::input(format!(
                    "{}: the scene or its options changed since this checkpoint was written \
                     (scene hash {scene_hash:016x}, checkpoint {:016x}); render it anew",
                    path.display(),
                    ckpt.scene_hash
                )));
            }
            let f = &ckpt.film;
            if f.bounds != bounds
                || (f.full_width, f.full_height) != (desc.film.xresolution, desc.film.yresolution)
                || ckpt.done.len() != units.len()
            {
                return Err(CliError::input(format!(
                    "{}: the checkpoint's film or units of work do not match its options",
                    path.display()
                )));
            }
            (ckpt.cwd, ckpt.args, ckpt.film, ckpt.done)
        }
        None => (
            std::env::current_dir().unwrap_or_default(),
            checkpoint::render_args(),
            Film::new(desc.film.xresolution, desc.film.yresolution, bounds),
            vec![false; units.len()],
        ),
    };

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| CliError::runtime(format!("cannot start worker threads: {e}")))?;
    let t_build = Instant::now();
    let scene = Scene::build(&desc).map_err(|e| CliError::input(format!("scene: {e}")))?;
    let build_s = t_build.elapsed().as_secs_f64();
    let load_s = t0.elapsed().as_secs_f64();

    let settings = RenderSettings {
        bounds,
        samples: plan.samples.clone(),
        tile_size: TILE_SIZE,
        spectral: args.spectral,
        ..RenderSettings::from_desc(&desc)
    };
    let part_meta = PartMeta {
        scene_hash,
        seed: desc.sampler.seed,
        spp: desc.sampler.spp,
        samples: plan.samples.clone(),
        render_bounds,
        scale: desc.film.scale,
    };
    checkpoint::install_handler().map_err(CliError::runtime)?;
    let remaining: u64 = units
        .iter()
        .zip(&done)
        .filter(|(_, d)| !**d)
        .map(|(u, _)| u.tile.area() * u.samples.len() as u64)
        .sum();
    let bar = progress::bar(remaining, args.quiet);
    let every = args
        .checkpoint_every
        .map(|m| Duration::from_secs_f64(m * 60.0));
    let t1 = Instant::now();
    let live = preview::LiveOutputs::start(
        bounds,
        desc.film.scale,
        args.preview
            .clone()
            .map(|p| (p, Duration::from_secs_f64(args.preview_every))),
        args.display_server
            .clone()
            .map(|a| (a, output.display().to_string())),
    );
    let on_unit = |unit: &WorkUnit, sums: &[PixelSum]| {
        bar.inc(unit.tile.area() * unit.samples.len() as u64);
        live.tile(&unit.tile, sums);
    };
    let mut stats = RenderStats::default();
    loop {
        let deadline = every.map(|d| Instant::now() + d);
        let stop = || checkpoint::interrupted() || deadline.is_some_and(|d| Instant::now() >= d);
        let s = pool.install(|| {
            render_units(
                &scene, &settings, &mut film, &units, &mut done, &on_unit, &stop,
            )
        });
        stats.add(&s);
        // A checkpoint stop is not a cancellation: only the last call's stop counts.
        stats.cancelled = s.cancelled;
        if done.iter().all(|&d| d) {
            break;
        }
        // Stopped by a signal or the checkpoint timer: save the image so far and the state.
        bar.suspend(|| -> Result<(), CliError> {
            if !plan.is_part {
                write_image(
                    &output,
                    bounds.width(),
                    bounds.height(),
                    &film.image(desc.film.scale),
                )
                .map_err(|e| CliError::runtime(e.to_string()))?;
            }
            Checkpoint {
                cwd: ckpt_cwd.clone(),
                args: ckpt_args.clone(),
                scene_hash,
                done: done.clone(),
                film: film.clone(),
            }
            .write(&ckpt_path)
            .map_err(|e| CliError::runtime(format!("cannot write the checkpoint: {e}")))
        })?;
        wrote_ckpt = true;
        if checkpoint::interrupted() {
            bar.finish_and_clear();
            let finished = done.iter().filter(|&&d| d).count();
            eprintln!(
                "interrupted: {} of {} units of work done; {}checkpoint {}; continue with \
                 `lancer render -o {} --resume {}`",
                finished,
                units.len(),
                if plan.is_part {
                    String::new()
                } else {
                    format!("image so far in {}, ", output.display())
                },
                ckpt_path.display(),
                output.display(),
                ckpt_path.display()
            );
            std::process::exit(130);
        }
    }
    bar.finish_and_clear();
    let render_s = t1.elapsed().as_secs_f64();

    let t_write = Instant::now();
    let pixels = film.image(desc.film.scale);
    let fallback_dir = args
        .on_write_error
        .clone()
        .unwrap_or_else(std::env::temp_dir);
    let written = write_with_fallback(&output, &fallback_dir, |path| {
        if plan.is_part {
            write_part(path, &film, &part_meta).map_err(|e| e.to_string())
        } else {
            write_image(path, bounds.width(), bounds.height(), &pixels).map_err(|e| e.to_string())
        }
    });
    let write_s = t_write.elapsed().as_secs_f64();
    live.finish(&pixels);
    written?;
    if wrote_ckpt {
        let _ = std::fs::remove_file(&ckpt_path);
    }
    if !args.quiet {
        eprintln!(
            "{}: {}x{} pixels, samples {}..{} of {} spp in {:.2} s (+{:.2} s loading): {:.2} M samples/s, {:.2} M rays/s",
            output.display(),
            bounds.width(),
            bounds.height(),
            plan.samples.start,
            plan.samples.end,
            desc.sampler.spp,
            render_s,
            load_s,
            stats.samples as f64 / render_s / 1e6,
            stats.rays as f64 / render_s / 1e6,
        );
    }
    if args.stats == Some(stats::StatsFormat::Json) {
        let summary = stats::RenderSummary {
            scene: args.scene.as_ref().map(|p| p.display().to_string()),
            output: output.display().to_string(),
            size: (bounds.width(), bounds.height()),
            spp: desc.sampler.spp,
            threads: pool.current_num_threads(),
            samples: stats.samples,
            nonfinite: stats.nonfinite,
            rays: stats.rays,
            spectral: args.spectral,
        };
        let phases = stats::Phases {
            parse: parse_s,
            build: build_s,
            render: render_s,
            write: write_s,
            total: t0.elapsed().as_secs_f64(),
        };
        let mem = stats::SceneMemory::of(&scene);
        println!("{}", stats::render_json(&summary, &phases, &mem));
    }
    report_nonfinite(&scene, &settings, &stats, args.check_nan)
}

/// Writes the result with `write` to `output`; if that fails (a write error the checks before
/// rendering could not foresee), writes it into `fallback_dir` under a name of its own instead,
/// and reports both, so that hours of rendering are not lost to a full disk.
fn write_with_fallback(
    output: &Path,
    fallback_dir: &Path,
    write: impl Fn(&Path) -> Result<(), String>,
) -> Result<(), CliError> {
    let Err(first) = write(output) else {
        return Ok(());
    };
    let name = output
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "lancer.exr".into());
    let rescue = fallback_dir.join(format!("lancer-rescued-{}-{name}", std::process::id()));
    match write(&rescue) {
        Ok(()) => Err(CliError::runtime(format!(
            "{first}; the image was saved to {} instead",
            rescue.display()
        ))),
        Err(second) => Err(CliError::runtime(format!(
            "{first}; saving it to {} failed too: {second}",
            rescue.display()
        ))),
    }
}

/// Says how many samples were NaN or infinite; with `--check-nan`, replays the first one and
/// prints its path, and fails.
fn report_nonfinite(
    scene: &Scene,
    settings: &RenderSettings,
    stats: &RenderStats,
    check_nan: bool,
) -> Result<(), CliError> {
    let Some(id) = stats.first_nonfinite else {
        return Ok(());
    };
    let what = format!(
        "{} camera sample{} gave NaN or infinite radiance and {} dropped; the first is sample {} \
         of pixel ({}, {})",
        stats.nonfinite,
        if stats.nonfinite == 1 { "" } else { "s" },
        if stats.nonfinite == 1 { "was" } else { "were" },
        id.sample,
        id.x,
        id.y
    );
    if !check_nan {
        eprintln!("warning: {what} (--check-nan shows its path)");
        return Ok(());
    }
    let (l, path) = lancer::render::trace_sample(scene, settings, id);
    eprintln!("{what}; its radiance is {l:?}; its path:");
    for v in &path {
        eprintln!(
            "  bounce {}: primitive {} at {:?}, n {:?}, shading n {:?}, wo {:?}; sampled wi {:?}, \
             f {:?}, pdf {:?}; throughput before {:?}, radiance so far {:?}",
            v.depth, v.prim, v.p, v.n, v.ns, v.wo, v.wi, v.f, v.pdf, v.beta, v.l
        );
    }
    if path.is_empty() {
        eprintln!("  (no surface vertex recorded: the camera ray or a light gave it)");
    }
    Err(CliError::runtime(
        "--check-nan: a sample was not finite (see above)",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_write_falls_back_to_the_rescue_folder() {
        let dir = lancer_testing::ScratchDir::new("rescue");
        let out = Path::new("/no/such/folder/image.exr");
        let write =
            |p: &Path| std::fs::write(p, b"pixels").map_err(|e| format!("{}: {e}", p.display()));
        let e = write_with_fallback(out, &dir, write).unwrap_err();
        let rescued = dir.join(format!("lancer-rescued-{}-image.exr", std::process::id()));
        assert_eq!(std::fs::read(&rescued).unwrap(), b"pixels");
        let msg = e.message;
        assert!(msg.contains("/no/such/folder/image.exr"), "{msg}");
        assert!(msg.contains(&rescued.display().to_string()), "{msg}");
        // Both failing: the message says so, and names both places.
        let e = write_with_fallback(out, Path::new("/no/such/rescue"), write).unwrap_err();
        assert!(e.message.contains("failed too"), "{}", e.message);
        // A write that works goes to the output only.
        let ok = dir.join("ok.exr");
        write_with_fallback(&ok, &dir, write).unwrap();
        assert!(ok.exists());
    }

    #[test]
    fn resolutions_parse_and_absurd_ones_are_refused() {
        assert_eq!(parse_resolution("640x480"), Ok((640, 480)));
        assert!(parse_resolution("0x10").is_err());
        assert!(parse_resolution("-5x10").is_err());
        assert!(parse_resolution("100000x10").is_err());
        assert!(parse_resolution("abc").is_err());
    }

    #[test]
    fn crop_window_rounds_like_pbrt() {
        let mut d = SceneDesc::default();
        d.film.xresolution = 100;
        d.film.yresolution = 50;
        d.film.crop_window = [0.25, 0.755, 0.0, 0.5];
        assert_eq!(
            pixel_bounds(&d),
            PixelBounds {
                x0: 25,
                x1: 76,
                y0: 0,
                y1: 25
            }
        );
    }
}
