//! How `mlt` renders a film ([`crate::integrator::mlt`]): the bootstrap, then the Markov
//! chains, whose splats are the whole image.
//!
//! Determinism: bootstrap vector k (k = i·(maxdepth + 1) + depth) draws from a generator
//! seeded by (seed, k), and chain i's own choices (its start, its acceptances) from one seeded
//! by (seed, i); the bootstrap weights are summed in their order, so b and every chain are
//! the same whatever the threads. A chain's mutations are its share of the render's, fixed by
//! i alone. The splats are fixed-point sums (order-free), so a render split into ranges of
//! chains (its "samples", [`crate::integrator::Integrator::sample_indices`]), or interrupted
//! and resumed between chains, adds up to the same bits.

use super::{RenderJob, RenderSettings, RenderStats, Splats, counts, scene_film_rgb};
use crate::film::splat::AtomicSplats;
use crate::integrator::mlt::sampler::PssSampler;
use crate::integrator::mlt::{MltFilm, MltOptions, PathSample, path_sample};
use crate::math::luminance;
use crate::sampling::{Pcg32, hash_u64};
use crate::scene::Scene;
use rayon::prelude::*;
use std::sync::Mutex;

/// Tag of the generators of bootstrap vectors (and of the chains' vectors, which start from
/// one of them).
const BOOTSTRAP_TAG: u64 = 0x6d6c_745f_626f_6f74;
/// Tag of a chain's own generator.
const CHAIN_TAG: u64 = 0x6d6c_745f_6368_6169;

/// What the chains share.
struct Chains<'a> {
    scene: &'a Scene,
    settings: &'a RenderSettings,
    options: &'a MltOptions,
    film: MltFilm,
}

impl Chains<'_> {
    /// The vector generator of bootstrap vector `k`.
    fn vector(&self, k: u64) -> PssSampler {
        let rng = Pcg32::new(hash_u64(&[self.settings.seed, BOOTSTRAP_TAG, k]), 0);
        PssSampler::new(rng, self.options.sigma, self.options.large_step_probability)
    }

    /// L(u) of the current state of `x` for a path of `depth` bounces.
    fn sample(&self, depth: u32, x: &mut PssSampler) -> PathSample {
        path_sample(self.scene, self.options, depth, x, &self.film)
    }

    /// c(L): the luminance of the film colour of `p` (0 for a negative or non-finite one).
    fn c(&self, p: &PathSample) -> f32 {
        let y = luminance(scene_film_rgb(self.scene, p.lambda.as_ref(), p.l));
        if y.is_finite() && y > 0.0 { y } else { 0.0 }
    }
}

/// The sample bounds of a film over `bounds` with `filter`: pbrt-v4's, the pixels grown by
/// the filter's radius less half a pixel, [x0 + ½ − r, x1 − ½ + r) × …
fn sample_bounds(settings: &RenderSettings) -> [f32; 4] {
    let b = settings.splat_bounds;
    let r = settings.filter.radius();
    [
        b.x0 as f32 + 0.5 - r.x,
        b.x1 as f32 - 0.5 + r.x,
        b.y0 as f32 + 0.5 - r.y,
        b.y1 as f32 - 0.5 + r.y,
    ]
}

/// Mutations of chain `i` of `chains`, out of `total`: ⌊(i + 1)·N/C⌋ − ⌊i·N/C⌋ (pbrt-v4's
/// share, the last chains taking the remainder).
pub(super) fn chain_mutations(i: u64, chains: u64, total: u64) -> u64 {
    let share = |i: u64| ((i as u128 * total as u128) / chains.max(1) as u128) as u64;
    share(i + 1).min(total) - share(i)
}

