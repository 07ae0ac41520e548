//! Volumetric path tracing, as pbrt-v4's `VolPathIntegrator`: the path tracer of
//! [`super::path`] extended to participating media.
//!
//! Along each ray through a medium, tentative collisions are drawn against the majorant σ_maj
//! ([`sample_t_maj`]); at each one the path is absorbed, scattered or passes on (a null
//! collision) with probabilities σ_a/σ_maj, σ_s/σ_maj and the rest (delta tracking). Sampling
//! follows one lane (the *hero*); the others ride along with the ratios
//! r_u = p_u(λ)/p_path and r_l = p_l(λ)/p_path of the unidirectional and light-sampling
//! densities of every lane to the density actually used, and a contribution f/p is divided by
//! the average of those ratios: the one-sample balance heuristic across lanes (spectral MIS)
//! and, with r_l, across BSDF/phase and light sampling. Shadow rays estimate transmittance by
//! ratio tracking and pass through `interface` surfaces.
//!
//! In spectral mode lane 0 is already a random wavelength. In RGB mode the lanes are
//! (r, g, b, b); the hero is one of the four chosen uniformly per camera ray (a hash of the
//! ray), which makes the lane average the matching mixture density (b counted twice, chosen
//! twice as often).
//!
//! A scene without media is rendered by [`super::path`] itself: the same image, at the same
//! cost.

use super::{bsdf_at, emitted, path};
use crate::light::LightSampleContext;
use crate::material::{Material, TransportMode};
use crate::math::{SampledSpectrum, Vec3, normalize};
use crate::medium::{MediumProperties, PhaseSample, sample_t_maj};
use crate::ray::Ray;
use crate::sampling::{Pcg32, Sampler, hash_u64};
use crate::scene::{Scene, SceneHit};
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// The average of the lanes (the spectral-MIS denominator).
#[inline]
pub(super) fn avg(s: SampledSpectrum) -> f32 {
    s.element_sum() * 0.25
}

/// True when `s` has a non-zero lane.
#[inline]
fn nonzero(s: SampledSpectrum) -> bool {
    s != SampledSpectrum::ZERO
}

/// The medium a ray leaving `hit` in direction `d` travels in: the far side of a medium
/// boundary, else the medium it was already in.
#[inline]
pub(super) fn medium_after(
    scene: &Scene,
    hit: &SceneHit,
    d: Vec3,
    current: Option<u32>,
) -> Option<u32> {
    scene.medium_past(hit.prim, hit.si.n, d, current)
}

/// A generator seeded by a hash of two sampler values (pbrt-v4 seeds the collision stream the
/// same way: deterministic per sample, independent of the sampler's dimensions beyond these).
pub(super) fn seeded_rng(a: f32, b: f32) -> Pcg32 {
    Pcg32::new(
        hash_u64(&[a.to_bits() as u64]),
        hash_u64(&[b.to_bits() as u64]),
    )
}

/// The lane whose densities drive sampling: 0 in spectral mode, one of the four chosen by a
/// hash of the camera ray in RGB mode.
pub(super) fn hero_lane(ray: &Ray, lambda: Option<&SampledWavelengths>) -> usize {
    if lambda.is_some() {
        return 0;
    }
    let h = hash_u64(&[
        ray.o.x.to_bits() as u64 | (ray.o.y.to_bits() as u64) << 32,
        ray.o.z.to_bits() as u64 | (ray.d.x.to_bits() as u64) << 32,
        ray.d.y.to_bits() as u64 | (ray.d.z.to_bits() as u64) << 32,
    ]);
    (h >> 62) as usize
}

/// Radiance along a camera ray by volumetric path tracing, up to `max_depth` scattering events
/// (surfaces and media). The camera sits in the scene's camera medium.
pub fn li(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    regularize: bool,
) -> SampledSpectrum {
    if scene.media().is_empty() {
        return path::li(scene, ray, sampler, lambda, max_depth, regularize);
    }
    Walk {
        scene,
        hero: hero_lane(ray, lambda),
        wavelengths: lambda.copied(),
        max_depth,
        regularize,
    }
    .run(*ray, sampler)
}

