//! `lancer render`: load, plan, build, render in parallel tiles, write the image atomically,
//! report. Each step is a function of its own, over plain values, so that another front end
//! (a Python module, say) can call them in the same order.

use crate::checkpoint::{self, Checkpoint};
use crate::cli_error::CliError;
use crate::film_memory::check_film_memory;
use crate::output::{check_output, default_checkpoint_path, write_with_fallback};
use crate::preview::LiveOutputs;
use crate::progress::Progress;
use crate::render_args::{RenderArgs, Resumed, apply_overrides, resumed_args};
use crate::split::{self, SAMPLES_PER_PASS, TILE_SIZE};
use crate::{input, stats, strategy_images};
use lancer::film::part::{PartMeta, write_part};
use lancer::film::spectral::SpectralSums;
use lancer::film::spectral_write::write_spectral_exr;
use lancer::film::{Film, PixelBounds, PixelSum};
use lancer::gbuffer::write::HALF_MAX;
use lancer::gbuffer::{GbufferConfig, GbufferFilm, GbufferHeader, write_gbuffer_exr};
use lancer::image_io::{ImageFormat, write_image, write_image_fn};
use lancer::render::strategies::StrategyImages;
use lancer::render::{RenderJob, RenderSettings, RenderStats, WorkUnit, work_units};
use lancer::{Scene, SceneDesc};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Runs `lancer render`: the steps in order, timed.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
    let Loaded {
        args,
        desc,
        resumed,
    } = load(args)?;
    let parse_s = t0.elapsed().as_secs_f64();
    let checkpoint = resumed.as_ref().map(|r| r.path.clone());
    let mut plan = plan(&args, &desc, resumed)?;
    let is_part = plan.pixels.is_part;
    crate::denoise::prepare(
        &args,
        &desc,
        &mut plan.state.film,
        is_part,
        checkpoint.as_deref(),
    )?;
    let t_build = Instant::now();
    let scene = build(&desc)?;
    let build_s = t_build.elapsed().as_secs_f64();
    let load_s = t0.elapsed().as_secs_f64();
    let settings = render_settings(&desc, &plan.pixels, args.spectral_mode());
    // The scene holds what it needs: the description's meshes need not stay for the render.
    drop(desc);
    let rendered = match render(&scene, &settings, &args, &mut plan)? {
        Outcome::Done(r) => r,
        Outcome::Interrupted(message) => {
            eprintln!("{message}");
            std::process::exit(130);
        }
    };
    if let Some(h) = &mut plan.gbuffer {
        h.render_time_seconds = Some(rendered.seconds as f32);
    }
    let denoised = crate::denoise::run(
        &args,
        &plan.state.film,
        plan.meta.scale,
        &plan.output,
        is_part,
    )?;
    let image = denoised.as_ref().map(|d| d.pixels.as_slice());
    let write_s = write(&args, &plan, rendered.live, image)?;
    if let Some(images) = rendered.strategies {
        strategy_images::write(images, &plan.state.film, plan.meta.scale, &plan.output)?;
    }
    let finished = Finished {
        stats: rendered.stats,
        threads: rendered.threads,
        load_s,
        phases: stats::Phases {
            parse: parse_s,
            build: build_s,
            render: rendered.seconds,
            denoise: denoised.map(|d| d.seconds),
            write: write_s,
            total: t0.elapsed().as_secs_f64(),
        },
    };
    report(&args, &plan, &scene, &settings, &finished)
}

/// What step [`load`] gives.
pub struct Loaded {
    /// The options: the command line's, or for `--resume` the checkpoint's merged with them.
    pub args: RenderArgs,
    /// The scene, with the command line's overrides applied.
    pub desc: SceneDesc,
    /// The checkpoint resumed from.
    pub resumed: Option<Resumed>,
}

