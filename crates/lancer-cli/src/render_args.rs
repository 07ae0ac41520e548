//! The options of `lancer render`, pbrt-v4's spellings of them, their overrides of the scene,
//! and the options a resumed render takes from its checkpoint.

use crate::checkpoint::Checkpoint;
use crate::cli_error::CliError;
use crate::progress::{LINE_INTERVAL, ProgressMode};
use crate::{split, stats};
use clap::Args;
use lancer::SceneDesc;
use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// Options of `lancer render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene file (.pbrt), glTF model (.gltf, .glb) or bare mesh (.obj, .ply), framed and lit
    /// when it has no camera or light; `-` reads a pbrt scene from standard input; without it,
    /// the built-in default scene.
    pub scene: Option<PathBuf>,
    /// Output image (.png or .exr); defaults to the scene's Film filename, else lancer.png.
    #[arg(short, long, visible_alias = "outfile")]
    pub output: Option<PathBuf>,
    /// Samples per pixel (overrides the scene).
    #[arg(long, conflicts_with = "resume")]
    pub spp: Option<u32>,
    /// Worker threads (default: all cores).
    #[arg(long, visible_alias = "nthreads")]
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
    /// pbrt's spelling of --crop: the crop window as four numbers x0 x1 y0 y1.
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"],
          conflicts_with_all = ["crop", "resume"])]
    pub cropwindow: Option<Vec<f32>>,
    /// Render only the pixels x0 ≤ x < x1, y0 ≤ y < y1 (pbrt's `--pixelbounds`; overrides the
    /// scene's crop window and pixel bounds).
    #[arg(long, num_args = 4, value_names = ["X0", "X1", "Y0", "Y1"],
          conflicts_with_all = ["crop", "cropwindow", "resume"])]
    pub pixelbounds: Option<Vec<i32>>,
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
    /// SIGINT/SIGTERM, and on SIGHUP unless it is ignored, as under nohup).
    #[arg(long, value_name = "MINUTES", value_parser = parse_minutes)]
    pub checkpoint_every: Option<f64>,
    /// Checkpoint file (default: the output path followed by .ckpt).
    #[arg(long, value_name = "FILE")]
    pub checkpoint: Option<PathBuf>,
    /// Continue the render saved in this checkpoint, with its scene and options.
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Continue from the checkpoint (--checkpoint, default OUTPUT.ckpt) when it exists, with
    /// the same checks as --resume and this command line's options, which must be the
    /// checkpoint's; start afresh when it does not: one command line serves the first run and
    /// every rerun (a requeued batch job).
    #[arg(long, conflicts_with = "resume")]
    pub resume_if_exists: bool,
    /// No progress bar, no progress lines, no summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// Every warning of the scene reader is an error (exit status 2), as pbrt-v4 refuses
    /// parameters it does not use.
    #[arg(long)]
    pub strict: bool,
    /// What the reader makes of displaced meshes.
    #[command(flatten)]
    pub read: crate::input::ReadArgs,
    /// How progress is shown on stderr: `auto` (a bar on a terminal, plain lines in a log
    /// file), `bar`, `lines`, or `json` (one JSON object per line, for programs).
    #[arg(long, value_enum, value_name = "MODE", default_value_t)]
    pub progress: ProgressMode,
    /// Longest silence, in seconds, between two progress lines in a log (a line also comes at
    /// each tenth of the work).
    #[arg(long, value_name = "SECS", default_value_t = LINE_INTERVAL.as_secs_f64(),
          value_parser = parse_seconds)]
    pub log_every: f64,
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
    /// Print a summary on stdout at the end: times per phase, samples, rays, memory; as text,
    /// or as one JSON object with `--stats json` (a bare --stats, as in pbrt, means text).
    #[arg(long, value_enum, value_name = "FORMAT", num_args = 0..=1, default_missing_value = "text")]
    pub stats: Option<stats::StatsFormat>,
    /// Render spectrally, as pbrt-v4 does: the default (each sample carries four wavelengths
    /// and RGB colours are uplifted to spectra). Accepted for scripts written when RGB was
    /// the default.
    #[arg(long, conflicts_with = "resume")]
    pub spectral: bool,
    /// Render in RGB, as Mitsuba 3's RGB variants and Tungsten do: to compare with their
    /// images, or to reproduce a render made in RGB (its parts and checkpoints).
    #[arg(long, conflicts_with_all = ["resume", "spectral"])]
    pub rgb: bool,
    /// Denoise the image with Open Image Denoise's network (lancer's own CPU inference), from
    /// the colour, albedo and shading normal rendered in the same pass: for previews and low
    /// sample counts, not for reference images. A part of a split render (--split,
    /// --samples) is not denoised but keeps the albedo and normal sums, for `lancer merge
    /// --denoise`.
    #[arg(long)]
    pub denoise: bool,
    /// With --denoise: also write the denoiser's inputs beside the output, as OUT.noisy.exr,
    /// OUT.albedo.exr and OUT.normal.exr (RGB float), for `lancer img denoise` or another
    /// denoiser.
    #[arg(long, requires = "denoise")]
    pub denoise_inputs: bool,
    /// Not an option: the arguments given after `lancer render` ([`crate::run`] sets them),
    /// which a new checkpoint records so that `--resume` renders with them again.
    #[arg(skip)]
    pub command_line: Vec<String>,
}