/// Renders the chains of the units of `units` not marked in `done` into `film`'s splat plane
/// (see the module's documentation). A unit's `samples` are a range of chains; units of the
/// same range (the tiles of one pass, as [`super::work_units`] makes them) are that range
/// once, all marked when it is done. `stop()` is asked before each range but the first
/// starts.
pub(super) fn render_chains(job: RenderJob<'_>, options: &MltOptions) -> RenderStats {
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
    let chains = Chains {
        scene,
        settings,
        options,
        film: MltFilm {
            wavelengths: settings.spectral.then_some(kind),
            sample_bounds: sample_bounds(settings),
            pixel_area: settings.splat_bounds.area() as f32,
        },
    };
    // The distinct chain ranges still to do, in order.
    let mut ranges: Vec<std::ops::Range<u32>> = Vec::new();
    for (u, d) in units.iter().zip(done.iter()) {
        if !*d && !ranges.contains(&u.samples) {
            ranges.push(u.samples.clone());
        }
    }
    let totals = RenderStats::default();
    if ranges.is_empty() {
        return totals;
    }
    let bootstrap = bootstrap(&chains);
    let plane = AtomicSplats::new(settings.splat_bounds, kind.splat_channels());
    let splats = Splats::new(scene, settings, Some(&plane), kind);
    let state = Mutex::new((&mut *film, &mut *done));
    let totals_m = Mutex::new(totals);
    ranges.par_iter().enumerate().for_each(|(r, range)| {
        // The first range runs whatever `stop()` says: each call then makes progress, even
        // when a checkpoint falls due during the bootstrap (which every call computes anew).
        if r > 0 && stop() {
            totals_m.lock().unwrap().cancelled = true;
            return;
        }
        let counts0 = counts();
        let mut stats = RenderStats::default();
        if let Some(b) = &bootstrap {
            for i in range.clone() {
                run_chain(&chains, b, i, &splats, &mut stats);
            }
        }
        stats.add_counts_since(counts0);
        let finished: Vec<(usize, Vec<crate::film::PixelSum>)> = {
            let mut st = state.lock().unwrap();
            let marked: Vec<usize> = (0..units.len())
                .filter(|&k| units[k].samples == *range && !st.1[k])
                .collect();
            marked
                .into_iter()
                .map(|k| {
                    st.1[k] = true;
                    (k, super::tile_sums(st.0, &units[k].tile))
                })
                .collect()
        };
        for (k, sums) in &finished {
            on_unit(&units[*k], sums);
        }
        totals_m.lock().unwrap().add(&stats);
    });
    film.merge_splats(&plane.into_plane());
    totals_m.into_inner().unwrap()
}

/// The bootstrap: c(L(u)) of every bootstrap vector, their cumulative sums (to choose a
/// chain's start in proportion to c) and the image's normalisation scale.
struct Bootstrap {
    /// Σ c over vectors 0 … k, in f64, summed in order.
    cdf: Vec<f64>,
    /// b / `mutationsperpixel`, b = (maxdepth + 1)·mean c = Σ c / `bootstrapsamples`.
    scale: f32,
    /// Mutations of the whole render: ⌊sample bounds' area⌋ × `mutationsperpixel`.
    total_mutations: u64,
}

/// Evaluates the bootstrap vectors (in parallel; each a pure function of (seed, k)). `None`
/// when no vector carries light (the image is black: nothing to splat).
fn bootstrap(chains: &Chains<'_>) -> Option<Bootstrap> {
    let o = chains.options;
    let depths = o.max_depth as u64 + 1;
    let n = o.bootstrap_samples as u64 * depths;
    let weights: Vec<f32> = (0..n)
        .into_par_iter()
        .map(|k| {
            let mut x = chains.vector(k);
            let p = chains.sample((k % depths) as u32, &mut x);
            chains.c(&p)
        })
        .collect();
    let mut sum = 0.0f64;
    let cdf: Vec<f64> = weights
        .iter()
        .map(|&w| {
            sum += w as f64;
            sum
        })
        .collect();
    if sum <= 0.0 {
        return None;
    }
    let b = sum / o.bootstrap_samples.max(1) as f64;
    let [x0, x1, y0, y1] = chains.film.sample_bounds;
    let area = ((x1 - x0) * (y1 - y0)).max(0.0) as u64;
    Some(Bootstrap {
        cdf,
        scale: (b / o.mutations_per_pixel.max(1) as f64) as f32,
        total_mutations: area * o.mutations_per_pixel as u64,
    })
}

