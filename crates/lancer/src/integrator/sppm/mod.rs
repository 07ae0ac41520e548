//! Stochastic progressive photon mapping (pbrt-v4's `sppm`; Hachisuka and Jensen 2009): the
//! light that reaches diffuse surfaces only through specular ones (caustics, a pool floor seen
//! through water) is gathered from photons traced from the lights.
//!
//! Each iteration has two passes over the same wavelengths (pbrt-v4 draws one set per
//! iteration for every pixel and every photon, so that a photon's flux and a visible point's
//! BSDF are values at the same wavelengths):
//!
//! - the camera pass ([`camera_path`]): a path from each pixel through specular surfaces to its
//!   first diffuse (or, at the last bounce, glossy) surface, its *visible point*; on the way the
//!   pixel gathers emitted light and direct light by light sampling (`Ld`), weighted by MIS as a
//!   path tracer does;
//! - the photon pass ([`trace_photon`]): photons leave lights chosen in proportion to their
//!   power, and every surface a photon reaches after its first bounce (the first is direct
//!   light, which `Ld` has) adds its flux to the visible points within their pixel's radius,
//!   through the visible point's BSDF: Φ += β_vp · β_photon · f(wo_vp, wi).
//!
//! Then each pixel's estimate progresses ([`PixelState::update`]), and the image is
//! L = Ld/iterations + τ/(N_p·π·R²) ([`PixelState::estimate`]). The driver that runs the
//! passes over a film is `crate::render::sppm`; [`grid`] finds the visible points near a
//! photon.
//!
//! Surfaces only, as pbrt-v4's: participating media and subsurface scattering are not
//! sampled.

pub mod grid;

pub use super::desc::SppmOptions;

#[cfg(test)]
mod tests;

use super::{bsdf_at, direct_light, emitted, keep_hero_only};
use crate::light::LightSampleContext;
use crate::material::{Bsdf, BxdfFlags, TransportMode};
use crate::math::{Rgb, SampledSpectrum, Vec2, Vec3, normalize};
use crate::ray::Ray;
use crate::sampling::halton::{DigitPermutations, PRIME_TABLE_SIZE, scrambled_radical_inverse};
use crate::sampling::{Sampler, power_heuristic};
use crate::sampling::{hash_u64, u32_to_unit_f32};
use crate::scene::Scene;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;
use std::sync::Arc;

/// How fast the radius shrinks: the fraction γ of each iteration's photons a pixel keeps
/// (pbrt-v4's 2/3).
pub const GAMMA: f64 = 2.0 / 3.0;

/// One pixel's progressive estimate: its radius R, photon count N, the flux τ gathered within
/// R (film RGB), and the sum of its direct light Ld over the iterations so far.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelState {
    /// Search radius R.
    pub radius: f64,
    /// Photon count N (fractional: γ of each iteration's photons).
    pub n: f64,
    /// Flux τ, film RGB.
    pub tau: [f64; 3],
    /// Σ Ld over the iterations, film RGB.
    pub ld: [f64; 3],
}

impl PixelState {
    /// A pixel before its first iteration: radius `radius`, nothing gathered.
    pub fn new(radius: f64) -> PixelState {
        PixelState {
            radius,
            n: 0.0,
            tau: [0.0; 3],
            ld: [0.0; 3],
        }
    }

    /// Adds an iteration's `m` photons of total flux `phi` (film RGB) found within the radius:
    /// N' = N + γM, R' = R·√(N'/(N + M)), τ' = (τ + Φ)·R'²/R². Nothing changes when M = 0.
    pub fn update(&mut self, m: u64, phi: [f64; 3]) {
        if m == 0 {
            return;
        }
        let m = m as f64;
        let n_new = self.n + GAMMA * m;
        let r_new = self.radius * (n_new / (self.n + m)).sqrt();
        let shrink = (r_new * r_new) / (self.radius * self.radius);
        for (t, p) in self.tau.iter_mut().zip(phi) {
            *t = (*t + p) * shrink;
        }
        self.n = n_new;
        self.radius = r_new;
    }

