//! `lancer img`: the image tool (pbrt-v4's `imgtool` for the everyday jobs).
//!
//! - `img diff A B` compares A with the reference B: channel means, relative MSE, pbrt-v4's
//!   MRSE, MSE, RMSE, MAE and the relative error of the channel means (see [`metrics`]);
//!   `--threshold X` turns one of them into an exit status; `-o` writes `|A − B|`.
//! - `img convert IN OUT` crops, resizes (box filter), exposes and tone-maps, EXR ↔ PNG.
//! - `img info IMG` prints size, channels and per-channel mean, min, max, NaN and ∞ counts.
//! - `img denoise COLOR [--albedo A [--normal N]] -o OUT` runs the denoiser ([`denoise`]).
//!
//! Images are read as lancer reads textures (PNG decoded from sRGB to linear, EXR as stored,
//! JPEG too) and written as lancer writes renders (PNG 8-bit sRGB clamped to [0, 1], EXR
//! 32-bit float), atomically. Exit status: 0, 1 when `diff --threshold` is exceeded, 2 for any
//! error (unreadable or unwritable file, bad option, images of different sizes).

pub mod denoise;
pub mod metrics;
pub mod ops;

use crate::cli_error::CliError;
use clap::{Args, Subcommand, ValueEnum};
use lancer::image_io::{ImageFormat, ImageWriteError, write_image};
use lancer::math::Rgb;
use lancer_scene::image_read::{Encoding, MAX_SIDE, MAX_TEXELS, read_image};
use metrics::{ChannelStats, DiffMetrics, diff_metrics, difference_image, rgb_stats};
use ops::{Crop, Picture, Tonemap};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// The subcommands of `lancer img`.
#[derive(Subcommand, Debug)]
pub enum ImgCommand {
    /// Compare image A with the reference B: channel means and error metrics.
    Diff(DiffArgs),
    /// Convert an image (EXR ↔ PNG), with crop, resize, exposure and tone mapping.
    Convert(ConvertArgs),
    /// Size, channels and per-channel mean, min, max, NaN and infinity counts of an image.
    Info(ImgInfoArgs),
    /// Denoise an HDR render with Open Image Denoise's network (optionally with its albedo and
    /// normal images).
    Denoise(denoise::DenoiseArgs),
}

/// The metric `diff --threshold` compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Metric {
    /// Relative MSE: mean of (a − b)² / (b² + 0.01).
    Relmse,
    /// pbrt-v4's MRSE: mean of (a − b)² / (b + 0.01)².
    Mrse,
    /// Mean squared error.
    Mse,
    /// Root mean squared error.
    Rmse,
    /// Mean absolute error.
    Mae,
    /// Largest relative error of a channel mean: |mean_A − mean_B| / mean_B.
    Mre,
}

impl Metric {
    fn name(self) -> &'static str {
        match self {
            Metric::Relmse => "relmse",
            Metric::Mrse => "mrse",
            Metric::Mse => "mse",
            Metric::Rmse => "rmse",
            Metric::Mae => "mae",
            Metric::Mre => "mre",
        }
    }

    fn of(self, m: &DiffMetrics) -> f64 {
        match self {
            Metric::Relmse => m.relmse,
            Metric::Mrse => m.mrse,
            Metric::Mse => m.mse,
            Metric::Rmse => m.rmse,
            Metric::Mae => m.mae,
            Metric::Mre => m.mre,
        }
    }
}