/// What stays fixed along one path.
struct Walk<'a> {
    scene: &'a Scene,
    hero: usize,
    /// The path's own copy of its wavelengths, which a dispersive surface may terminate.
    wavelengths: Option<SampledWavelengths>,
    max_depth: u32,
    regularize: bool,
}

/// What changes along one path.
struct State {
    l: SampledSpectrum,
    beta: SampledSpectrum,
    r_u: SampledSpectrum,
    r_l: SampledSpectrum,
    depth: u32,
    specular_bounce: bool,
    any_non_specular: bool,
    eta_scale: f32,
    prev_ctx: Option<LightSampleContext>,
    ray: Ray,
    medium: Option<u32>,
}

/// What happened to a ray crossing a medium.
enum MediumEvent {
    /// The path ends (absorbed, out of depth, or zero throughput).
    Terminated,
    /// It scattered: the state holds the new ray.
    Scattered,
    /// It reached the end of the segment (a surface, or infinity).
    Passed,
}

impl Walk<'_> {
    fn lambda(&self) -> Option<&SampledWavelengths> {
        self.wavelengths.as_ref()
    }

    fn run(mut self, ray: Ray, sampler: &mut Sampler) -> SampledSpectrum {
        let scene = self.scene;
        let mut s = State {
            l: SampledSpectrum::ZERO,
            beta: SampledSpectrum::ONE,
            r_u: SampledSpectrum::ONE,
            r_l: SampledSpectrum::ONE,
            depth: 0,
            specular_bounce: false,
            any_non_specular: false,
            eta_scale: 1.0,
            prev_ctx: None,
            ray,
            medium: scene.camera_medium(),
        };
        loop {
            let hit = scene.intersect(&s.ray);
            if s.medium.is_some() {
                match self.through_medium(&mut s, hit.as_ref().map(|h| h.si.t), sampler) {
                    MediumEvent::Terminated => return s.l,
                    MediumEvent::Scattered => continue,
                    MediumEvent::Passed => {}
                }
            }
            let Some(hit) = hit else {
                self.escaped(&mut s);
                break;
            };
            let si = &hit.si;
            let wo = si.wo;
            // Emission of an area light reached by unidirectional sampling.
            let le = emitted(scene, &hit, wo, self.lambda());
            if nonzero(le) {
                match (s.depth == 0 || s.specular_bounce, s.prev_ctx) {
                    (false, Some(ctx)) => {
                        let e = scene.prim(hit.prim).emission;
                        let p_l = e.map_or(0.0, |e| {
                            scene.light_sampler().pmf(&ctx, e.light as usize)
                                * scene.lights()[e.light as usize].pdf_li(
                                    &ctx,
                                    normalize(s.ray.d),
                                    Some((si.p, si.n)),
                                )
                        });
                        let r_l = s.r_l * p_l;
                        s.l += s.beta * le / avg(s.r_u + r_l);
                    }
                    _ => s.l += s.beta * le / avg(s.r_u),
                }
            }
            let Some((mut bsdf, disperses)) = bsdf_at(scene, &hit, self.lambda()) else {
                // A boundary that does not scatter: the ray goes on, perhaps in a new medium.
                s.medium = medium_after(scene, &hit, s.ray.d, s.medium);
                s.ray = si.spawn_ray(s.ray.d);
                continue;
            };
            if let Some(lam) = self
                .wavelengths
                .as_mut()
                .filter(|l| disperses && !l.secondary_terminated())
            {
                lam.terminate_secondary();
                s.l *= HERO_ONLY;
                s.beta *= HERO_ONLY;
            }
            if s.depth >= self.max_depth {
                return s.l;
            }
            s.depth += 1;
            if self.regularize && s.any_non_specular {
                bsdf.bxdf.regularize();
            }
            let ctx = LightSampleContext::at(si);
            if bsdf.flags().is_non_specular() {
                let ul = sampler.get_1d();
                let u = sampler.get_2d();
                let scatter = |wi: Vec3| {
                    (
                        bsdf.f(wo, wi, TransportMode::Radiance) * wi.dot(si.shading.n).abs(),
                        bsdf.pdf(wo, wi, TransportMode::Radiance),
                    )
                };
                let origin = |target: Vec3| si.spawn_ray_to(target);
                s.l += self.sample_ld(&ctx, ul, u, scatter, origin, s.medium, s.beta, s.r_u);
            } else {
                sampler.get_1d();
                sampler.get_2d();
            }
            s.prev_ctx = Some(ctx);
            let uc = sampler.get_1d();
            let u = sampler.get_2d();
            let Some(bs) = bsdf.sample_f(wo, uc, u, TransportMode::Radiance) else {
                break;
            };
            s.beta *= bs.f * bs.wi.dot(si.shading.n).abs() / bs.pdf;
            s.r_l = if bs.pdf_is_proportional {
                s.r_u / bsdf.pdf(wo, bs.wi, TransportMode::Radiance)
            } else {
                s.r_u / bs.pdf
            };
            s.specular_bounce = bs.flags.is_specular();
            s.any_non_specular |= !s.specular_bounce;
            if bs.flags.has(crate::material::BxdfFlags::TRANSMISSION) {
                s.eta_scale *= bs.eta * bs.eta;
            }
            s.medium = medium_after(scene, &hit, bs.wi, s.medium);
            s.ray = si.spawn_ray(bs.wi);
            if !nonzero(s.beta) || !s.beta.is_finite() {
                break;
            }
            // Russian roulette on the throughput relative to the lanes' average density.
            let rr = s.beta * s.eta_scale / avg(s.r_u);
            let m = rr.max_element();
            if m < 1.0 && s.depth > super::RR_AFTER_DEPTH {
                let q = (1.0 - m).max(0.0);
                if sampler.get_1d() < q {
                    break;
                }
                s.beta /= 1.0 - q;
            }
        }
        s.l
    }

    /// Environment lights seen by a ray leaving the scene.
    fn escaped(&self, s: &mut State) {
        let scene = self.scene;
        for &i in scene.infinite_lights() {
            let (i, light) = (i as usize, &scene.lights()[i as usize]);
            let le = scene.environment_radiance(i, self.lambda(), s.ray.d);
            if le == SampledSpectrum::ZERO {
                continue;
            }
            match (s.depth == 0 || s.specular_bounce, s.prev_ctx) {
                (false, Some(ctx)) => {
                    let p_l = scene.light_sampler().pmf(&ctx, i)
                        * light.pdf_li(&ctx, normalize(s.ray.d), None);
                    s.l += s.beta * le / avg(s.r_u + s.r_l * p_l);
                }
                _ => s.l += s.beta * le / avg(s.r_u),
            }
        }
    }

    /// Delta tracking along `s.ray` in `s.medium` up to the surface at `t_hit` (or infinity):
    /// emission gathered at every tentative collision, then absorption, real scattering (with
    /// next-event estimation through the phase function) or a null collision.
    fn through_medium(
        &self,
        s: &mut State,
        t_hit: Option<f32>,
        sampler: &mut Sampler,
    ) -> MediumEvent {
        let scene = self.scene;
        let h = self.hero;
        let medium = scene.medium(s.medium.expect("in a medium"));
        let t_max = t_hit.unwrap_or(f32::INFINITY);
        let mut rng = seeded_rng(sampler.get_1d(), sampler.get_1d());
        let u = sampler.get_1d();
        let mut scattered = false;
        let mut terminated = false;
        let (o, d) = (s.ray.o, s.ray.d);
        let t_maj = sample_t_maj(
            medium,
            o,
            d,
            t_max,
            u,
            &mut rng,
            self.lambda(),
            h,
            |p, mp: &MediumProperties, sigma_maj, t_maj, rng| {
                if !nonzero(s.beta) {
                    terminated = true;
                    return false;
                }
                // Emission: L += β·T_maj·σ_a·Le / (σ_maj·T_maj)[h], weighted across lanes.
                if s.depth < self.max_depth && nonzero(mp.le) {
                    let pdf = sigma_maj[h] * t_maj[h];
                    let betap = s.beta * t_maj / pdf;
                    let r_e = s.r_u * sigma_maj * t_maj / pdf;
                    if nonzero(r_e) {
                        s.l += betap * mp.sigma_a * mp.le / avg(r_e);
                    }
                }
                match collision(mp, sigma_maj, h, rng.uniform()) {
                    Collision::Absorb => {
                        terminated = true;
                        false
                    }
                    Collision::Scatter => {
                        // Real scattering.
                        if s.depth >= self.max_depth {
                            terminated = true;
                            return false;
                        }
                        s.depth += 1;
                        let pdf = t_maj[h] * mp.sigma_s[h];
                        s.beta *= t_maj * mp.sigma_s / pdf;
                        s.r_u *= t_maj * mp.sigma_s / pdf;
                        if nonzero(s.beta) && nonzero(s.r_u) {
                            let wo = -normalize(d);
                            let ctx = LightSampleContext::in_medium(p);
                            let phase = mp.phase;
                            let ul = sampler.get_1d();
                            let u = sampler.get_2d();
                            let scatter = |wi: Vec3| {
                                let f = phase.p(wo, wi);
                                (SampledSpectrum::splat(f), f)
                            };
                            // Rays leaving a medium point keep the path's time.
                            let time = s.ray.time;
                            let origin = |target: Vec3| {
                                Ray::spawn_to(p, Vec3::ZERO, Vec3::ZERO, target).at_time(time)
                            };
                            s.l += self
                                .sample_ld(&ctx, ul, u, scatter, origin, s.medium, s.beta, s.r_u);
                            match phase.sample(wo, sampler.get_2d()) {
                                Some(PhaseSample { p: f, wi, pdf }) => {
                                    s.beta *= f / pdf;
                                    s.r_l = s.r_u / pdf;
                                    s.prev_ctx = Some(ctx);
                                    s.ray = Ray::new(p, wi).at_time(time);
                                    s.specular_bounce = false;
                                    s.any_non_specular = true;
                                    scattered = true;
                                }
                                None => terminated = true,
                            }
                        }
                        false
                    }
                    Collision::Null => {
                        // Null collision: the path goes on, reweighted.
                        let sigma_n =
                            (sigma_maj - mp.sigma_a - mp.sigma_s).max(SampledSpectrum::ZERO);
                        let pdf = t_maj[h] * sigma_n[h];
                        if pdf == 0.0 {
                            s.beta = SampledSpectrum::ZERO;
                        } else {
                            s.beta *= t_maj * sigma_n / pdf;
                            s.r_u *= t_maj * sigma_n / pdf;
                            s.r_l *= t_maj * sigma_maj / pdf;
                        }
                        nonzero(s.beta) && nonzero(s.r_u)
                    }
                }
            },
        );
        if terminated || !nonzero(s.beta) || !nonzero(s.r_u) || !s.beta.is_finite() {
            return MediumEvent::Terminated;
        }
        if scattered {
            return MediumEvent::Scattered;
        }
        // Reached the end: T_maj / T_maj[h] (the hero's transmittance was the probability of
        // getting here).
        let w = t_maj / t_maj[h];
        s.beta *= w;
        s.r_u *= w;
        s.r_l *= w;
        if !s.beta.is_finite() {
            return MediumEvent::Terminated;
        }
        MediumEvent::Passed
    }

    /// Next-event estimation from a point (a surface or a point in a medium): one light chosen
    /// by the scene's light sampler, one point on it, its visibility and transmittance by ratio
    /// tracking through media and `interface` surfaces. `scatter(wi)` gives the point's
    /// f·|cos| (or phase value) and its sampling density; `origin(target)` the shadow ray
    /// towards a point; `medium` the medium the shadow ray starts in; `beta` and `r_p` the
    /// path's throughput and ratios.
    #[allow(clippy::too_many_arguments)]
    fn sample_ld(
        &self,
        ctx: &LightSampleContext,
        ul: f32,
        u: crate::math::Vec2,
        scatter: impl Fn(Vec3) -> (SampledSpectrum, f32),
        origin: impl Fn(Vec3) -> Ray,
        medium: Option<u32>,
        beta: SampledSpectrum,
        r_p: SampledSpectrum,
    ) -> SampledSpectrum {
        let scene = self.scene;
        let Some((i, pmf)) = scene.light_sampler().sample(ctx, ul) else {
            return SampledSpectrum::ZERO;
        };
        let light = &scene.lights()[i];
        let Some(ls) = scene.sample_li(light, ctx, u) else {
            return SampledSpectrum::ZERO;
        };
        if ls.pdf <= 0.0 {
            return SampledSpectrum::ZERO;
        }
        let (f_hat, scatter_pdf) = scatter(ls.wi);
        if !nonzero(f_hat) {
            return SampledSpectrum::ZERO;
        }
        let Some((t_ray, mut r_l, mut r_u)) = transmittance(
            scene,
            origin(ls.p_light),
            ls.p_light,
            medium,
            self.lambda(),
            self.hero,
        ) else {
            return SampledSpectrum::ZERO;
        };
        let l = scene.light_radiance(i, self.lambda(), ls.l, ls.factor, ls.wi);
        let p_l = pmf * ls.pdf;
        r_l *= r_p * p_l;
        r_u *= r_p * scatter_pdf;
        if light.is_delta() || invisible(scene, light) {
            beta * f_hat * t_ray * l / avg(r_l)
        } else {
            beta * f_hat * t_ray * l / avg(r_l + r_u)
        }
    }
}