    /// The pixel's radiance after `iterations` iterations of `photons_per_iteration` photons:
    /// L = Ld/iterations + τ/(N_p·π·R²), N_p = iterations · photons_per_iteration.
    pub fn estimate(&self, iterations: u32, photons_per_iteration: u64) -> Rgb {
        if iterations == 0 {
            return Rgb::ZERO;
        }
        let np = iterations as f64 * photons_per_iteration as f64;
        let area = np * std::f64::consts::PI * self.radius * self.radius;
        let c = |i: usize| {
            let t = if area > 0.0 { self.tau[i] / area } else { 0.0 };
            (self.ld[i] / iterations as f64 + t) as f32
        };
        Rgb::new(c(0), c(1), c(2))
    }
}

/// Where a camera path stopped to gather photons: the first diffuse surface (or glossy at the
/// last bounce), seen from `wo`, with the path's throughput to it.
#[derive(Clone, Copy, Debug)]
pub struct VisiblePoint {
    /// The surface point.
    pub p: Vec3,
    /// Direction back along the camera path.
    pub wo: Vec3,
    /// The surface's BSDF.
    pub bsdf: Bsdf,
    /// The camera path's throughput β to the point (the camera's weight included).
    pub beta: SampledSpectrum,
    /// The camera path kept only its hero wavelength (a dispersive surface on the way).
    pub hero_only: bool,
}

/// What a camera path of one iteration gives its pixel.
#[derive(Clone, Copy, Debug)]
pub struct CameraPath {
    /// Emitted and directly sampled light along the path (in the integrator's lanes).
    pub ld: SampledSpectrum,
    /// The visible point, if the path found one.
    pub vp: Option<VisiblePoint>,
}

/// The weight of a contribution of a path that did (or did not) keep only its hero wavelength.
#[inline]
fn hero_weight(hero_only: bool) -> SampledSpectrum {
    if hero_only {
        HERO_ONLY
    } else {
        SampledSpectrum::ONE
    }
}

