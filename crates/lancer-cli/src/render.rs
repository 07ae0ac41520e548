//! `lancer render`: load, build, render in parallel tiles, write the image atomically.

use crate::cli_error::CliError;
use crate::{input, preview, progress, stats};
use clap::Args;
use lancer::film::{Film, PixelBounds};
use lancer::filter::Filter;
use lancer::image_io::{ImageFormat, write_image};
use lancer::integrator::Integrator;
use lancer::render::{RenderSettings, render_observed};
use lancer::{Scene, SceneDesc};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// Options of `lancer render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (.pbrt), or a bare mesh (.obj, .ply) to frame and light; without it, the built-in default scene.
    pub scene: Option<PathBuf>,
    /// Output image (.png or .exr); defaults to the scene's Film filename, else lancer.png.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Samples per pixel (overrides the scene).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Seed of the samplers (overrides the scene).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Image size WIDTHxHEIGHT (overrides the scene).
    #[arg(long, value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// No progress bar, no summary.
    #[arg(short, long)]
    pub quiet: bool,
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
}

/// Largest image side accepted, in pixels: the scene reader's limit.
pub const MAX_RESOLUTION: u32 = lancer_scene::pbrt::convert::MAX_RESOLUTION as u32;

/// Largest film accepted, in bytes of accumulators and output pixels: a render that could not
/// fit in memory is refused before it starts rather than killed by the allocator.
pub const MAX_FILM_BYTES: u64 = 16 << 30;

/// Memory a film over `bounds` needs: the accumulators and the finished image.
pub fn film_bytes(bounds: &PixelBounds) -> u64 {
    let per_pixel =
        std::mem::size_of::<lancer::film::PixelSum>() + std::mem::size_of::<lancer::math::Rgb>();
    bounds.area() * per_pixel as u64
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

/// Runs `lancer render`.
pub fn run(args: RenderArgs) -> Result<(), CliError> {
    let t0 = Instant::now();
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
    let bounds = pixel_bounds(&desc);
    if bounds.is_empty() {
        return Err(CliError::input("the crop window selects no pixel"));
    }
    if film_bytes(&bounds) > MAX_FILM_BYTES {
        return Err(CliError::input(format!(
            "a {}x{} image would need {:.1} GiB of memory for its film (the limit is {} GiB); \
             render it in parts with the film's \"cropwindow\"",
            bounds.width(),
            bounds.height(),
            film_bytes(&bounds) as f64 / (1u64 << 30) as f64,
            MAX_FILM_BYTES >> 30
        )));
    }
    if desc.sampler.spp == 0 {
        return Err(CliError::input("samples per pixel must be at least 1"));
    }

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
        samples: 0..desc.sampler.spp,
        spp: desc.sampler.spp,
        seed: desc.sampler.seed,
        sampler: desc.sampler.kind,
        filter: Filter::new(desc.filter),
        integrator: Integrator::from_desc(&desc.integrator),
        tile_size: 16,
        max_component_value: desc.film.max_component_value,
    };
    let mut film = Film::new(desc.film.xresolution, desc.film.yresolution, bounds);
    let bar = progress::bar(bounds.area(), args.quiet);
    let cancel = AtomicBool::new(false);
    let t1 = Instant::now();
    let live = preview::LiveOutputs::start(
        bounds,
        desc.film.scale,
        args.preview
            .clone()
            .map(|p| (p, std::time::Duration::from_secs_f64(args.preview_every))),
        args.display_server
            .clone()
            .map(|a| (a, output.display().to_string())),
    );
    let on_tile = |tile: &PixelBounds, sums: &[lancer::film::PixelSum]| {
        bar.inc(tile.area());
        live.tile(tile, sums);
    };
    let stats = pool.install(|| render_observed(&scene, &settings, &mut film, &on_tile, &cancel));
    bar.finish_and_clear();
    let render_s = t1.elapsed().as_secs_f64();

    let t_write = Instant::now();
    let pixels = film.image(desc.film.scale);
    let written = write_image(&output, bounds.width(), bounds.height(), &pixels)
        .map_err(|e| CliError::runtime(e.to_string()));
    let write_s = t_write.elapsed().as_secs_f64();
    live.finish(&pixels);
    written?;
    if !args.quiet {
        eprintln!(
            "{}: {}x{} pixels, {} spp in {:.2} s (+{:.2} s loading): {:.2} M samples/s, {:.2} M rays/s",
            output.display(),
            bounds.width(),
            bounds.height(),
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
            rays: stats.rays,
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
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
