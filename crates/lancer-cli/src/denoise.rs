//! `lancer render --denoise [--denoise-inputs]`: the render's film also gathers the
//! denoiser's auxiliary images (albedo and shading normal of the first surface that is not
//! perfectly specular, with the film's pixel filter: [`GbufferConfig::denoiser`]); once the
//! render is done, Open Image Denoise's network ([`lancer_denoise`]) turns the noisy colour
//! into the image written.

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
/// is a part of a split one), and gives the film its auxiliary sums.
pub fn prepare(
    args: &RenderArgs,
    desc: &SceneDesc,
    film: &mut Film,
    is_part: bool,
) -> Result<(), CliError> {
    if !args.denoise {
        return Ok(());
    }
    let refuse = |what: &str| {
        Err(CliError::input(format!(
            "--denoise cannot be used with {what} yet: the film's auxiliary images (albedo, \
             normal) are not kept in parts or checkpoints; render in one go"
        )))
    };
    if is_part {
        return refuse("a part of a split render (--split, --samples)");
    }
    if args.resume.is_some() {
        return refuse("--resume");
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
/// `output` with `--denoise-inputs`); `None` without `--denoise`.
pub fn run(
    args: &RenderArgs,
    film: &Film,
    scale: f32,
    output: &Path,
) -> Result<Option<Denoised>, CliError> {
    if !args.denoise {
        return Ok(None);
    }
    let b = film.bounds;
    let noisy = film.image(scale);
    let (albedo, normal) = film
        .gbuffer
        .as_ref()
        .expect("prepare gave the film its auxiliary sums")
        .denoiser_images();
    if args.denoise_inputs {
        for (kind, img) in [("noisy", &noisy), ("albedo", &albedo), ("normal", &normal)] {
            let path = input_path(output, kind);
            write_image(&path, b.width(), b.height(), img)
                .map_err(|e| CliError::runtime(format!("cannot write {}: {e}", path.display())))?;
        }
    }
    let json = args.progress == ProgressMode::Json;
    if !args.quiet && !json {
        eprintln!(
            "denoising {}x{} (colour + albedo + normal)…",
            b.width(),
            b.height()
        );
    }
    let start = Instant::now();
    let flat = |v: &[Rgb]| v.iter().flat_map(|c| [c.x, c.y, c.z]).collect::<Vec<f32>>();
    let out = denoise_rgb(
        &flat(&noisy),
        Some(&flat(&albedo)),
        Some(&flat(&normal)),
        b.width(),
        b.height(),
    )?;
    let seconds = start.elapsed().as_secs_f64();
    if !args.quiet && json {
        eprintln!(
            "{}",
            serde_json::json!({ "denoise_s": (seconds * 1000.0).round() / 1000.0 })
        );
    }
    Ok(Some(Denoised {
        pixels: out
            .chunks_exact(3)
            .map(|c| Rgb::new(c[0], c[1], c[2]))
            .collect(),
        seconds,
    }))
}