/// Step 1: reads the checkpoint (with `--resume`, or `--resume-if-exists` when it exists) and the scene (printing its warnings), and
/// applies the overrides.
pub fn load(args: RenderArgs) -> Result<Loaded, CliError> {
    let (args, resumed) = resumed_args(args)?;
    let options = args.read.options();
    let loaded = if args.strict {
        let loaded = input::read(args.scene.as_deref(), &options)?;
        input::refuse_warnings(&loaded)?;
        loaded
    } else {
        input::load(args.scene.as_deref(), &options)?
    };
    if !args.quiet {
        input::print_notes(&loaded);
    }
    let mut desc = loaded.desc;
    apply_overrides(&mut desc, &args)?;
    Ok(Loaded {
        args,
        desc,
        resumed,
    })
}

/// A render's state: the film so far, the finished units of work, and what a checkpoint
/// records about how the render started.
pub struct RenderState {
    /// The film.
    pub film: Film,
    /// Which units of work are done, in the order of [`Plan::units`].
    pub done: Vec<bool>,
    /// Folder the render started in.
    pub cwd: PathBuf,
    /// Arguments the render started with.
    pub args: Vec<String>,
    /// A checkpoint was resumed from or written (and is to be removed at the end).
    pub checkpointed: bool,
}

/// What step [`plan`] gives: where the result goes, what this process renders, and the state
/// to start from.
pub struct Plan {
    /// The image, or the part of a split render.
    pub output: PathBuf,
    /// The pixels and samples this process renders.
    pub pixels: split::Plan,
    /// What a part records: scene hash, seed, spp, samples, the whole render's pixels, scale.
    pub meta: PartMeta,
    /// The units of work.
    pub units: Vec<WorkUnit>,
    /// The checkpoint file.
    pub checkpoint: PathBuf,
    /// The film and finished units: fresh, or the resumed checkpoint's.
    pub state: RenderState,
    /// For a `gbuffer` film, the header attributes of its image (the render time is filled in
    /// once known).
    pub gbuffer: Option<GbufferHeader>,
    /// For a `spectral` film, whether it is written in half floats (`savefp16`).
    pub spectral_fp16: Option<bool>,
}