/// The transmittance of the shadow ray `ray` towards `target`, starting in `medium`, with
/// its lane ratios (T_ray, r_l, r_u): `None` when an opaque surface blocks it. Surfaces
/// with an `interface` material let it through (changing its medium); media attenuate it
/// by ratio tracking (homogeneous ones by their closed form), with Russian roulette once it
/// carries little. `lambda` and the hero lane `h` are the path's.
pub(super) fn transmittance(
    scene: &Scene,
    mut ray: Ray,
    target: Vec3,
    mut medium: Option<u32>,
    lambda: Option<&SampledWavelengths>,
    h: usize,
) -> Option<(SampledSpectrum, SampledSpectrum, SampledSpectrum)> {
    let mut t_ray = SampledSpectrum::ONE;
    let mut r_l = SampledSpectrum::ONE;
    let mut r_u = SampledSpectrum::ONE;
    let mut rng = Pcg32::new(
        hash_u64(&[
            ray.o.x.to_bits() as u64,
            ray.o.y.to_bits() as u64,
            ray.o.z.to_bits() as u64,
        ]),
        hash_u64(&[
            ray.d.x.to_bits() as u64,
            ray.d.y.to_bits() as u64,
            ray.d.z.to_bits() as u64,
        ]),
    );
    loop {
        if ray.d == Vec3::ZERO {
            break;
        }
        let hit = scene.intersect(&ray);
        if let Some(hit) = &hit
            && !is_interface(scene, hit)
        {
            return None;
        }
        let t_max = hit.as_ref().map_or(ray.t_max, |h| h.si.t);
        let uniform =
            medium.and_then(|m| scene.medium(m).uniform_transmittance(ray.d, t_max, lambda));
        if let Some(tr) = uniform {
            // A homogeneous stretch: its transmittance in closed form (ratio tracking's
            // expectation, without its noise).
            t_ray *= tr;
        } else if let Some(m) = medium {
            let u = rng.uniform();
            let t_maj = sample_t_maj(
                scene.medium(m),
                ray.o,
                ray.d,
                t_max,
                u,
                &mut rng,
                lambda,
                h,
                |_, mp, sigma_maj, t_maj, rng| {
                    // Ratio tracking: weight by σ_n/σ_maj at every tentative collision.
                    let sigma_n = (sigma_maj - mp.sigma_a - mp.sigma_s).max(SampledSpectrum::ZERO);
                    let pdf = t_maj[h] * sigma_maj[h];
                    t_ray *= t_maj * sigma_n / pdf;
                    r_l *= t_maj * sigma_maj / pdf;
                    r_u *= t_maj * sigma_n / pdf;
                    let tr = t_ray / avg(r_l + r_u);
                    if tr.max_element() < 0.05 {
                        let q = 0.75;
                        if rng.uniform() < q {
                            t_ray = SampledSpectrum::ZERO;
                        } else {
                            t_ray /= 1.0 - q;
                        }
                    }
                    nonzero(t_ray)
                },
            );
            let w = t_maj / t_maj[h];
            t_ray *= w;
            r_l *= w;
            r_u *= w;
        }
        if !nonzero(t_ray) || !t_ray.is_finite() {
            return None;
        }
        let Some(hit) = hit else {
            break;
        };
        medium = medium_after(scene, &hit, ray.d, medium);
        ray = hit.si.spawn_ray_to(target);
    }
    Some((t_ray, r_l, r_u))
}

