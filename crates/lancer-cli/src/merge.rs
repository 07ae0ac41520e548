//! `lancer merge PARTS... -o OUT [--denoise]`: adds up the parts of a split render and writes
//! the image, bit for bit the one a single process would have written (with `--denoise`, the
//! merged image denoised with the parts' auxiliary sums, as `render --denoise` does).

use crate::cli_error::CliError;
use crate::output::check_output;
use clap::Args;
use lancer::film::part::{PartError, PartMeta, read_part};
use lancer::film::{Film, PixelBounds};
use lancer::gbuffer::GbufferFilm;
use lancer::image_io::write_image;
use std::path::{Path, PathBuf};

/// Options of `lancer merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// Part files written by `lancer render --split i/N` (or `--samples a..b`).
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The image to write (.png or .exr).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Denoise the merged image (the parts must have been rendered with --denoise, which
    /// keeps the denoiser's albedo and normal sums in them).
    #[arg(long)]
    pub denoise: bool,
    /// With --denoise: also write the denoiser's inputs beside the output, as
    /// OUT.noisy.exr, OUT.albedo.exr and OUT.normal.exr.
    #[arg(long, requires = "denoise")]
    pub denoise_inputs: bool,
}

fn show(b: &PixelBounds) -> String {
    format!("pixels x {}..{}, y {}..{}", b.x0, b.x1, b.y0, b.y1)
}

/// Checks that `parts` make up exactly one render: the same scene, seed, samples per pixel,
/// resolution, crop and scale; each part inside the render; no two overlapping (as boxes of
/// pixels × sample indices); together covering every pixel with every sample (their volumes
/// add up to the render's, `Σ area·samples = area(render)·spp`, which with no overlap means no
/// hole). The message names the part at fault and what differs.
pub fn check_parts(parts: &[(PathBuf, Film, PartMeta)]) -> Result<(), String> {
    let (p0, f0, m0) = &parts[0];
    let p0 = p0.display();
    for (p, f, m) in &parts[1..] {
        let p = p.display();
        let differs =
            |what: &str, a: String, b: String| Err(format!("{p} has {what} {a} but {p0} has {b}"));
        if m.seed != m0.seed {
            return differs("seed", m.seed.to_string(), m0.seed.to_string());
        }
        if m.spp != m0.spp {
            return differs("spp", m.spp.to_string(), m0.spp.to_string());
        }
        if (f.full_width, f.full_height) != (f0.full_width, f0.full_height) {
            return differs(
                "resolution",
                format!("{}x{}", f.full_width, f.full_height),
                format!("{}x{}", f0.full_width, f0.full_height),
            );
        }
        if m.render_bounds != m0.render_bounds {
            return differs(
                "crop window",
                show(&m.render_bounds),
                show(&m0.render_bounds),
            );
        }
        if m.scale.to_bits() != m0.scale.to_bits() {
            return differs("film scale", m.scale.to_string(), m0.scale.to_string());
        }
        // Last: the specific differences above say more than a hash.
        if m.scene_hash != m0.scene_hash {
            return Err(format!(
                "{p} is a part of another scene (or of the same one with other options) than {p0}: \
                 scene hash {:016x} vs {:016x}",
                m.scene_hash, m0.scene_hash
            ));
        }
    }
    let rb = m0.render_bounds;
    for (p, f, m) in parts {
        if f.bounds.intersect(&rb) != f.bounds || m.samples.end > m.spp {
            return Err(format!(
                "{} holds {} samples {}..{}, outside the render's {} samples 0..{}",
                p.display(),
                show(&f.bounds),
                m.samples.start,
                m.samples.end,
                show(&rb),
                m.spp
            ));
        }
    }
    for (i, (pa, fa, ma)) in parts.iter().enumerate() {
        for (pb, fb, mb) in &parts[i + 1..] {
            let pixels = fa.bounds.intersect(&fb.bounds);
            let s0 = ma.samples.start.max(mb.samples.start);
            let s1 = ma.samples.end.min(mb.samples.end);
            if !pixels.is_empty() && s0 < s1 {
                return Err(format!(
                    "{} and {} overlap: both hold {} samples {s0}..{s1}",
                    pa.display(),
                    pb.display(),
                    show(&pixels)
                ));
            }
        }
    }
    let covered: u64 = parts
        .iter()
        .map(|(_, f, m)| f.bounds.area() * m.samples.len() as u64)
        .sum();
    let total = rb.area() * m0.spp as u64;
    if covered != total {
        return Err(format!(
            "the parts leave holes: they hold {covered} pixel samples of the render's {total} \
             ({} at {} spp); a part is missing",
            show(&rb),
            m0.spp
        ));
    }
    Ok(())
}

/// The message for a part that cannot be read: the file named, and the reason in words (not
/// the system's `os error N`).
fn part_error(path: &Path, e: PartError) -> String {
    match e {
        PartError::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => {
            format!("{}: no such part file", path.display())
        }
        PartError::Io { source, .. } => {
            format!(
                "{}: cannot read this part: {}",
                path.display(),
                source.kind()
            )
        }
        e @ PartError::Format { .. } => e.to_string(),
    }
}

/// Runs `lancer merge`: reads and checks every part before writing anything.
pub fn run(args: MergeArgs) -> Result<(), CliError> {
    check_output(&args.output)?;
    let mut parts = Vec::new();
    for p in &args.parts {
        let (film, meta) = read_part(p).map_err(|e| CliError::input(part_error(p, e)))?;
        parts.push((p.clone(), film, meta));
    }
    if args.denoise
        && let Some((p, _, _)) = parts.iter().find(|(_, f, _)| f.gbuffer.is_none())
    {
        return Err(CliError::input(format!(
            "cannot merge with --denoise: {} has no denoiser's albedo and normal sums (render \
             the parts with --denoise)",
            p.display()
        )));
    }
    let (film, scale) =
        merge_parts(&parts).map_err(|e| CliError::input(format!("cannot merge: {e}")))?;
    let image = if args.denoise {
        crate::denoise::denoise_film(&film, scale, &args.output, args.denoise_inputs)?.pixels
    } else {
        film.image(scale)
    };
    let b = film.bounds;
    write_image(&args.output, b.width(), b.height(), &image)
        .map_err(|e| CliError::runtime(e.to_string()))
}

/// Checks the parts ([`check_parts`]) and adds up their exact sums into the whole render's
/// film (and the denoiser's auxiliary sums, when every part has them); returns it with the
/// film scale its image is made with (`film.image(scale)`).
pub fn merge_parts(parts: &[(PathBuf, Film, PartMeta)]) -> Result<(Film, f32), String> {
    if parts.is_empty() {
        return Err("no part to merge".into());
    }
    check_parts(parts)?;
    let (_, f0, m0) = &parts[0];
    let mut film = Film::new(f0.full_width, f0.full_height, m0.render_bounds);
    // The denoiser's sums, when every part kept them.
    if let Some(g) = &f0.gbuffer
        && parts.iter().all(|(_, f, _)| f.gbuffer.is_some())
    {
        film.gbuffer = Some(Box::new(GbufferFilm::new(
            g.config,
            film.bounds.area() as usize,
        )));
    }
    for (_, f, _) in parts {
        film.merge_film(f);
    }
    Ok((film, m0.scale))
}