/// Step 2: checks the outputs and the options against the scene, before any long work, and
/// works out the pixels, samples, units of work and film (fresh, or the checkpoint's).
pub fn plan(
    args: &RenderArgs,
    desc: &SceneDesc,
    resumed: Option<Resumed>,
) -> Result<Plan, CliError> {
    let output = args
        .output
        .clone()
        .or_else(|| desc.film.filename.as_ref().map(PathBuf::from))
        // pbrt-v4 writes a gbuffer film only as EXR.
        .unwrap_or_else(|| {
            PathBuf::from(
                if desc.film.gbuffer.is_some() || desc.film.spectral.is_some() {
                    "lancer.exr"
                } else {
                    "lancer.png"
                },
            )
        });
    check_output(&output)?;
    check_preview(args)?;
    let render_bounds = pixel_bounds(desc);
    if render_bounds.is_empty() {
        return Err(CliError::input(match &args.pixelbounds {
            Some(b) => format!(
                "--pixelbounds {} {} {} {} selects no pixel of the {}x{} image",
                b[0], b[1], b[2], b[3], desc.film.xresolution, desc.film.yresolution
            ),
            None => "the crop window selects no pixel".into(),
        }));
    }
    if desc.sampler.spp == 0 {
        return Err(CliError::input("samples per pixel must be at least 1"));
    }
    let split = args.split.map(|s| (s, args.split_by));
    split::check_split(desc, split)?;
    let pixels = split::plan(
        render_bounds,
        desc.integrator.sample_indices(desc.sampler.spp),
        args.samples.clone(),
        split,
    )?;
    if matches!(desc.integrator, lancer::integrator::Integrator::Sppm(_)) {
        check_sppm(args, &pixels, desc.sampler.spp)?;
    }
    if pixels.is_part && ImageFormat::from_path(&output) != Some(ImageFormat::Exr) {
        return Err(CliError::input(format!(
            "{}: a part of a split render (--split, --samples) is written as .exr",
            output.display()
        )));
    }
    if desc.film.gbuffer.is_some() {
        check_gbuffer(
            args,
            &output,
            &pixels,
            resumed.is_some(),
            "gbuffer",
            "g-buffer",
        )?;
    }
    if desc.film.spectral.is_some() {
        // The buckets hold radiance at the sampled wavelengths, which an RGB render has
        // not: refuse rather than write a file whose spectral channels are all zero.
        if !args.spectral_mode() {
            return Err(CliError::input(
                "Film \"spectral\" writes radiance per wavelength bucket, which needs the \
                 spectral mode: drop --rgb (or use Film \"rgb\")",
            ));
        }
        check_gbuffer(
            args,
            &output,
            &pixels,
            resumed.is_some(),
            "spectral",
            "spectral",
        )?;
    }
    let bounds = pixels.bounds;
    check_film_memory(&bounds, args.max_film_gib)?;
    let meta = pixels.part_meta(desc, args.spectral_mode());
    let units = work_units(&bounds, TILE_SIZE, pixels.samples.clone(), SAMPLES_PER_PASS);
    let checkpoint = args
        .checkpoint
        .clone()
        .unwrap_or_else(|| default_checkpoint_path(&output));
    if resumed.is_none() && checkpoint.exists() && !args.quiet {
        eprintln!(
            "warning: {} exists (an interrupted render?); this new render will replace it if it \
             is interrupted; to continue the old one instead, use --resume {}",
            checkpoint.display(),
            checkpoint.display()
        );
    }
    let state = match resumed {
        Some(r) => resumed_state(r, desc, &bounds, &units, meta.scene_hash)?,
        None => RenderState {
            film: new_film(desc, &bounds),
            done: vec![false; units.len()],
            cwd: std::env::current_dir().unwrap_or_default(),
            args: args.command_line.clone(),
            checkpointed: false,
        },
    };
    Ok(Plan {
        output,
        pixels,
        meta,
        units,
        checkpoint,
        state,
        gbuffer: desc
            .film
            .gbuffer
            .is_some()
            .then(|| GbufferHeader::of(desc, None)),
        spectral_fp16: desc.film.spectral.map(|_| desc.film.save_fp16),
    })
}

/// A fresh film over `bounds` for `desc`: with g-buffer sums for a `gbuffer` film.
fn new_film(desc: &SceneDesc, bounds: &PixelBounds) -> Film {
    let mut film = Film::new(desc.film.xresolution, desc.film.yresolution, *bounds);
    if let Some(g) = desc.film.gbuffer {
        let config = GbufferConfig::new(g, desc.camera.camera_from_world, desc.sampler.spp);
        film.gbuffer = Some(Box::new(GbufferFilm::new(config, bounds.area() as usize)));
    }
    if let Some(s) = desc.film.spectral {
        film.spectral = Some(Box::new(SpectralSums::new(s, bounds.area() as usize)));
    }
    film
}

/// Refuses what a `gbuffer` or `spectral` film (`kind`, its extra channels `extra`) cannot
/// do: an output other than EXR (pbrt-v4 writes them only as EXR), and the ways of rendering
/// in pieces (split parts, sample ranges, checkpoints and resuming), whose files keep the
/// colour sums only.
fn check_gbuffer(
    args: &RenderArgs,
    output: &Path,
    pixels: &split::Plan,
    resumed: bool,
    kind: &str,
    extra: &str,
) -> Result<(), CliError> {
    if ImageFormat::from_path(output) != Some(ImageFormat::Exr) {
        return Err(CliError::input(format!(
            "{}: a {kind} film is written only as OpenEXR (.exr), as in pbrt-v4; name the \
             output .exr (or use Film \"rgb\" for a PNG)",
            output.display()
        )));
    }
    let piece = if pixels.is_part {
        Some("a part of a split render (--split, --samples)")
    } else if resumed {
        Some("resuming from a checkpoint (--resume)")
    } else if args.checkpoint_every.is_some() {
        Some("a checkpointed render (--checkpoint-every)")
    } else {
        None
    };
    match piece {
        Some(what) => Err(CliError::input(format!(
            "a {kind} film cannot be rendered as {what} yet: parts and checkpoints keep the \
             colour sums only, not the {extra} channels; render it in one go"
        ))),
        None => Ok(()),
    }
}

