//! The film loop of `vcm` ([`crate::integrator::vcm`]): iterations, one per sample index,
//! each a pass over the whole film: one light subpath per pixel of the whole render
//! (`settings.splat_bounds`), their vertices hashed into a grid of the iteration's radius,
//! then one camera sample per rendered pixel.
//!
//! Unlike sppm's, vcm's iterations are independent samples: iteration k's radius depends on
//! k alone, its wavelengths on (seed, k), its light subpath j on (seed, k, j) (its first
//! dimensions a scrambled Halton point, as sppm's photons), its camera sample of a pixel on (seed, pixel, k) (the
//! sampler's sample k). A pixel's image is the filter-weighted average of its iterations'
//! camera samples plus the splats of the t = 1 connections over the iterations, both
//! fixed-point sums: any thread count, any range of sample indices (`--samples`, a split by
//! samples), and an interruption resumed between ranges add up to the same bits.
//!
//! A part of the image (a split by tiles) traces every light subpath of the iteration (its
//! pixels merge with all of them, and connect to those of their own pixels), but splats only
//! the light subpaths of its own pixels: the parts' splats add up to the whole render's.

use super::{
    RenderJob, RenderSettings, RenderStats, SampleId, Splats, camera_ray_at, counts,
    sppm::wavelength_sample,
};
use crate::film::splat::AtomicSplats;
use crate::film::tile::{FilmKind, FilmTile, GbufferTile, RgbTile, SpectralTile};
use crate::film::{Film, PixelBounds};
use crate::integrator::sppm::PhotonSampler;
use crate::integrator::vcm::camera::{Merging, camera_path};
use crate::integrator::vcm::grid::MergeGrid;
use crate::integrator::vcm::{
    Iteration, LightVertex, VcmOptions, initial_radius, light_path, radius_at,
};
use crate::math::Vec3;
use crate::sampling::halton::DigitPermutations;
use crate::sampling::{Pcg32, SampleSource, Sampler, hash_u64};
use crate::scene::Scene;
use rayon::prelude::*;

/// Light subpaths per block: the light pass's unit of parallel work; blocks' vertices are
/// concatenated in block order.
const LIGHT_BLOCK: u64 = 1024;

/// Dimensions of a light subpath drawn from the scrambled Halton sequence over the render's
/// light subpaths (the light, the point on it, the direction: stratified over the paths);
/// the others from a PCG stream of the path's own, far cheaper than a radical inverse.
const HALTON_DIMS: u32 = 5;

/// The random numbers of light subpath j of iteration k: the first [`HALTON_DIMS`] from
/// sppm's photon sampler at index k·N + j (N subpaths per iteration), the rest from a
/// generator seeded by (seed, k·N + j): a pure function of (seed, iteration, index).
struct LightPathSampler {
    halton: PhotonSampler,
    rng: Pcg32,
    dim: u32,
    seed: u64,
}

impl LightPathSampler {
    /// Moves to light subpath `index` (k·N + j), dimension 0.
    fn start(&mut self, index: u64) {
        self.halton.start(index);
        self.rng = Pcg32::new(hash_u64(&[self.seed, 0x7663_6d6c, index]), 0);
        self.dim = 0;
    }
}

impl SampleSource for LightPathSampler {
    #[inline]
    fn get_1d(&mut self) -> f32 {
        self.dim += 1;
        if self.dim <= HALTON_DIMS {
            self.halton.get_1d()
        } else {
            self.rng.uniform()
        }
    }

    #[inline]
    fn get_2d(&mut self) -> crate::math::Vec2 {
        let x = self.get_1d();
        crate::math::Vec2::new(x, self.get_1d())
    }
}

/// Light subpaths of an iteration: their stored vertices, path after path, and where each
/// path's run starts (one more entry than there are paths).
#[derive(Default)]
struct LightPaths {
    /// Each block's vertices and its paths' vertex counts, as traced.
    blocks: Vec<(Vec<LightVertex>, Vec<u32>)>,
    vertices: Vec<LightVertex>,
    starts: Vec<u32>,
    /// What the light pass counted (rays, light paths, connections to the lens).
    counted: RenderStats,
}

/// One iteration as its camera pass reads it: its index, its shared state, its light
/// subpaths and their grid.
struct Current<'a> {
    k: u32,
    it: Iteration<'a>,
    paths: &'a LightPaths,
    grid: Option<MergeGrid>,
}