/// True for an area light whose surface has a constant alpha of 0: rays never meet it, so
/// light sampling is its only strategy and takes the full weight (pbrt-v4 makes such lights
/// delta-position lights for the same reason).
fn invisible(scene: &Scene, light: &crate::light::Light) -> bool {
    light
        .as_area()
        .is_some_and(|a| scene.prim(a.prim).alpha == Some(crate::texture::FloatTex::Const(0.0)))
}

/// True when the surface hit has no BSDF (an `interface` material): shadow rays pass it.
fn is_interface(scene: &Scene, hit: &SceneHit) -> bool {
    let m = scene.prim(hit.prim).material;
    matches!(scene.material(m), Material::Interface(_))
}

/// What a tentative collision of delta tracking turns out to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Collision {
    /// The path is absorbed.
    Absorb,
    /// The path scatters (a real collision).
    Scatter,
    /// A null collision: the path goes on.
    Null,
}

/// The event at a tentative collision with properties `mp` under majorant `sigma_maj`, at hero
/// lane `h`: absorption, scattering or a null collision with probabilities σ_a/σ_maj, σ_s/σ_maj
/// and the rest, chosen by `u` (pbrt-v4's `SampleDiscrete` over the three).
pub(super) fn collision(
    mp: &MediumProperties,
    sigma_maj: SampledSpectrum,
    h: usize,
    u: f32,
) -> Collision {
    let p_absorb = mp.sigma_a[h] / sigma_maj[h];
    let p_scatter = mp.sigma_s[h] / sigma_maj[h];
    let p_null = (1.0 - p_absorb - p_scatter).max(0.0);
    match sample_discrete3([p_absorb, p_scatter, p_null], u) {
        0 => Collision::Absorb,
        1 => Collision::Scatter,
        _ => Collision::Null,
    }
}

/// Picks 0, 1 or 2 with probabilities proportional to `w` (pbrt-v4's `SampleDiscrete`):
/// the first index whose running sum exceeds u·Σw.
fn sample_discrete3(w: [f32; 3], u: f32) -> usize {
    let sum = w[0] + w[1] + w[2];
    let up = u * sum;
    if up < w[0] {
        0
    } else if up < w[0] + w[1] {
        1
    } else {
        2
    }
}