/// Refuses what `sppm` cannot do: its iterations are not independent samples (each shrinks
/// the radii of the next), so a range of them (`--samples`, `--split-by samples`) and a
/// checkpoint between them (`--checkpoint-every`) have no meaning yet, and it gathers no
/// albedo and normal images for `--denoise`. A split by tiles is exact (every part traces the
/// same photons), and an interrupted render resumed with `--resume` starts again from its
/// first iteration (its checkpoint holds the image so far, not the photon state).
fn check_sppm(args: &RenderArgs, pixels: &split::Plan, spp: u32) -> Result<(), CliError> {
    let refused = if pixels.samples != (0..spp) {
        Some(format!(
            "a range of samples ({}..{} of {spp}; --samples, --split-by samples): each \
             iteration depends on those before it; split it by tiles (--split-by tiles)",
            pixels.samples.start, pixels.samples.end
        ))
    } else if args.checkpoint_every.is_some() {
        Some(
            "checkpoints at intervals (--checkpoint-every): the photon state between \
             iterations is not saved (an interrupted sppm render resumed with --resume starts \
             again from its first iteration)"
                .to_string(),
        )
    } else if args.denoise {
        Some("--denoise: sppm gathers no albedo and normal images for the denoiser".to_string())
    } else {
        None
    };
    match refused {
        Some(what) => Err(CliError::input(format!(
            "integrator \"sppm\" cannot render {what}"
        ))),
        None => Ok(()),
    }
}

/// Refuses a `--preview` that is not a PNG in a writable folder, or a nonsense interval.
fn check_preview(args: &RenderArgs) -> Result<(), CliError> {
    let Some(p) = &args.preview else {
        return Ok(());
    };
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
    Ok(())
}

/// The state saved in a checkpoint, if it is one of this very render: the same scene hash,
/// film and units of work.
fn resumed_state(
    Resumed { path, ckpt }: Resumed,
    desc: &SceneDesc,
    bounds: &PixelBounds,
    units: &[WorkUnit],
    scene_hash: u64,
) -> Result<RenderState, CliError> {
    if ckpt.scene_hash != scene_hash {
        return Err(CliError::input(format!(
            "{}: the scene or its options changed since this checkpoint was written \
             (scene hash {scene_hash:016x}, checkpoint {:016x}); render it anew",
            path.display(),
            ckpt.scene_hash
        )));
    }
    let f = &ckpt.film;
    if f.bounds != *bounds
        || (f.full_width, f.full_height) != (desc.film.xresolution, desc.film.yresolution)
        || ckpt.done.len() != units.len()
    {
        return Err(CliError::input(format!(
            "{}: the checkpoint's film or units of work do not match its options",
            path.display()
        )));
    }
    Ok(RenderState {
        film: ckpt.film,
        done: ckpt.done,
        cwd: ckpt.cwd,
        args: ckpt.args,
        checkpointed: true,
    })
}

/// The pixels to render: pbrt's `pixelbounds`, else its crop window
/// ([`lancer::scene::desc::FilmDesc::render_bounds`]).
pub fn pixel_bounds(desc: &SceneDesc) -> PixelBounds {
    desc.film.render_bounds()
}

/// Step 3: builds the scene (BVH, lights, textures).
pub fn build(desc: &SceneDesc) -> Result<Scene, CliError> {
    Scene::build(desc).map_err(|e| CliError::input(format!("scene: {e}")))
}