impl RenderArgs {
    /// True for a spectral render: the default, unless `--rgb` was given.
    pub fn spectral_mode(&self) -> bool {
        !self.rgb
    }
}

/// Largest image side accepted, in pixels: the scene reader's limit.
pub const MAX_RESOLUTION: u32 = lancer_scene::pbrt::convert::MAX_RESOLUTION as u32;

/// Largest film accepted by default, in GiB of accumulators and output pixels: a render that
/// could not fit in memory is refused before it starts rather than killed by the allocator
/// (`--max-film-gib` raises it on a bigger machine).
pub const MAX_FILM_GIB: u64 = 16;

fn parse_minutes(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(m) if m > 0.0 && m < 1e9 => Ok(m),
        _ => Err(format!("'{s}' is not a positive number of minutes")),
    }
}

fn parse_seconds(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x > 0.0 && x < 1e9 => Ok(x),
        _ => Err(format!("'{s}' is not a positive number of seconds")),
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

/// pbrt users write `--stats` alone, often right before the scene (`--stats scene.pbrt`),
/// where clap would take the scene for the format: a `--stats` followed by anything but a
/// format name becomes `--stats=text`. Arguments after `--` are left alone.
pub fn bare_stats_as_text(args: Vec<OsString>) -> Vec<OsString> {
    use clap::ValueEnum;
    let is_format = |a: Option<&OsString>| {
        a.and_then(|a| a.to_str())
            .is_some_and(|a| stats::StatsFormat::from_str(a, false).is_ok())
    };
    let mut out = Vec::with_capacity(args.len());
    let mut options = true;
    for (i, a) in args.iter().enumerate() {
        if options && a == "--stats" && !is_format(args.get(i + 1)) {
            out.push(OsString::from("--stats=text"));
            continue;
        }
        options &= a != "--";
        out.push(a.clone());
    }
    out
}

/// Four values as the command line showed them: `a b c d`.
fn show4<T: ToString>(v: [T; 4]) -> String {
    v.map(|x| x.to_string()).join(" ")
}

/// The crop window of `--cropwindow x0 x1 y0 y1` (pbrt's spelling of `--crop`), checked.
fn cropwindow(args: &RenderArgs) -> Result<Option<[f32; 4]>, CliError> {
    let Some(&[x0, x1, y0, y1]) = args.cropwindow.as_deref() else {
        return Ok(None);
    };
    let c = [x0, x1, y0, y1];
    split::check_crop(c)
        .map(Some)
        .map_err(|e| CliError::input(format!("--cropwindow {}: {e}", show4(c))))
}

/// The pixel bounds of `--pixelbounds x0 x1 y0 y1` (pbrt's option), checked.
fn pixelbounds(args: &RenderArgs) -> Result<Option<[i32; 4]>, CliError> {
    let Some(&[x0, x1, y0, y1]) = args.pixelbounds.as_deref() else {
        return Ok(None);
    };
    let b = [x0, x1, y0, y1];
    split::check_pixel_bounds(b)
        .map(Some)
        .map_err(|e| CliError::input(format!("--pixelbounds {}: {e}", show4(b))))
}

/// Applies the command line's overrides to the scene.
pub fn apply_overrides(desc: &mut SceneDesc, args: &RenderArgs) -> Result<(), CliError> {
    let (cropwindow, pixelbounds) = (cropwindow(args)?, pixelbounds(args)?);
    if let Some(spp) = args.spp {
        desc.sampler.spp = spp;
        // pbrt-v4's --spp sets mlt's mutations per pixel (mlt takes no pixel samples).
        if let lancer::integrator::Integrator::Mlt(o) = &mut desc.integrator {
            o.mutations_per_pixel = spp;
        }
    }
    if let Some(seed) = args.seed {
        desc.sampler.seed = seed;
    }
    if let Some((w, h)) = args.resolution {
        desc.film.xresolution = w;
        desc.film.yresolution = h;
        desc.film.pixel_bounds = None;
    }
    if let Some(c) = args.crop.or(cropwindow) {
        desc.film.crop_window = c;
        desc.film.pixel_bounds = None;
    }
    if let Some(b) = pixelbounds {
        desc.film.pixel_bounds = Some(b);
    }
    Ok(())
}

/// The checkpoint a render resumes from, with where it was read.
pub struct Resumed {
    /// The checkpoint file.
    pub path: PathBuf,
    /// What it holds.
    pub ckpt: Checkpoint,
}

/// The options to render with and the checkpoint to continue, if any: `--resume FILE`'s
/// ([`resume_args`]), `--resume-if-exists`'s ([`resume_if_exists`]), or none.
pub fn resumed_args(args: RenderArgs) -> Result<(RenderArgs, Option<Resumed>), CliError> {
    if let Some(path) = args.resume.clone() {
        let (a, r) = resume_args(args, &path)?;
        return Ok((a, Some(r)));
    }
    if args.resume_if_exists {
        return resume_if_exists(args);
    }
    Ok((args, None))
}

/// The options that decide a render's pixels and samples (those `--resume` takes from the
/// checkpoint and refuses on the command line), by name, as the command line gave them: a
/// checkpoint continued by `--resume-if-exists` must have been started with the same.
fn pixel_options(a: &RenderArgs) -> [(&'static str, String); 10] {
    [
        ("--spp", format!("{:?}", a.spp)),
        ("--seed", format!("{:?}", a.seed)),
        ("--resolution", format!("{:?}", a.resolution)),
        ("--crop", format!("{:?}", a.crop)),
        ("--cropwindow", format!("{:?}", a.cropwindow)),
        ("--pixelbounds", format!("{:?}", a.pixelbounds)),
        ("--samples", format!("{:?}", a.samples)),
        ("--split", format!("{:?}", a.split)),
        ("--split-by", format!("{:?}", a.split_by)),
        ("--rgb", format!("{:?}", a.rgb)),
    ]
}

/// `lancer render … --resume-if-exists`: when the checkpoint exists, this command line's
/// options with the checkpoint to continue, after checking that the checkpoint was started
/// with the same options that decide pixels (the scene hash, film and units of work are
/// checked as for `--resume` when the plan is made); when it does not, the options as they are.
fn resume_if_exists(args: RenderArgs) -> Result<(RenderArgs, Option<Resumed>), CliError> {
    let path = match (&args.checkpoint, &args.output) {
        (Some(c), _) => c.clone(),
        (None, Some(o)) => crate::output::default_checkpoint_path(o),
        (None, None) => {
            return Err(CliError::input(
                "--resume-if-exists needs the output (-o) or --checkpoint, to know which \
                 checkpoint to look for",
            ));
        }
    };
    if !path.exists() {
        return Ok((args, None));
    }
    let ckpt = Checkpoint::read(&path).map_err(|e| CliError::input(e.to_string()))?;
    let saved = parse_saved(&ckpt, &path)?;
    let differ: Vec<&str> = pixel_options(&saved)
        .into_iter()
        .zip(pixel_options(&args))
        .filter(|(a, b)| a.1 != b.1)
        .map(|(a, _)| a.0)
        .collect();
    if !differ.is_empty() {
        return Err(CliError::input(format!(
            "{}: this checkpoint is of a render started with other {} ({}); remove it to \
             start afresh, or continue it with --resume {}",
            path.display(),
            if differ.len() == 1 {
                "option"
            } else {
                "options"
            },
            differ.join(", "),
            path.display()
        )));
    }
    if !args.quiet {
        let done = ckpt.done.iter().filter(|&&d| d).count();
        eprintln!(
            "{}: continuing the render saved there ({done} of {} units of work done)",
            path.display(),
            ckpt.done.len()
        );
    }
    let mut a = args;
    a.checkpoint = Some(path.clone());
    Ok((a, Some(Resumed { path, ckpt })))
}

/// The options saved in a checkpoint, parsed as the command line's.
fn parse_saved(ckpt: &Checkpoint, path: &Path) -> Result<RenderArgs, CliError> {
    #[derive(clap::Parser)]
    #[command(no_binary_name = true)]
    struct Saved {
        #[command(flatten)]
        args: RenderArgs,
    }
    let saved_args = bare_stats_as_text(ckpt.args.iter().map(OsString::from).collect());
    let saved = <Saved as clap::Parser>::try_parse_from(saved_args).map_err(|e| {
        CliError::input(format!(
            "{}: the saved options do not parse: {}",
            path.display(),
            e.to_string().lines().next().unwrap_or_default()
        ))
    })?;
    Ok(saved.args)
}

/// The refusal to continue with `--denoise` the checkpoint at `path`, written by a render
/// without it: the work it holds has no albedo and normal sums (they would be zero there).
pub fn checkpoint_without_sums(path: &Path) -> CliError {
    CliError::input(format!(
        "{}: this checkpoint was written by a render without --denoise, so it has no albedo \
         and normal sums for the work it holds, which the denoiser needs: continue it without \
         --denoise (lancer render -o OUT --resume {}), or remove it to render afresh with \
         --denoise",
        path.display(),
        path.display()
    ))
}

/// `lancer render --resume FILE`: the checkpoint's options, with this command line's scene
/// (if given, e.g. after moving it), output, checkpoint settings, threads and quietness.
pub fn resume_args(args: RenderArgs, path: &Path) -> Result<(RenderArgs, Resumed), CliError> {
    let ckpt = Checkpoint::read(path).map_err(|e| CliError::input(e.to_string()))?;
    let mut a = parse_saved(&ckpt, path)?;
    // The checkpoint's options win; a --denoise it was not rendered with is refused rather
    // than dropped in silence.
    if args.denoise && !a.denoise {
        return Err(checkpoint_without_sums(path));
    }
    let in_cwd = |p: PathBuf| {
        if p == Path::new("-") {
            p
        } else {
            ckpt.cwd.join(p)
        }
    };
    a.scene = args.scene.or(a.scene.map(in_cwd));
    a.output = args.output.or(a.output.map(|p| ckpt.cwd.join(p)));
    a.checkpoint = args.checkpoint.or_else(|| Some(path.to_path_buf()));
    a.checkpoint_every = args.checkpoint_every.or(a.checkpoint_every);
    a.threads = args.threads;
    a.quiet = args.quiet;
    a.progress = args.progress;
    a.log_every = args.log_every;
    a.resume = None;
    a.resume_if_exists = false;
    let resumed = Resumed {
        path: path.to_path_buf(),
        ckpt,
    };
    Ok((a, resumed))
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
    fn a_bare_stats_means_text_and_a_format_is_kept() {
        let v = |a: &[&str]| a.iter().map(OsString::from).collect::<Vec<_>>();
        assert_eq!(
            bare_stats_as_text(v(&["render", "--stats", "s.pbrt"])),
            v(&["render", "--stats=text", "s.pbrt"])
        );
        assert_eq!(
            bare_stats_as_text(v(&["render", "s.pbrt", "--stats"])),
            v(&["render", "s.pbrt", "--stats=text"])
        );
        let kept = v(&["render", "--stats", "json", "s.pbrt", "--", "--stats"]);
        assert_eq!(bare_stats_as_text(kept.clone()), kept);
    }

    #[test]
    fn resume_if_exists_compares_every_option_that_resume_refuses() {
        #[derive(clap::Parser)]
        #[command(no_binary_name = true)]
        struct Render {
            #[command(flatten)]
            args: RenderArgs,
        }
        let cmd = <Render as clap::CommandFactory>::command();
        let args = <Render as clap::Parser>::try_parse_from(Vec::<String>::new())
            .unwrap()
            .args;
        let mut compared: Vec<String> = pixel_options(&args)
            .iter()
            .map(|(n, _)| n.to_string())
            .collect();
        // `--spectral` is the default mode (given or not, the same render), and
        // `--resume-if-exists` the other way of resuming.
        let mut refused: Vec<String> = cmd
            .get_arguments()
            .filter(|a| {
                cmd.get_arg_conflicts_with(a)
                    .iter()
                    .any(|c| c.get_id() == "resume")
            })
            .map(|a| format!("--{}", a.get_long().unwrap_or_default()))
            .filter(|n| n != "--spectral" && n != "--resume-if-exists")
            .collect();
        compared.sort();
        refused.sort();
        assert_eq!(compared, refused);
    }
}
