//! `lancer render --denoise [--denoise-inputs]`: the render's film also gathers the
//! denoiser's auxiliary images (albedo and shading normal of the first surface that is not
//! perfectly specular, with the film's pixel filter: [`GbufferConfig::denoiser`]); once the
//! render is done, Open Image Denoise's network ([`lancer_denoise`]) turns the noisy colour
//! into the image written. A part of a split render keeps the auxiliary sums instead, and
//! `lancer merge --denoise` denoises the merged image ([`denoise_film`]).

use crate::cli_error::CliError;
use crate::img::denoise::denoise_rgb;
use crate::progress::ProgressMode;
use crate::render_args::{RenderArgs, checkpoint_without_sums};
use lancer::SceneDesc;
use lancer::film::Film;
use lancer::gbuffer::{GbufferConfig, GbufferFilm};
use lancer::image_io::write_image;
use lancer::math::Rgb;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Refuses what `--denoise` cannot do, before the render starts, and gives the film its
/// auxiliary sums. `is_part`: the render is a part of a split one, whose file keeps the sums
/// for `lancer merge --denoise`. `checkpoint`: the film is the checkpoint's at that path,
/// continued by `--resume` or `--resume-if-exists`; a `--denoise` render's checkpoint keeps
/// the sums of its finished work (exactly: [`crate::checkpoint`]), which the render goes on
/// adding to, and one written without `--denoise` cannot be continued with it.
pub fn prepare(
    args: &RenderArgs,
    desc: &SceneDesc,
    film: &mut Film,
    is_part: bool,
    checkpoint: Option<&Path>,
) -> Result<(), CliError> {
    // The sums a checkpoint kept: the scene's configuration, for the work left.
    // Without --denoise (a requeued command line that dropped it), they are not needed: the
    // image is the noisy one.
    let kept = match checkpoint {
        Some(_) if film.gbuffer.as_ref().is_some_and(|g| g.config.for_denoiser) => {
            film.gbuffer.take()
        }
        _ => None,
    };
    if !args.denoise {
        return Ok(());
    }
    if is_part && args.denoise_inputs {
        return Err(CliError::input(
            "--denoise-inputs with a part of a split render (--split, --samples): a part keeps \
             the denoiser's sums and is not denoised; give --denoise --denoise-inputs to \
             lancer merge",
        ));
    }
    if let lancer::integrator::Integrator::Mlt(_) = desc.integrator {
        return Err(CliError::input(
            "--denoise gathers its albedo and normal images from camera samples, which \
             integrator \"mlt\" does not take (its Markov chains only splat): render it \
             without --denoise",
        ));
    }
    if desc.film.gbuffer.is_some() || desc.film.spectral.is_some() {
        return Err(CliError::input(
            "--denoise writes a denoised RGB image: use it with Film \"rgb\" (this scene's \
             film is a gbuffer or spectral film, whose extra channels it would drop)",
        ));
    }
    let config = GbufferConfig::denoiser(desc.camera.camera_from_world, desc.sampler.spp);
    let n = film.bounds.area() as usize;
    let g = match (checkpoint, kept) {
        (None, _) => GbufferFilm::new(config, n),
        (Some(_), Some(g)) if g.pixels.len() == n => GbufferFilm {
            config,
            pixels: g.pixels,
        },
        (Some(path), _) => return Err(checkpoint_without_sums(path)),
    };
    film.gbuffer = Some(Box::new(g));
    Ok(())
}

/// `OUT.KIND.exr` beside `OUT.ext`.
pub fn input_path(output: &Path, kind: &str) -> PathBuf {
    output.with_extension(format!("{kind}.exr"))
}

/// What [`run`] gives: the denoised image and the seconds the network took.
pub struct Denoised {
    /// The image to write instead of the film's.
    pub pixels: Vec<Rgb>,
    /// Seconds spent denoising (the network, its transfer and tiling).
    pub seconds: f64,
}

/// Denoises the finished film, its image scaled by `scale` (and writes its inputs beside
/// `output` with `--denoise-inputs`); `None` without `--denoise` or for a part (`is_part`),
/// which keeps the sums for `lancer merge --denoise`.
pub fn run(
    args: &RenderArgs,
    film: &Film,
    scale: f32,
    output: &Path,
    is_part: bool,
) -> Result<Option<Denoised>, CliError> {
    if !args.denoise || is_part {
        return Ok(None);
    }
    let json = args.progress == ProgressMode::Json;
    if !args.quiet && !json {
        let b = film.bounds;
        eprintln!(
            "denoising {}x{} (colour + albedo + normal)…",
            b.width(),
            b.height()
        );
    }
    let denoised = denoise_film(film, scale, output, args.denoise_inputs)?;
    if !args.quiet && json {
        eprintln!(
            "{}",
            serde_json::json!({ "denoise_s": (denoised.seconds * 1000.0).round() / 1000.0 })
        );
    }
    Ok(Some(denoised))
}

/// Denoises a film that gathered the denoiser's auxiliary sums (a `--denoise` render's, or
/// the merge of its parts), its image scaled by `scale`; with `write_inputs`, first writes
/// the denoiser's inputs beside `output` ([`input_path`]).
pub fn denoise_film(
    film: &Film,
    scale: f32,
    output: &Path,
    write_inputs: bool,
) -> Result<Denoised, CliError> {
    let b = film.bounds;
    let noisy = film.image(scale);
    let (albedo, normal) = film
        .gbuffer
        .as_ref()
        .filter(|g| g.config.for_denoiser)
        .ok_or_else(|| CliError::runtime("the film has no denoiser's auxiliary images"))?
        .denoiser_images();
    if write_inputs {
        for (kind, img) in [("noisy", &noisy), ("albedo", &albedo), ("normal", &normal)] {
            let path = input_path(output, kind);
            write_image(&path, b.width(), b.height(), img)
                .map_err(|e| CliError::runtime(format!("cannot write {}: {e}", path.display())))?;
        }
    }
    let start = Instant::now();
    let pixels = denoise_rgb(&noisy, Some(&albedo), Some(&normal), b.width(), b.height())?;
    Ok(Denoised {
        pixels,
        seconds: start.elapsed().as_secs_f64(),
    })
}