/// The renderer's settings for the pixels and samples of `pixels`, from the scene description;
/// the only place they are assembled.
pub fn render_settings(desc: &SceneDesc, pixels: &split::Plan, spectral: bool) -> RenderSettings {
    RenderSettings {
        bounds: pixels.bounds,
        samples: pixels.samples.clone(),
        tile_size: TILE_SIZE,
        spectral,
        ..RenderSettings::from_desc(desc)
    }
}

/// What step [`render`] gives when every unit of work is done.
pub struct Rendered {
    /// Samples, rays, NaNs.
    pub stats: RenderStats,
    /// Worker threads used.
    pub threads: usize,
    /// Seconds spent rendering.
    pub seconds: f64,
    /// The live outputs, still waiting for the final image.
    pub live: LiveOutputs,
    /// bdpt's strategy images, when the scene asks for them ([`strategy_images`]).
    pub strategies: Option<StrategyImages>,
}

/// How step [`render`] ends.
pub enum Outcome {
    /// Every unit of work is done.
    Done(Rendered),
    /// A signal stopped the render; the image so far and the checkpoint are written. The
    /// message says where, and how to continue.
    Interrupted(String),
}

/// Step 4: renders the units of work not done yet into `plan.state`, in parallel, with the
/// progress display and the live outputs; stops on a signal (SIGINT, SIGTERM, SIGHUP unless
/// ignored) or when a checkpoint is due, saves, and goes on (or, for a signal, ends).
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    args: &RenderArgs,
    plan: &mut Plan,
) -> Result<Outcome, CliError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| CliError::runtime(format!("cannot start worker threads: {e}")))?;
    checkpoint::install_handler().map_err(CliError::runtime)?;
    let state = &mut plan.state;
    let remaining: u64 = plan
        .units
        .iter()
        .zip(&state.done)
        .filter(|(_, d)| !**d)
        .map(|(u, _)| u.tile.area() * u.samples.len() as u64)
        .sum();
    let progress = Progress::new(
        remaining,
        args.quiet,
        args.progress,
        Duration::from_secs_f64(args.log_every),
    );
    let every = args
        .checkpoint_every
        .map(|m| Duration::from_secs_f64(m * 60.0));
    let t1 = Instant::now();
    let live = LiveOutputs::start(
        plan.pixels.bounds,
        plan.meta.scale,
        args.preview
            .clone()
            .map(|p| (p, Duration::from_secs_f64(args.preview_every))),
        args.display_server
            .clone()
            .map(|a| (a, plan.output.display().to_string())),
    );
    let on_unit = |unit: &WorkUnit, sums: &[PixelSum]| {
        progress.inc(unit.tile.area() * unit.samples.len() as u64);
        live.tile(&unit.tile, sums);
    };
    let resumed = state.done.iter().any(|&d| d);
    let strategies = strategy_images::start(settings, plan.pixels.is_part, resumed);
    let mut stats = RenderStats::default();
    loop {
        let deadline = every.map(|d| Instant::now() + d);
        let stop = || checkpoint::interrupted() || deadline.is_some_and(|d| Instant::now() >= d);
        let s = pool.install(|| {
            strategy_images::render_units(
                strategies.as_ref(),
                RenderJob {
                    scene,
                    settings,
                    film: &mut state.film,
                    units: &plan.units,
                    done: &mut state.done,
                    on_unit: &on_unit,
                    stop: &stop,
                },
            )
        });
        stats.add(&s);
        // A checkpoint stop is not a cancellation: only the last call's stop counts.
        stats.cancelled = s.cancelled;
        if state.done.iter().all(|&d| d) {
            break;
        }
        // Stopped by a signal or the checkpoint timer: save the image so far and the state.
        let image = (!plan.pixels.is_part).then_some(plan.output.as_path());
        progress.suspend(|| {
            save_checkpoint(
                image,
                state,
                &plan.meta,
                plan.gbuffer.as_ref(),
                plan.spectral_fp16,
                &plan.checkpoint,
            )
        })?;
        state.checkpointed = true;
        if checkpoint::interrupted() {
            progress.finish_and_clear();
            return Ok(Outcome::Interrupted(interrupted_message(plan)));
        }
    }
    progress.finish_and_clear();
    Ok(Outcome::Done(Rendered {
        stats,
        threads: pool.current_num_threads(),
        seconds: t1.elapsed().as_secs_f64(),
        live,
        strategies,
    }))
}