/// Options of `lancer img diff`.
#[derive(Args, Debug)]
pub struct DiffArgs {
    /// The image to judge.
    pub a: PathBuf,
    /// The reference (the denominators of the relative metrics are its values).
    pub b: PathBuf,
    /// Exit with status 1 when the metric chosen by --metric exceeds this value (or when a
    /// value is not finite in one image only).
    #[arg(long, value_name = "X")]
    pub threshold: Option<f64>,
    /// The metric --threshold compares.
    #[arg(long, value_enum, default_value = "relmse")]
    pub metric: Metric,
    /// Write the difference image |A − B| (per channel) here (.exr or .png).
    #[arg(short, long, value_name = "DIFF")]
    pub output: Option<PathBuf>,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Options of `lancer img convert`.
#[derive(Args, Debug)]
pub struct ConvertArgs {
    /// The image to read (.exr, .png, .jpg).
    pub input: PathBuf,
    /// The image to write (.exr or .png).
    pub output: PathBuf,
    /// Multiply the values by 2^STOPS (after crop and resize, before tone mapping).
    #[arg(
        long,
        value_name = "STOPS",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    pub exposure: f32,
    /// Tone mapping, last: none, aces (Narkowicz 2015) or reinhard (x / (1 + x)).
    #[arg(long, value_enum, default_value = "none")]
    pub tonemap: Tonemap,
    /// Keep the pixels [x0, x1) × [y0, y1) only (first).
    #[arg(long, value_name = "x0,x1,y0,y1", value_parser = parse_crop)]
    pub crop: Option<Crop>,
    /// Resample to WxH pixels with a box filter (area-weighted average), after the crop.
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    pub resize: Option<(u32, u32)>,
}

/// Options of `lancer img info`.
#[derive(Args, Debug)]
pub struct ImgInfoArgs {
    /// The image (.exr, .png, .jpg).
    pub image: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

fn parse_crop(s: &str) -> Result<Crop, String> {
    let n: Vec<u32> = s
        .split(',')
        .map(|v| v.trim().parse())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not x0,x1,y0,y1 (four pixel coordinates, 0 or more)"))?;
    match n[..] {
        [x0, x1, y0, y1] => Ok(Crop { x0, x1, y0, y1 }),
        _ => Err(format!("'{s}' is not x0,x1,y0,y1 (four pixel coordinates)")),
    }
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("'{s}' is not WxH (two positive whole numbers, e.g. 640x480)");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    // The limits of lancer's image reader: what it could not read back, it does not write.
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || w as u64 * h as u64 > MAX_TEXELS {
        return Err(format!(
            "'{s}': each side must be 1 to {MAX_SIDE}, and the image at most {MAX_TEXELS} pixels"
        ));
    }
    Ok((w, h))
}

/// An image as read: its linear pixels, and alpha when the file has one that is not 1 everywhere.
struct Loaded {
    picture: Picture,
    alpha: Option<Vec<f32>>,
}

/// Reads an image as lancer reads textures (PNG and JPEG decoded from sRGB); errors say
/// `cannot read FILE: why`.
fn read(path: &Path) -> Result<Loaded, CliError> {
    let decoded = read_image(path, Encoding::Srgb).map_err(|e| {
        let why = e
            .message
            .strip_prefix("cannot read: ")
            .unwrap_or(&e.message);
        CliError::input(format!("cannot read {}: {why}", path.display()))
    })?;
    let image = &decoded.rgb;
    Ok(Loaded {
        picture: Picture {
            width: image.width,
            height: image.height,
            pixels: image.texels.iter().map(|&t| Rgb::from(t)).collect(),
        },
        alpha: decoded.alpha.clone(),
    })
}

/// The linear pixels of the image at `path`, as [`read`] reads them.
pub(crate) fn read_picture(path: &Path) -> Result<Picture, CliError> {
    Ok(read(path)?.picture)
}

/// Refuses an output whose extension names no format lancer writes, before any work.
pub(crate) fn check_output_format(path: &Path) -> Result<(), CliError> {
    match ImageFormat::from_path(path) {
        Some(_) => Ok(()),
        None => Err(CliError::input(format!(
            "cannot write {}: unknown image format (use .png or .exr)",
            path.display()
        ))),
    }
}

/// Writes `picture` (atomically, as renders are written); errors say `cannot write FILE: why`.
pub(crate) fn write(path: &Path, picture: &Picture) -> Result<(), CliError> {
    write_image(path, picture.width, picture.height, &picture.pixels).map_err(|e| {
        let why = match e {
            ImageWriteError::UnknownFormat { .. } => {
                "unknown image format (use .png or .exr)".to_string()
            }
            ImageWriteError::Encode { message, .. } => format!("cannot encode: {message}"),
            ImageWriteError::Io { source, .. } => source.to_string(),
        };
        CliError::input(format!("cannot write {}: {why}", path.display()))
    })
}

/// Runs `lancer img …`.
pub fn run(cmd: ImgCommand) -> Result<(), CliError> {
    match cmd {
        ImgCommand::Diff(args) => diff(args),
        ImgCommand::Convert(args) => convert(args),
        ImgCommand::Info(args) => info(args),
        ImgCommand::Denoise(args) => denoise::denoise(args),
    }
}

/// A figure for text output: fixed notation for ordinary magnitudes, scientific otherwise.
fn num(v: f64) -> String {
    if v == 0.0 || (1e-4..1e6).contains(&v.abs()) {
        format!("{v:.6}")
    } else {
        format!("{v:.4e}")
    }
}

/// Three figures, `R x  G y  B z`.
fn rgb3(v: [f64; 3]) -> String {
    format!("R {}  G {}  B {}", num(v[0]), num(v[1]), num(v[2]))
}

fn diff(args: DiffArgs) -> Result<(), CliError> {
    if let Some(t) = args.threshold.filter(|t| t.is_nan() || *t < 0.0) {
        return Err(CliError::input(format!(
            "--threshold {t}: must be 0 or more"
        )));
    }
    if let Some(o) = &args.output {
        check_output_format(o)?;
    }
    let a = read(&args.a)?.picture;
    let b = read(&args.b)?.picture;
    if (a.width, a.height) != (b.width, b.height) {
        return Err(CliError::input(format!(
            "cannot compare {} ({}x{}) with {} ({}x{}): the sizes differ",
            args.a.display(),
            a.width,
            a.height,
            args.b.display(),
            b.width,
            b.height
        )));
    }
    let m = diff_metrics(&a.pixels, &b.pixels);
    let value = args.metric.of(&m);
    let name = args.metric.name();
    let failure = args.threshold.and_then(|t| {
        if m.nonfinite_mismatches > 0 {
            Some(format!(
                "{} samples are not finite in one image and differ in the other",
                m.nonfinite_mismatches
            ))
        } else if value.is_nan() || value > t {
            Some(format!("{name} {} exceeds --threshold {t}", num(value)))
        } else {
            None
        }
    });
    if args.json {
        let v = json!({
            "a": args.a.display().to_string(),
            "b": args.b.display().to_string(),
            "width": a.width,
            "height": a.height,
            "means_a": m.means_a,
            "means_b": m.means_b,
            "relmse": m.relmse,
            "mrse": m.mrse,
            "mse": m.mse,
            "rmse": m.rmse,
            "mae": m.mae,
            "mre": m.mre,
            "mre_channels": m.mre_channels,
            "samples_compared": m.compared,
            "samples_not_finite": m.skipped,
            "nonfinite_mismatches": m.nonfinite_mismatches,
            "metric": name,
            "threshold": args.threshold,
            "pass": args.threshold.map(|_| failure.is_none()),
        });
        println!("{v}");
    } else {
        println!("A  {}: means {}", args.a.display(), rgb3(m.means_a));
        println!("B  {}: means {}", args.b.display(), rgb3(m.means_b));
        println!("size      {}x{}", a.width, a.height);
        println!("relmse    {}   mean of (A-B)^2/(B^2+0.01)", num(m.relmse));
        println!(
            "mrse      {}   pbrt-v4's MRSE: mean of (A-B)^2/(B+0.01)^2",
            num(m.mrse)
        );
        println!("mse       {}", num(m.mse));
        println!("rmse      {}", num(m.rmse));
        println!("mae       {}", num(m.mae));
        println!(
            "mre       {}   |mean A - mean B| / mean B, largest of {}",
            num(m.mre),
            rgb3(m.mre_channels)
        );
        if m.skipped > 0 {
            println!(
                "not finite: {} samples left out of the metrics ({} differ between A and B)",
                m.skipped, m.nonfinite_mismatches
            );
        }
    }
    if let Some(o) = &args.output {
        let d = Picture {
            width: a.width,
            height: a.height,
            pixels: difference_image(&a.pixels, &b.pixels),
        };
        write(o, &d)?;
    }
    match failure {
        Some(why) => Err(CliError::runtime(format!(
            "{} differs from {}: {why}",
            args.a.display(),
            args.b.display()
        ))),
        None => Ok(()),
    }
}

fn convert(args: ConvertArgs) -> Result<(), CliError> {
    check_output_format(&args.output)?;
    if !args.exposure.is_finite() {
        return Err(CliError::input(format!(
            "--exposure {}: must be a finite number of stops",
            args.exposure
        )));
    }
    let mut p = read(&args.input)?.picture;
    if let Some(c) = args.crop {
        p = p
            .crop(c)
            .map_err(|e| CliError::input(format!("cannot crop {}: {e}", args.input.display())))?;
    }
    if let Some((w, h)) = args.resize {
        p = p.resize(w, h);
    }
    if args.exposure != 0.0 {
        p.expose(args.exposure);
    }
    if args.tonemap != Tonemap::None {
        p.tonemap(args.tonemap);
    }
    write(&args.output, &p)
}

fn stats_json(s: &ChannelStats) -> Value {
    json!({ "mean": s.mean, "min": s.min, "max": s.max, "nan": s.nan, "inf": s.inf })
}

fn info(args: ImgInfoArgs) -> Result<(), CliError> {
    let loaded = read(&args.image)?;
    let p = &loaded.picture;
    let mut names = vec!["R", "G", "B"];
    let mut stats = rgb_stats(&p.pixels).to_vec();
    if let Some(a) = &loaded.alpha {
        names.push("A");
        stats.push(metrics::channel_stats(a.iter().copied()));
    }
    let format = args
        .image
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_uppercase())
        .unwrap_or_default();
    let encoded = format != "EXR";
    if args.json {
        let channels: serde_json::Map<String, Value> = names
            .iter()
            .zip(&stats)
            .map(|(n, s)| (n.to_string(), stats_json(s)))
            .collect();
        let v = json!({
            "file": args.image.display().to_string(),
            "format": format,
            "width": p.width,
            "height": p.height,
            "channels": names,
            "srgb_decoded": encoded,
            "stats": channels,
        });
        println!("{v}");
        return Ok(());
    }
    println!(
        "{}: {}x{} pixels, {format}, channels {}{}",
        args.image.display(),
        p.width,
        p.height,
        names.join(", "),
        if encoded {
            " (colour decoded from sRGB to linear)"
        } else {
            " (linear)"
        }
    );
    println!(
        "{:<8}{:>14}{:>14}{:>14}{:>10}{:>10}",
        "channel", "mean", "min", "max", "NaN", "Inf"
    );
    for (n, s) in names.iter().zip(&stats) {
        println!(
            "{n:<8}{:>14}{:>14}{:>14}{:>10}{:>10}",
            num(s.mean),
            num(s.min),
            num(s.max),
            s.nan,
            s.inf
        );
    }
    Ok(())
}