/// Follows the camera ray `ray` (camera weight `weight`) through specular surfaces to its
/// visible point, gathering `Ld` on the way, at most `max_depth` bounces, as pbrt-v4's SPPM
/// camera pass: emitted light counts in full at the camera ray and after a specular bounce,
/// and weighted by the power heuristic against light sampling after the others; direct light
/// by one light sample at each surface before the visible point (delta lights unweighted).
/// Once the visible point is set the path takes one more bounce, for the emitted light its
/// BSDF sample finds (the other half of the MIS pair), then stops.
pub fn camera_path(
    scene: &Scene,
    ray: &Ray,
    weight: f32,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
) -> CameraPath {
    let mut wavelengths = lambda.copied();
    let mut hero_only = false;
    let mut ld = SampledSpectrum::ZERO;
    let mut vp = None;
    let mut beta = SampledSpectrum::splat(weight);
    let mut ray = *ray;
    let mut depth = 0u32;
    let mut specular_bounce = false;
    let mut p_b = 1.0f32;
    let mut prev_ctx: Option<LightSampleContext> = None;
    let mut eta_scale = 1.0f32;
    loop {
        let Some(hit) = scene.intersect(&ray) else {
            for &i in scene.infinite_lights() {
                let (i, light) = (i as usize, &scene.lights()[i as usize]);
                let le = scene.environment_radiance(i, wavelengths.as_ref(), ray.d);
                if le == SampledSpectrum::ZERO {
                    continue;
                }
                let w = match (depth == 0 || specular_bounce, prev_ctx) {
                    (false, Some(ctx)) => {
                        let p_l = scene.light_sampler().pmf(&ctx, i)
                            * light.pdf_li(&ctx, normalize(ray.d), None);
                        power_heuristic(p_b, p_l)
                    }
                    _ => 1.0,
                };
                ld += beta * le * w * hero_weight(hero_only);
            }
            break;
        };
        let si = &hit.si;
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, wavelengths.as_ref()) else {
            // An interface between media: the ray goes on (pbrt-v4's SkipIntersection).
            ray = si.spawn_ray(ray.d);
            continue;
        };
        // A dispersive surface: the path keeps its hero wavelength from here on (pbrt-v4
        // terminates the secondary wavelengths as it builds the BSDF, before the emission).
        hero_only |= keep_hero_only(&mut wavelengths, disperses);
        let wo = si.wo;
        let le = emitted(scene, &hit, wo, wavelengths.as_ref());
        if le != SampledSpectrum::ZERO {
            let w = match (
                depth == 0 || specular_bounce,
                prev_ctx,
                scene.prim(hit.prim).emission,
            ) {
                (false, Some(ctx), Some(e)) => {
                    let light = &scene.lights()[e.light as usize];
                    let p_l = scene.light_sampler().pmf(&ctx, e.light as usize)
                        * light.pdf_li(&ctx, normalize(ray.d), Some((si.p, si.n)));
                    power_heuristic(p_b, p_l)
                }
                _ => 1.0,
            };
            ld += beta * le * w * hero_weight(hero_only);
        }
        if depth == max_depth || vp.is_some() {
            break;
        }
        depth += 1;
        let ctx = LightSampleContext::at(si);
        let flags = bsdf.flags();
        ld += beta
            * direct_light(scene, si, &bsdf, wo, &ctx, sampler, wavelengths.as_ref())
            * hero_weight(hero_only);
        if flags.has(BxdfFlags::DIFFUSE) || (flags.has(BxdfFlags::GLOSSY) && depth == max_depth) {
            vp = Some(VisiblePoint {
                p: si.p,
                wo,
                bsdf,
                beta,
                hero_only,
            });
        }
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let Some(bs) = bsdf.sample_f(wo, uc, u, TransportMode::Radiance) else {
            break;
        };
        specular_bounce = bs.flags.is_specular();
        if bs.is_transmission() {
            eta_scale *= bs.eta * bs.eta;
        }
        beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
        p_b = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, TransportMode::Radiance)
        } else {
            bs.pdf
        };
        // Russian roulette as pbrt-v4's SPPM: from the first bounce, q = max(0.05, 1 − max β).
        let m = (beta * eta_scale).max_element();
        if m < 1.0 {
            let q = (1.0 - m).max(0.05);
            if sampler.get_1d() < q {
                break;
            }
            beta /= 1.0 - q;
        }
        if !beta.is_finite() || beta == SampledSpectrum::ZERO {
            break;
        }
        ray = si.spawn_ray(bs.wi);
        prev_ctx = Some(ctx);
    }
    CameraPath { ld, vp }
}

/// The random numbers of one photon: dimension d of photon i of iteration k is the scrambled
/// radical inverse of k·N + i (N photons per iteration) in the d-th prime base, as pbrt-v4's
/// SPPM draws them (a Halton sequence over all photons of the render, its digits permuted by
/// the seed), so that each photon is a pure function of (seed, iteration, photon index).
/// Past the last prime base, a hash of (seed, index, dimension).
pub struct PhotonSampler {
    perms: Arc<DigitPermutations>,
    seed: u64,
    index: u64,
    dim: usize,
}

impl PhotonSampler {
    /// The sampler of the photons seeded by `seed`, at Halton index `index`.
    pub fn new(perms: Arc<DigitPermutations>, seed: u64, index: u64) -> PhotonSampler {
        PhotonSampler {
            perms,
            seed,
            index,
            dim: 0,
        }
    }

    /// Moves to Halton index `index`, dimension 0.
    pub fn start(&mut self, index: u64) {
        self.index = index;
        self.dim = 0;
    }

    /// The next dimension.
    pub fn get_1d(&mut self) -> f32 {
        let d = self.dim;
        self.dim += 1;
        if d < PRIME_TABLE_SIZE {
            scrambled_radical_inverse(d, self.index, &self.perms, self.seed)
        } else {
            u32_to_unit_f32(hash_u64(&[self.seed, self.index, d as u64]) as u32)
        }
    }

    /// The next two dimensions.
    pub fn get_2d(&mut self) -> Vec2 {
        let x = self.get_1d();
        Vec2::new(x, self.get_1d())
    }
}

impl crate::sampling::SampleSource for PhotonSampler {
    #[inline]
    fn get_1d(&mut self) -> f32 {
        PhotonSampler::get_1d(self)
    }

