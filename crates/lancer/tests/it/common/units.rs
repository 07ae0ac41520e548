//! Rendering a list of work units on a pool of a chosen size, for the tests that compare a
//! film across thread counts and splits of its work.

use lancer::Scene;
use lancer::film::Film;
use lancer::render::{
    RenderJob, RenderSettings, RenderStats, SampleIntegrator, WorkUnit, render_units_with,
};

/// Renders `units` into `film` with `integrator` on a rayon pool of `threads` threads, with
/// no progress hook and no stop; returns the render's totals.
pub fn render_units_on<I: SampleIntegrator + ?Sized>(
    threads: usize,
    scene: &Scene,
    settings: &RenderSettings,
    integrator: &I,
    film: &mut Film,
    units: &[WorkUnit],
) -> RenderStats {
    let mut done = vec![false; units.len()];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        render_units_with(
            RenderJob::new(scene, settings, film, units, &mut done),
            integrator,
        )
    })
}
