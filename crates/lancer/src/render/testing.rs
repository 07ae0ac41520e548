//! Test helpers of the film loops: a whole render of a scene description into a fresh film.

use super::{RenderJob, RenderSettings, RenderStats, render_units, work_units};
use crate::film::Film;
use crate::scene::Scene;
use crate::scene::desc::SceneDesc;

/// Renders `settings.bounds` of `desc` on `threads` threads, in tiles of `tile` pixels, into
/// a fresh film; asserts every unit is done.
pub(crate) fn render_on(
    desc: &SceneDesc,
    settings: &RenderSettings,
    threads: usize,
    tile: u32,
) -> (Film, RenderStats) {
    let scene = Scene::build(desc).unwrap();
    let mut film = Film::new(
        desc.film.xresolution,
        desc.film.yresolution,
        settings.bounds,
    );
    let units = work_units(&settings.bounds, tile, settings.samples.clone(), 4);
    let mut done = vec![false; units.len()];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let stats = pool.install(|| {
        render_units(RenderJob::new(
            &scene, settings, &mut film, &units, &mut done,
        ))
    });
    assert!(done.iter().all(|&d| d));
    (film, stats)
}