/// Writes the image so far to `image` (not for a part: a part file is written once complete)
/// and the checkpoint to `path`, both atomically. A g-buffer film's image so far has all its
/// channels (its checkpoint cannot be resumed: [`check_gbuffer`]).
fn save_checkpoint(
    image: Option<&Path>,
    state: &RenderState,
    meta: &PartMeta,
    gbuffer: Option<&GbufferHeader>,
    spectral_fp16: Option<bool>,
    path: &Path,
) -> Result<(), CliError> {
    if let Some(output) = image {
        let b = state.film.bounds;
        match (gbuffer, spectral_fp16) {
            (Some(h), _) => write_gbuffer_exr(output, &state.film, meta.scale, h).map(|_| ()),
            (None, Some(fp16)) => {
                write_spectral_exr(output, &state.film, meta.scale, fp16).map(|_| ())
            }
            (None, None) => {
                write_image(output, b.width(), b.height(), &state.film.image(meta.scale))
            }
        }
        .map_err(|e| CliError::runtime(e.to_string()))?;
    }
    Checkpoint {
        cwd: state.cwd.clone(),
        args: state.args.clone(),
        scene_hash: meta.scene_hash,
        done: state.done.clone(),
        film: state.film.clone(),
    }
    .write(path)
    .map_err(|e| CliError::runtime(format!("cannot write the checkpoint: {e}")))
}

/// What an interrupted render says: how far it got, what it saved, how to continue.
fn interrupted_message(plan: &Plan) -> String {
    let finished = plan.state.done.iter().filter(|&&d| d).count();
    format!(
        "interrupted: {} of {} units of work done; {}checkpoint {}; continue with \
         `lancer render -o {} --resume {}`",
        finished,
        plan.units.len(),
        if plan.pixels.is_part {
            String::new()
        } else {
            format!("image so far in {}, ", plan.output.display())
        },
        plan.checkpoint.display(),
        plan.output.display(),
        plan.checkpoint.display()
    )
}

/// Step 5: writes the image (or the part) atomically, to the rescue folder if the output
/// fails; hands the final image to the live outputs; removes the checkpoint once the result
/// is safe. `image`, when given, is written instead of the film's (the denoised image).
/// Returns the seconds spent encoding and writing.
pub fn write(
    args: &RenderArgs,
    plan: &Plan,
    live: LiveOutputs,
    image: Option<&[lancer::math::Rgb]>,
) -> Result<f64, CliError> {
    let t_write = Instant::now();
    let film = &plan.state.film;
    let bounds = plan.pixels.bounds;
    let fallback_dir = args
        .on_write_error
        .clone()
        .unwrap_or_else(std::env::temp_dir);
    let written = write_with_fallback(&plan.output, &fallback_dir, |path| {
        if let Some(h) = &plan.gbuffer {
            let clamped =
                write_gbuffer_exr(path, film, plan.meta.scale, h).map_err(|e| e.to_string())?;
            if clamped > 0 && !args.quiet {
                eprintln!(
                    "warning: {clamped} pixel values clamped to the largest half float, \
                     {HALF_MAX} (as pbrt-v4 does with savefp16)"
                );
            }
            Ok(())
        } else if let Some(fp16) = plan.spectral_fp16 {
            let clamped =
                write_spectral_exr(path, film, plan.meta.scale, fp16).map_err(|e| e.to_string())?;
            if clamped > 0 && !args.quiet {
                eprintln!(
                    "warning: {clamped} pixel values clamped to the largest half float, \
                     {HALF_MAX} (as pbrt-v4 does with savefp16)"
                );
            }
            Ok(())
        } else if plan.pixels.is_part {
            write_part(path, film, &plan.meta).map_err(|e| e.to_string())
        } else {
            // The film's pixels are computed as the encoder reads them: an image of them
            // beside the film would be the peak memory of a small render.
            let (w, h) = (bounds.width(), bounds.height());
            match image {
                Some(pixels) => write_image(path, w, h, pixels),
                None => write_image_fn(path, w, h, film.scaled_pixels(plan.meta.scale)),
            }
            .map_err(|e| e.to_string())
        }
    });
    let write_s = t_write.elapsed().as_secs_f64();
    live.finish(|| image.map_or_else(|| film.image(plan.meta.scale), <[_]>::to_vec));
    written?;
    if plan.state.checkpointed {
        let _ = std::fs::remove_file(&plan.checkpoint);
    }
    Ok(write_s)
}

