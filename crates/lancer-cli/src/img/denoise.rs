//! `lancer img denoise COLOR [--albedo A [--normal N]] -o OUT`: Open Image Denoise's network
//! (lancer's own inference, [`lancer_denoise`]) on an HDR image and its auxiliary images.

use super::ops::Picture;
use super::{check_output_format, read_picture, write};
use crate::cli_error::CliError;
use clap::Args;
use lancer::math::Rgb;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Options of `lancer img denoise`.
#[derive(Args, Debug)]
pub struct DenoiseArgs {
    /// The noisy HDR colour image (.exr; .png/.jpg are decoded from sRGB to linear).
    pub color: PathBuf,
    /// The albedo image of the same render (first non-specular surface's reflectance).
    #[arg(long, value_name = "A")]
    pub albedo: Option<PathBuf>,
    /// The shading normal image (components in [-1, 1]); needs --albedo.
    #[arg(long, value_name = "N", requires = "albedo")]
    pub normal: Option<PathBuf>,
    /// The denoised image to write (.exr or .png).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,
    /// Print nothing.
    #[arg(short, long)]
    pub quiet: bool,
}

/// Reads an auxiliary image and checks that its size is the colour's.
fn read_aux(path: &Path, color: &Picture, color_path: &Path) -> Result<Vec<Rgb>, CliError> {
    let p = read_picture(path)?;
    if (p.width, p.height) != (color.width, color.height) {
        return Err(CliError::input(format!(
            "{} is {}x{} but {} is {}x{}: the denoiser's images must have one size",
            path.display(),
            p.width,
            p.height,
            color_path.display(),
            color.width,
            color.height
        )));
    }
    Ok(p.pixels)
}

/// Denoises row-major images (the denoiser takes and gives interleaved RGB floats); a
/// failure (which only corrupted built-in weights could cause once the sizes are checked) is
/// a runtime error.
pub fn denoise_rgb(
    color: &[Rgb],
    albedo: Option<&[Rgb]>,
    normal: Option<&[Rgb]>,
    width: u32,
    height: u32,
) -> Result<Vec<Rgb>, CliError> {
    let flat = |v: &[Rgb]| v.iter().flat_map(|c| [c.x, c.y, c.z]).collect::<Vec<f32>>();
    let (a, n) = (albedo.map(flat), normal.map(flat));
    let out = lancer_denoise::denoise(
        &flat(color),
        a.as_deref(),
        n.as_deref(),
        width as usize,
        height as usize,
    )
    .map_err(|e| CliError::runtime(format!("denoiser: {e}")))?;
    Ok(out
        .chunks_exact(3)
        .map(|c| Rgb::new(c[0], c[1], c[2]))
        .collect())
}

/// Runs `lancer img denoise`.
pub fn denoise(args: DenoiseArgs) -> Result<(), CliError> {
    check_output_format(&args.output)?;
    let color = read_picture(&args.color)?;
    let albedo = args
        .albedo
        .as_deref()
        .map(|a| read_aux(a, &color, &args.color))
        .transpose()?;
    let normal = args
        .normal
        .as_deref()
        .map(|n| read_aux(n, &color, &args.color))
        .transpose()?;
    let start = Instant::now();
    let pixels = denoise_rgb(
        &color.pixels,
        albedo.as_deref(),
        normal.as_deref(),
        color.width,
        color.height,
    )?;
    let secs = start.elapsed().as_secs_f64();
    let out = Picture {
        width: color.width,
        height: color.height,
        pixels,
    };
    write(&args.output, &out)?;
    if !args.quiet {
        let with = match (&albedo, &normal) {
            (None, _) => "colour only",
            (Some(_), None) => "colour + albedo",
            (Some(_), Some(_)) => "colour + albedo + normal",
        };
        println!(
            "denoised {}x{} ({with}) in {secs:.2} s: {}",
            color.width,
            color.height,
            args.output.display()
        );
    }
    Ok(())
}