/// What the passes of a render share.
struct Pass<'a> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    options: VcmOptions,
    perms: std::sync::Arc<DigitPermutations>,
    kind: FilmKind,
    splats: &'a Splats<'a>,
}

impl Pass<'_> {
    /// Iteration `k`'s shared state.
    fn iteration(&self, k: u32) -> Iteration<'_> {
        let s = self.settings;
        let lambda = (s.spectral && s.integrator.computes_radiance())
            .then(|| self.kind.sample_wavelengths(wavelength_sample(s.seed, k)));
        let r = radius_at(
            initial_radius(self.scene, &self.options),
            self.options.alpha,
            k,
        );
        Iteration::new(
            self.scene,
            lambda,
            self.options.max_depth,
            r,
            s.splat_bounds.area(),
        )
    }

    /// Traces iteration `it`'s (index `k`) light subpaths into `paths` (whose buffers are
    /// reused from one iteration to the next), splatting those of the pixels in
    /// `splat_tiles`.
    fn light_pass(
        &self,
        it: &Iteration<'_>,
        k: u32,
        splat_tiles: &[PixelBounds],
        paths: &mut LightPaths,
    ) {
        let sb = self.settings.splat_bounds;
        let n = sb.area();
        let w = sb.width().max(1) as u64;
        let lambda = it.lambda;
        paths
            .blocks
            .resize_with(n.div_ceil(LIGHT_BLOCK) as usize, Default::default);
        let counted: Vec<RenderStats> = paths
            .blocks
            .par_iter_mut()
            .enumerate()
            .map(|(b, (vertices, lens))| {
                let b = b as u64;
                let c0 = counts();
                let seed = self.settings.seed;
                let mut u = LightPathSampler {
                    halton: PhotonSampler::new(self.perms.clone(), seed, 0),
                    rng: Pcg32::new(0, 0),
                    dim: 0,
                    seed,
                };
                vertices.clear();
                lens.clear();
                for j in b * LIGHT_BLOCK..((b + 1) * LIGHT_BLOCK).min(n) {
                    u.start(k as u64 * n + j);
                    let (x, y) = (sb.x0 + (j % w) as i32, sb.y0 + (j / w) as i32);
                    let mine = splat_tiles.iter().any(|t| t.index(x, y).is_some());
                    let before = vertices.len();
                    let mut splat = |(p, l)| self.splats.add_splat(p, l, lambda.as_ref());
                    let splat: Option<&mut dyn FnMut(_)> =
                        if mine { Some(&mut splat) } else { None };
                    light_path(it, &mut u, vertices, splat);
                    lens.push((vertices.len() - before) as u32);
                }
                let mut st = RenderStats::default();
                st.add_counts_since(c0);
                st
            })
            .collect();
        paths.vertices.clear();
        paths.starts.clear();
        paths.starts.push(0u32);
        for (v, lens) in &paths.blocks {
            paths.vertices.extend_from_slice(v);
            for l in lens {
                let s = paths.starts.last().unwrap() + l;
                paths.starts.push(s);
            }
        }
        paths.counted = RenderStats::default();
        for c in &counted {
            paths.counted.add(c);
        }
    }

    /// Iteration `c`'s camera samples of the pixels of `tile`, added to `sums`, counted (and
    /// their merges) into `stats`.
    fn camera_pass<T: FilmTile>(
        &self,
        c: &Current<'_>,
        tile: &PixelBounds,
        sums: &mut T,
        stats: &mut RenderStats,
    ) {
        let (it, k, paths) = (&c.it, c.k, c.paths);
        let grid = c.grid.as_ref();
        let (scene, settings) = (self.scene, self.settings);
        let sb = settings.splat_bounds;
        let mut sampler = Sampler::new(settings.sampler, settings.spp, settings.seed);
        let merging = Merging {
            vertices: &paths.vertices,
            grid,
        };
        let w = tile.width() as usize;
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let i = (y - tile.y0) as usize * w + (x - tile.x0) as usize;
                let (ray, weight, p_film, p_lens) =
                    camera_ray_at(scene, settings, &mut sampler, x, y, k);
                let own = match sb.index(x, y) {
                    Some(j) => {
                        &paths.vertices[paths.starts[j] as usize..paths.starts[j + 1] as usize]
                    }
                    None => &[],
                };
                let l = match &ray {
                    Some(r) => {
                        camera_path(it, &r.ray, &mut sampler, own, merging, &mut stats.merges)
                            * r.weight
                    }
                    None => crate::math::SampledSpectrum::ZERO,
                };
                let sample = super::camera_sample::CameraSample {
                    id: SampleId { y, x, sample: k },
                    ray: ray.as_ref(),
                    p_film,
                    p_lens,
                    l,
                    lambda: it.lambda.as_ref(),
                    weight,
                };
                super::camera_sample::add(scene, settings, sums, stats, i, &sample);
            }
        }
    }

    /// Iterations `range` over `tiles`, into fresh tile sums made by `new_tile`.
    fn run<T: FilmTile + Send>(
        &self,
        range: std::ops::Range<u32>,
        tiles: &[PixelBounds],
        new_tile: impl Fn(&PixelBounds) -> T,
        stats: &mut RenderStats,
    ) -> Vec<T> {
        let mut sums: Vec<T> = tiles.iter().map(new_tile).collect();
        let mut paths = LightPaths::default();
        for k in range {
            let it = self.iteration(k);
            self.light_pass(&it, k, tiles, &mut paths);
            let points: Vec<Vec3> = paths.vertices.par_iter().map(|v| v.p).collect();
            let grid = MergeGrid::build(&points, it.radius);
            let c = Current {
                k,
                it,
                paths: &paths,
                grid,
            };
            let parts: Vec<RenderStats> = sums
                .par_iter_mut()
                .zip(tiles)
                .map(|(s, t)| {
                    let c0 = counts();
                    let mut st = RenderStats::default();
                    self.camera_pass(&c, t, s, &mut st);
                    st.add_counts_since(c0);
                    st.samples = t.area();
                    st
                })
                .collect();
            for p in &parts {
                stats.add(p);
            }
            stats.add(&c.paths.counted);
            stats.photons += c.paths.vertices.len() as u64;
        }
        sums
    }
}