/// What step [`report`] tells about a finished render besides its plan.
pub struct Finished {
    /// Samples, rays, NaNs.
    pub stats: RenderStats,
    /// Worker threads used.
    pub threads: usize,
    /// Seconds from the start to the built scene.
    pub load_s: f64,
    /// Seconds per phase.
    pub phases: stats::Phases,
}

/// Step 6: the one-line summary on stderr (unless quiet), the `--stats` summary on stdout,
/// and the NaN report (with `--check-nan`, the first bad sample's path, and an error).
pub fn report(
    args: &RenderArgs,
    plan: &Plan,
    scene: &Scene,
    settings: &RenderSettings,
    done: &Finished,
) -> Result<(), CliError> {
    let bounds = plan.pixels.bounds;
    let render_s = done.phases.render;
    if !args.quiet {
        eprintln!(
            "{}: {}x{} pixels, samples {}..{} of {} spp in {:.2} s (+{:.2} s loading): {:.2} M samples/s, {:.2} M rays/s",
            plan.output.display(),
            bounds.width(),
            bounds.height(),
            plan.pixels.samples.start,
            plan.pixels.samples.end,
            plan.meta.spp,
            render_s,
            done.load_s,
            done.stats.samples as f64 / render_s / 1e6,
            done.stats.rays as f64 / render_s / 1e6,
        );
    }
    if let Some(format) = args.stats {
        let summary = stats::RenderSummary {
            scene: args.scene.as_ref().map(|p| p.display().to_string()),
            output: plan.output.display().to_string(),
            size: (bounds.width(), bounds.height()),
            spp: plan.meta.spp,
            threads: done.threads,
            samples: done.stats.samples,
            nonfinite: done.stats.nonfinite,
            rays: done.stats.rays,
            spectral: args.spectral_mode(),
            integrator: settings.integrator.pbrt_name(),
            photons: done.stats.photons,
            light_paths: done.stats.light_paths,
            connections: done.stats.connections,
            merges: done.stats.merges,
        };
        let mem = stats::SceneMemory::of(scene);
        match format {
            stats::StatsFormat::Json => {
                println!("{}", stats::render_json(&summary, &done.phases, &mem))
            }
            stats::StatsFormat::Text => {
                print!("{}", stats::render_text(&summary, &done.phases, &mem))
            }
        }
    }
    report_nonfinite(
        scene,
        settings,
        plan.state.film.kind(),
        &done.stats,
        args.check_nan,
    )
}

/// Says how many samples were NaN or infinite; with `--check-nan`, replays the first one and
/// prints its path, and fails.
fn report_nonfinite(
    scene: &Scene,
    settings: &RenderSettings,
    film: lancer::film::tile::FilmKind,
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
    let (l, path) = lancer::render::trace_sample(scene, settings, film, id);
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
        // Pixel bounds win over the crop window, clipped to the image.
        d.film.pixel_bounds = Some([90, 120, 10, 20]);
        assert_eq!(
            pixel_bounds(&d),
            PixelBounds {
                x0: 90,
                x1: 100,
                y0: 10,
                y1: 20
            }
        );
    }
}
