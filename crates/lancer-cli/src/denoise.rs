//! `lancer render --denoise [--denoise-inputs]`: the render's film also gathers the
//! denoiser's auxiliary images (albedo and shading normal of the first surface that is not
//! perfectly specular, with the film's pixel filter: [`GbufferConfig::denoiser`]); once the
//! render is done, Open Image Denoise's network ([`lancer_denoise`]) turns the noisy colour
//! into the image written. A part of a split render keeps the auxiliary sums instead, and
//! `lancer merge --denoise` denoises the merged image ([`denoise_film`]).

use crate::cli_error::CliError;
use crate::img::denoise::denoise_rgb;
use crate::progress::ProgressMode;
use crate::render_args::RenderArgs;
use lancer::SceneDesc;
use lancer::film::Film;
use lancer::gbuffer::{GbufferConfig, GbufferFilm};
use lancer::image_io::write_image;
use lancer::math::Rgb;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Refuses what `--denoise` cannot do yet, before the render starts (`is_part`: the render
/// is a part of a split one, whose file keeps the auxiliary sums for `lancer merge
/// --denoise`; `from_checkpoint`: the film is a checkpoint's, continued by `--resume` or
/// `--resume-if-exists`, which has no auxiliary sums for its finished work), and gives the
/// film its auxiliary sums.
pub fn prepare(
    args: &RenderArgs,
    desc: &SceneDesc,
    film: &mut Film,
    is_part: bool,
    from_checkpoint: bool,
) -> Result<(), CliError> {
    if !args.denoise {
        return Ok(());
    }
    let refuse = |what: &str| {
        Err(CliError::input(format!(
            "--denoise cannot be used with {what} yet: the film's auxiliary images (albedo, \
             normal) are not kept in checkpoints; render in one go (or in parts, --split, \
             and denoise with lancer merge --denoise)"
        )))
    };
    if is_part && args.denoise_inputs {
        return Err(CliError::input(
            "--denoise-inputs with a part of a split render (--split, --samples): a part keeps \
             the denoiser's sums and is not denoised; give --denoise --denoise-inputs to \
             lancer merge",
        ));
    }
    if from_checkpoint {
        return refuse("a checkpoint (--resume, or --resume-if-exists finding one)");
    }
    if args.checkpoint_every.is_some() {
        return refuse("--checkpoint-every");
    }
    if desc.film.gbuffer.is_some() || desc.film.spectral.is_some() {
        return Err(CliError::input(
            "--denoise writes a denoised RGB image: use it with Film \"rgb\" (this scene's \
             film is a gbuffer or spectral film, whose extra channels it would drop)",
        ));
    }
    let config = GbufferConfig::denoiser(desc.camera.camera_from_world, desc.sampler.spp);
    film.gbuffer = Some(Box::new(GbufferFilm::new(
        config,
        film.bounds.area() as usize,
    )));
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
