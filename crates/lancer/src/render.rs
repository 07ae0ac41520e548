//! Rendering: tiles of pixels, each pixel's samples taken in order, on all cores.

use crate::film::{Film, PixelBounds, PixelSum};
use crate::filter::Filter;
use crate::integrator::Integrator;
use crate::math::Vec2;
use crate::sampling::{Sampler, SamplerKind};
use crate::scene::Scene;
use rayon::prelude::*;
use std::cell::Cell;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

thread_local! {
    static RAYS: Cell<u64> = const { Cell::new(0) };
}

/// Counts one traced ray on this thread (for statistics).
#[inline]
pub fn count_ray() {
    RAYS.with(|r| r.set(r.get() + 1));
}

/// This thread's ray count so far.
pub fn rays_traced() -> u64 {
    RAYS.with(|r| r.get())
}

/// What to render.
#[derive(Clone, Debug)]
pub struct RenderSettings {
    /// Pixels to render (full-image coordinates).
    pub bounds: PixelBounds,
    /// Sample indices to take in each pixel: `[start, end)`.
    pub samples: std::ops::Range<u32>,
    /// Samples per pixel of the whole render (the sampler's point set depends on it).
    pub spp: u32,
    /// Seed.
    pub seed: u64,
    /// Point set.
    pub sampler: SamplerKind,
    /// Pixel filter.
    pub filter: Filter,
    /// Light transport.
    pub integrator: Integrator,
    /// Tile edge in pixels.
    pub tile_size: u32,
    /// Largest component a sample may have; brighter samples are scaled down to it, keeping
    /// their colour (pbrt's `maxcomponentvalue`; infinity keeps every sample as it is).
    pub max_component_value: f32,
}

/// Totals of a render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Camera samples taken.
    pub samples: u64,
    /// Rays traced (camera, bounce and shadow rays).
    pub rays: u64,
    /// True if the render stopped early because it was cancelled.
    pub cancelled: bool,
}

/// The tiles covering `bounds`, in scanline order.
pub fn tiles(bounds: &PixelBounds, size: u32) -> Vec<PixelBounds> {
    let s = size.max(1) as i32;
    let mut out = Vec::new();
    let mut y = bounds.y0;
    while y < bounds.y1 {
        let mut x = bounds.x0;
        while x < bounds.x1 {
            out.push(PixelBounds {
                x0: x,
                x1: (x + s).min(bounds.x1),
                y0: y,
                y1: (y + s).min(bounds.y1),
            });
            x += s;
        }
        y += s;
    }
    out
}

/// Renders one tile: every pixel's samples `settings.samples`, in order. Returns the tile's
/// sums and the number of rays traced.
pub fn render_tile(
    scene: &Scene,
    settings: &RenderSettings,
    tile: &PixelBounds,
) -> (Vec<PixelSum>, u64) {
    let rays0 = rays_traced();
    let mut sampler = Sampler::new(settings.sampler, settings.spp, settings.seed);
    let mut sums = vec![PixelSum::default(); tile.area() as usize];
    let w = tile.width() as usize;
    for y in tile.y0..tile.y1 {
        for x in tile.x0..tile.x1 {
            let sum = &mut sums[(y - tile.y0) as usize * w + (x - tile.x0) as usize];
            for s in settings.samples.clone() {
                sampler.start_pixel_sample(x, y, s as u64);
                let (offset, weight) = settings.filter.sample(sampler.get_pixel_2d());
                let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                let p_lens = sampler.get_2d();
                let ray = scene.camera.generate_ray(p_film, p_lens);
                let l = settings.integrator.li(scene, &ray, &mut sampler);
                // A non-finite sample is a bug upstream; it must not poison the pixel.
                let l = if l.is_finite() {
                    l
                } else {
                    crate::math::Rgb::ZERO
                };
                let m = l.max_element();
                let l = if m > settings.max_component_value {
                    l * (settings.max_component_value / m)
                } else {
                    l
                };
                sum.add(l, weight);
            }
        }
    }
    (sums, rays_traced() - rays0)
}

/// The film's sums over `tile` (a part of its bounds), row-major.
fn tile_sums(film: &Film, tile: &PixelBounds) -> Vec<PixelSum> {
    let fw = film.bounds.width() as usize;
    let mut out = Vec::with_capacity(tile.area() as usize);
    for y in tile.y0..tile.y1 {
        let row = (y - film.bounds.y0) as usize * fw;
        let a = row + (tile.x0 - film.bounds.x0) as usize;
        out.extend_from_slice(&film.pixels[a..a + tile.width() as usize]);
    }
    out
}

/// Renders `settings.bounds` into `film` on the current rayon pool. `progress(pixels)` is
/// called as tiles finish; `cancel` stops the render between tiles (the film then holds the
/// finished tiles only).
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut Film,
    progress: &(dyn Fn(u64) + Sync),
    cancel: &AtomicBool,
) -> RenderStats {
    render_observed(
        scene,
        settings,
        film,
        &|tile, _| progress(tile.area()),
        cancel,
    )
}

/// Called as each tile finishes, with the tile and the film's sums over it after the tile was
/// added (row-major over the tile), for live previews. Calls come from the worker threads.
pub type TileHook<'a> = &'a (dyn Fn(&PixelBounds, &[PixelSum]) + Sync);

/// [`render`], with `on_tile` called for every finished tile instead of a pixel count.
pub fn render_observed(
    scene: &Scene,
    settings: &RenderSettings,
    film: &mut Film,
    on_tile: TileHook<'_>,
    cancel: &AtomicBool,
) -> RenderStats {
    let tiles = tiles(&settings.bounds.intersect(&film.bounds), settings.tile_size);
    let film = Mutex::new(film);
    let totals = Mutex::new(RenderStats::default());
    tiles.par_iter().for_each(|tile| {
        if cancel.load(Ordering::Relaxed) {
            totals.lock().unwrap().cancelled = true;
            return;
        }
        let (sums, rays) = render_tile(scene, settings, tile);
        let merged = {
            let mut f = film.lock().unwrap();
            f.merge_tile(tile, &sums);
            tile_sums(&f, tile)
        };
        let mut t = totals.lock().unwrap();
        t.rays += rays;
        t.samples += tile.area() * settings.samples.len() as u64;
        drop(t);
        on_tile(tile, &merged);
    });
    totals.into_inner().unwrap()
}