/// The index of the first cumulative sum above `u`·total: vector k with probability c_k/Σc
/// (never one with c = 0).
fn pick(cdf: &[f64], u: f32) -> usize {
    let total = *cdf.last().unwrap_or(&0.0);
    let target = u as f64 * total;
    cdf.partition_point(|&c| c <= target).min(cdf.len() - 1)
}

/// Runs chain `i`: its start chosen among the bootstrap vectors, its mutations, a splat of
/// the current and of the proposed state at each (pbrt-v4's expected-value splats).
fn run_chain(
    chains: &Chains<'_>,
    b: &Bootstrap,
    i: u32,
    splats: &Splats<'_>,
    stats: &mut RenderStats,
) {
    let o = chains.options;
    let depths = o.max_depth as u64 + 1;
    let mut rng = Pcg32::new(hash_u64(&[chains.settings.seed, CHAIN_TAG, i as u64]), 0);
    let k = pick(&b.cdf, rng.uniform());
    let depth = (k as u64 % depths) as u32;
    let mut x = chains.vector(k as u64);
    let mut current = chains.sample(depth, &mut x);
    let mut c_current = chains.c(&current);
    let n = chain_mutations(i as u64, o.chains as u64, b.total_mutations);
    // Splats L·w/c, clamped, times b/mutationsperpixel.
    let splat = |p: &PathSample, w: f32, c: f32| {
        if w > 0.0 && c > 0.0 {
            let l = p.l * (w / c);
            let rgb = scene_film_rgb(chains.scene, p.lambda.as_ref(), l);
            splats.add_splat_scaled(p.p_film, l, rgb, p.lambda.as_ref(), b.scale);
        }
    };
    for _ in 0..n {
        x.start_iteration();
        let proposed = chains.sample(depth, &mut x);
        let c_proposed = chains.c(&proposed);
        if !proposed.l.is_finite() {
            stats.nonfinite += 1;
        }
        // a = min(1, c_proposed/c_current); a current state of c = 0 (a start that could not
        // be made again, which a pure L(u) excludes) moves to any proposal.
        let a = if c_current > 0.0 {
            (c_proposed / c_current).min(1.0)
        } else {
            1.0
        };
        splat(&proposed, a, c_proposed);
        splat(&current, 1.0 - a, c_current);
        if rng.uniform() < a {
            current = proposed;
            c_current = c_proposed;
            x.accept();
        } else {
            x.reject();
        }
    }
    stats.samples += n;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_share_the_mutations_exactly() {
        for (chains, total) in [(1000u64, 66049u64 * 64), (7, 10), (10, 3), (3, 0)] {
            let sum: u64 = (0..chains).map(|i| chain_mutations(i, chains, total)).sum();
            assert_eq!(sum, total);
            let max = (0..chains).map(|i| chain_mutations(i, chains, total)).max();
            assert!(max.unwrap() <= total.div_ceil(chains));
        }
    }

    #[test]
    fn picks_in_proportion_and_never_a_zero_weight() {
        let w = [0.0f64, 1.0, 0.0, 3.0, 0.0];
        let mut s = 0.0;
        let cdf: Vec<f64> = w
            .iter()
            .map(|v| {
                s += v;
                s
            })
            .collect();
        let mut counts = [0u32; 5];
        for j in 0..4000 {
            counts[pick(&cdf, (j as f32 + 0.5) / 4000.0)] += 1;
        }
        assert_eq!(counts, [0, 1000, 0, 3000, 0]);
        assert_eq!(pick(&cdf, 0.0), 1);
    }
}
