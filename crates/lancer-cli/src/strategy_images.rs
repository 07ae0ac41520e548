//! bdpt's `visualizestrategies` and `visualizeweights` in `lancer render`: the render then
//! also fills one image per strategy ([`lancer::render::strategies`]), written beside the
//! output under pbrt-v4's names (`bdpt_d01_s02_t01.exr`, …) once the render is done.
//!
//! The strategy images live in memory only: a render that resumes a checkpoint, or renders
//! a part of a split render, has not seen all of its samples' strategies, and writes none
//! (with a warning); one that saves checkpoints as it goes and finishes in the same process
//! writes them.

use crate::cli_error::CliError;
use lancer::film::Film;
use lancer::image_io::write_image;
use lancer::integrator::Integrator;
use lancer::integrator::bdpt::BdptOptions;
use lancer::render::strategies::{ObservedBdpt, StrategyImages};
use lancer::render::{RenderJob, RenderSettings, RenderStats, render_units_with};
use std::path::Path;

/// The strategy images the render of `settings` fills, when its integrator asks for them and
/// this process renders every sample of the image: not for a part of a split render
/// (`is_part`) nor a resumed one (`resumed`), which warn instead.
pub fn start(settings: &RenderSettings, is_part: bool, resumed: bool) -> Option<StrategyImages> {
    let Integrator::Bdpt {
        max_depth,
        visualize_strategies,
        visualize_weights,
        ..
    } = settings.integrator
    else {
        return None;
    };
    if !(visualize_strategies || visualize_weights) {
        return None;
    }
    if is_part || resumed {
        eprintln!(
            "warning: the bdpt strategy images (visualizestrategies, visualizeweights) are \
             written only by a render of the whole image in one run, not by {}",
            if is_part {
                "a part of a split render"
            } else {
                "a resumed render"
            }
        );
        return None;
    }
    // Both set: the weighted images, as pbrt-v4 (its visualizeweights wins).
    Some(StrategyImages::new(
        max_depth,
        visualize_weights,
        settings.splat_bounds,
    ))
}

/// [`lancer::render::render_units`], with bdpt observed into `images` when given.
pub fn render_units(images: Option<&StrategyImages>, job: RenderJob<'_>) -> RenderStats {
    let settings = job.settings;
    match (images, settings.integrator) {
        (
            Some(images),
            Integrator::Bdpt {
                max_depth,
                regularize,
                ..
            },
        ) => {
            let observed = ObservedBdpt {
                options: BdptOptions {
                    max_depth,
                    regularize,
                },
                images,
                filter: &settings.filter,
            };
            render_units_with(job, &observed)
        }
        _ => render_units_with(job, &settings.integrator),
    }
}

/// Writes `images` (filled by the render of `film`, times the film's `scale`) beside
/// `output`, one EXR per strategy under pbrt-v4's name.
pub fn write(
    images: StrategyImages,
    film: &Film,
    scale: f32,
    output: &Path,
) -> Result<(), CliError> {
    let dir = output.parent().unwrap_or(Path::new(""));
    let b = film.bounds;
    for (strategy, pixels) in images.images(film, scale) {
        let path = dir.join(strategy.file_name());
        write_image(&path, b.width(), b.height(), &pixels)
            .map_err(|e| CliError::runtime(e.to_string()))?;
    }
    Ok(())
}