/// Renders the units of `units` not marked in `done` into `film` by vcm with `options` (see
/// the module's documentation). Units of the same sample range (the tiles of one pass, as
/// [`super::work_units`] makes them) run together: the iterations of the range, each over
/// all their tiles; they are marked done (and `on_unit` called) when the range is finished.
/// `stop()` is asked before each range.
pub(super) fn render(job: RenderJob<'_>, options: VcmOptions) -> RenderStats {
    let RenderJob {
        scene,
        settings,
        film,
        units,
        done,
        on_unit,
        stop,
    } = job;
    let kind = film.kind();
    let mut ranges: Vec<std::ops::Range<u32>> = Vec::new();
    for (u, d) in units.iter().zip(done.iter()) {
        if !*d && !ranges.contains(&u.samples) {
            ranges.push(u.samples.clone());
        }
    }
    let mut stats = RenderStats::default();
    let plane = AtomicSplats::new(settings.splat_bounds, kind.splat_channels());
    let splats = Splats::new(scene, settings, Some(&plane), kind);
    let pass = Pass {
        scene,
        settings,
        options,
        perms: DigitPermutations::for_seed(settings.seed),
        kind,
        splats: &splats,
    };
    for range in ranges {
        if stop() {
            stats.cancelled = true;
            break;
        }
        let todo: Vec<usize> = (0..units.len())
            .filter(|&i| !done[i] && units[i].samples == range)
            .collect();
        let tiles: Vec<PixelBounds> = todo.iter().map(|&i| units[i].tile).collect();
        let mut add = |merge: &mut dyn FnMut(usize, &mut Film)| {
            for (n, &i) in todo.iter().enumerate() {
                merge(n, film);
                done[i] = true;
                on_unit(&units[i], &super::tile_sums(film, &units[i].tile));
            }
        };
        match kind {
            FilmKind::Rgb => {
                let sums = pass.run(range, &tiles, RgbTile::new, &mut stats);
                add(&mut |n, f| sums[n].merge_into(f, &tiles[n]));
            }
            FilmKind::Gbuffer(c) => {
                let sums = pass.run(range, &tiles, |t| GbufferTile::new(c, t), &mut stats);
                add(&mut |n, f| sums[n].merge_into(f, &tiles[n]));
            }
            FilmKind::Spectral(d) => {
                let max = settings.max_component_value;
                let sums = pass.run(range, &tiles, |t| SpectralTile::new(d, t, max), &mut stats);
                add(&mut |n, f| sums[n].merge_into(f, &tiles[n]));
            }
        }
    }
    film.merge_splats(&plane.into_plane());
    stats
}