    #[inline]
    fn get_2d(&mut self) -> Vec2 {
        PhotonSampler::get_2d(self)
    }
}

/// A photon's flux arriving at a surface point: deposited into the visible points near `p`.
#[derive(Clone, Copy, Debug)]
pub struct PhotonHit {
    /// The surface point.
    pub p: Vec3,
    /// Direction back towards where the photon came from (−ray direction).
    pub wi: Vec3,
    /// The photon's flux weight β.
    pub beta: SampledSpectrum,
    /// The photon kept only its hero wavelength (it went through a dispersive surface).
    pub hero_only: bool,
}

/// Traces one photon of at most `max_depth` bounces, giving `deposit` every surface it
/// reaches after `first_deposit` bounces (sppm's is 1, as pbrt-v4's: the light reaching a
/// surface straight from a light is the camera pass's Ld; 0 deposits direct light too, which
/// the tests compare with its analytic value), as pbrt-v4's SPPM photon pass: a light chosen by power
/// (p_l), a ray leaving it (p_pos, p_dir), β = Le·|cos θ|/(p_l·p_pos·p_dir); at each surface
/// the BSDF (importance transport) picks the next direction, β' = β·f·|cos θ|/pdf, and the
/// photon survives with probability min(1, max β'/max β) and is reweighted by it. Returns
/// whether a photon left a light.
pub fn trace_photon(
    scene: &Scene,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    first_deposit: u32,
    u: &mut PhotonSampler,
    deposit: &mut impl FnMut(&PhotonHit),
) -> bool {
    let ul = u.get_1d();
    let Some((light, p_l)) = scene.light_distribution().sample(ul) else {
        return false;
    };
    let (u0, u1) = (u.get_2d(), u.get_2d());
    let Some(les) = scene.lights()[light].sample_le(u0, u1, scene.shapes(), scene.meshes()) else {
        return false;
    };
    if les.pdf_pos == 0.0 || les.pdf_dir == 0.0 || p_l == 0.0 {
        return false;
    }
    let mut wavelengths = lambda.copied();
    let le = scene.light_radiance(light, wavelengths.as_ref(), les.l, les.factor, -les.w);
    let mut beta = le * (les.abs_cos() / (p_l * les.pdf_pos * les.pdf_dir));
    if beta == SampledSpectrum::ZERO || !beta.is_finite() {
        return false;
    }
    let mut hero_only = false;
    let mut ray = les.ray();
    let mut depth = 0;
    while depth < max_depth {
        let Some(hit) = scene.intersect(&ray) else {
            break;
        };
        let si = &hit.si;
        if depth >= first_deposit {
            deposit(&PhotonHit {
                p: si.p,
                wi: -ray.d,
                beta,
                hero_only,
            });
        }
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, wavelengths.as_ref()) else {
            // An interface between media: the photon goes on, the bounce not counted.
            ray = si.spawn_ray(ray.d);
            continue;
        };
        hero_only |= keep_hero_only(&mut wavelengths, disperses);
        let uc = u.get_1d();
        let u2 = u.get_2d();
        let Some(bs) = bsdf.sample_f(si.wo, uc, u2, TransportMode::Importance) else {
            break;
        };
        let b_new = beta * bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
        // Survival in proportion to the throughput's change.
        let q = (1.0 - b_new.max_element() / beta.max_element()).max(0.0);
        if u.get_1d() < q {
            break;
        }
        beta = b_new / (1.0 - q);
        if !beta.is_finite() || beta == SampledSpectrum::ZERO {
            break;
        }
        ray = si.spawn_ray(bs.wi);
        depth += 1;
    }
    true
}

/// What photon hit `h` adds to visible point `vp` (in the integrator's lanes, before the
/// film's colour): β_vp·β_photon·f(wo, wi), weighted once by [`HERO_ONLY`] if the camera path
/// or the photon kept only the hero wavelength.
#[inline]
pub fn photon_flux(vp: &VisiblePoint, h: &PhotonHit) -> SampledSpectrum {
    let f = vp.bsdf.f(vp.wo, h.wi, TransportMode::Radiance);
    vp.beta * h.beta * f * hero_weight(vp.hero_only || h.hero_only)
}
