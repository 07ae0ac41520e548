//! Bidirectional path tracing (pbrt-v4's `bdpt`): per camera sample, a camera subpath and a
//! light subpath, and every way of joining a prefix of one to a prefix of the other, each
//! weighted by multiple importance sampling against the others that make the same path.
//!
//! A path of depth d (d bounces, d + 2 vertices) is made by d + 2 strategies (s, t): s
//! vertices from the light subpath, t from the camera subpath, s + t = d + 2. The strategies
//! with t ≥ 2 give the radiance of the camera ray; those with t = 1 join a light subpath
//! vertex to a fresh point on the lens and land anywhere on the film, so they are splatted.
//!
//! Both subpaths go through participating media as pbrt-v4's do: distances by delta tracking
//! at one lane's coefficients (the hero), medium vertices that scatter by their phase
//! function, and every connection attenuated by the transmittance of its segment. Unlike
//! pbrt-v4 (which weights by the hero lane alone), a contribution is divided by the lanes'
//! average density ratio ([`vertex::Vertex::r`]), so chromatic media do not make fireflies
//! in the other lanes, and RGB mode can pick its hero per sample without bias. Without media
//! every ratio is 1 and nothing changes. (Emission from media is not gathered, as in pbrt-v4's
//! bdpt.)

mod connect;
mod trace;
mod vertex;
mod walk;

pub use trace::li as light_trace;

#[cfg(test)]
mod media_tests;
#[cfg(test)]
pub(crate) mod tests;
#[cfg(test)]
mod visualize_tests;

use super::Splat;
use crate::math::{SampledSpectrum, Vec2};
use crate::ray::Ray;
use crate::sampling::{SampleSource, Sampler};
use crate::scene::Scene;
use crate::spectrum::sampled::SampledWavelengths;
use connect::{Segment, connect};
use vertex::Vertex;
use vertex::lane_balance;
use walk::{PATHS, Walk};

/// What `visualizestrategies` and `visualizeweights` see of each strategy (pbrt-v4 writes
/// one image per (s, t)): called with s, t, where the strategy lands on the film (`None`:
/// the camera ray's own pixel), its contribution as it enters the image (MIS-weighted: what
/// [`li`] adds or splats, to the bit), and its MIS weight w > 0 (the unweighted contribution
/// is the first over the second). Only strategies that bring something are reported.
pub type StrategyObserver<'a> = &'a mut dyn FnMut(usize, usize, Option<Vec2>, SampledSpectrum, f32);

/// The bdpt settings of a render.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BdptOptions {
    /// Longest path, in bounces.
    pub max_depth: u32,
    /// Roughen near-specular lobes after a non-specular bounce.
    pub regularize: bool,
}

/// Radiance along the camera ray `ray` by every strategy with t ≥ 2; the t = 1 strategies'
/// contributions go to `splat`, and every strategy's to `observe` when given.
pub fn li(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    options: BdptOptions,
    splat: Splat<'_>,
    mut observe: Option<StrategyObserver<'_>>,
) -> SampledSpectrum {
    PATHS.with(|paths| {
        let (camera, light) = &mut *paths.borrow_mut();
        let max_depth = options.max_depth as usize;
        let mut walk = Walk::new(scene, ray, lambda, options.regularize);
        walk.camera_subpath(ray, sampler, max_depth + 2, camera);
        walk.light_subpath(sampler, max_depth + 1, light);
        let weight = walk.spectral_weight();
        let lambda = walk.lambda;
        let seg = Segment {
            scene,
            lambda: lambda.as_ref(),
            hero: walk.hero,
        };
        let mut l = SampledSpectrum::ZERO;
        for t in 1..=camera.len() {
            for s in 0..=light.len() {
                let depth = (s + t) as isize - 2;
                if (s == 1 && t == 1) || depth < 0 || depth > max_depth as isize {
                    continue;
                }
                let c = connect(seg, light, camera, s, t, sampler);
                if c.l == SampledSpectrum::ZERO {
                    continue;
                }
                let r = strategy_ratio(light, camera, s, t);
                let contribution = lane_balance(c.l, r) * weight;
                if let Some(observe) = observe.as_mut()
                    && c.weight > 0.0
                {
                    observe(s, t, c.p_raster, contribution, c.weight);
                }
                if t != 1 {
                    l += contribution;
                } else if let Some(p) = c.p_raster {
                    splat(p, contribution);
                }
            }
        }
        l
    })
}

/// What one strategy of a bidirectional path gives: its contribution, weighted by MIS against
/// the path's other strategies, and where a t = 1 strategy lands on the film (`None`: the
/// camera ray's own raster point).
#[derive(Clone, Copy, Debug)]
pub(crate) struct StrategySample {
    /// MIS-weighted contribution, in the lanes of the render (times the hero-only weight of a
    /// path a dispersive surface cut to its hero wavelength).
    pub l: SampledSpectrum,
    /// Raster point of a t = 1 strategy.
    pub p_raster: Option<Vec2>,
}

/// Strategy (s, t) alone over subpaths of exactly `s` light and `t` camera vertices (the
/// camera subpath leaving along `ray`), as bdpt computes it in [`li`] (pbrt-v4's MLT `L` once
/// it has chosen the strategy): the camera subpath draws from `sampler`, then
/// `next_stream(sampler)` is called, the light subpath draws, `next_stream` again, and the
/// connection draws. Zero when either subpath ends early.
#[allow(clippy::too_many_arguments)] // the strategy and what it is evaluated with
pub(crate) fn strategy<S: SampleSource + ?Sized>(
    scene: &Scene,
    ray: &Ray,
    lambda: Option<&SampledWavelengths>,
    regularize: bool,
    s: usize,
    t: usize,
    sampler: &mut S,
    next_stream: &mut dyn FnMut(&mut S),
) -> StrategySample {
    let none = StrategySample {
        l: SampledSpectrum::ZERO,
        p_raster: None,
    };
    if t == 0 || (s == 1 && t == 1) {
        return none;
    }
    PATHS.with(|paths| {
        let (camera, light) = &mut *paths.borrow_mut();
        let mut walk = Walk::new(scene, ray, lambda, regularize);
        walk.camera_subpath(ray, sampler, t, camera);
        if camera.len() != t {
            return none;
        }
        next_stream(sampler);
        walk.light_subpath(sampler, s, light);
        if light.len() != s {
            return none;
        }
        next_stream(sampler);
        let weight = walk.spectral_weight();
        let lambda = walk.lambda;
        let seg = Segment {
            scene,
            lambda: lambda.as_ref(),
            hero: walk.hero,
        };
        let c = connect(seg, light, camera, s, t, sampler);
        StrategySample {
            l: lane_balance(c.l, strategy_ratio(light, camera, s, t)) * weight,
            p_raster: c.p_raster,
        }
    })
}

/// The lanes' density ratio of strategy (s, t): r_light[s−1]·r_camera[t−1] (the vertices
/// sampled for s = 1 or t = 1 have none: 1).
fn strategy_ratio(light: &[Vertex], camera: &[Vertex], s: usize, t: usize) -> SampledSpectrum {
    let r = camera[t - 1].r;
    if s > 0 { r * light[s - 1].r } else { r }
}
