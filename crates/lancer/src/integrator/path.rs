//! Unidirectional path tracing with next-event estimation and multiple importance sampling.

use super::path_spectra::PathSpectra;
use super::{PathVertex, bsdf_at_memo, specular_differentials, subsurface};
use crate::light::LightSampleContext;
use crate::material::{Bsdf, TransportMode};
use crate::math::{SampledSpectrum, Vec3, normalize};
use crate::ray::Ray;
use crate::sampling::{Sampler, power_heuristic};
use crate::scene::{Nearest, Scene};
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// Radiance along a camera ray, by path tracing up to `max_depth` bounces. With `regularize`,
/// near-specular lobes met after a non-specular bounce are roughened (pbrt-v4's path
/// regularisation: a little bias for much less noise in caustics). With `lambda` (spectral
/// mode) every colour entering transport is evaluated at those wavelengths, and so is the
/// result.
pub fn li(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    regularize: bool,
) -> SampledSpectrum {
    li_observed::<_, false>(
        scene,
        ray,
        sampler,
        lambda,
        max_depth,
        regularize,
        &mut (),
        None,
    )
}

/// Path tracing that leaves out the paths light tracing renders better, for
/// [`super::caustics`]: those whose first vertex (the surface the camera sees) scattered
/// by a non-specular lobe and every later one by a specular lobe, on to a light (E D S⁺ L,
/// caustics seen directly) when the light is a caustic source
/// ([`crate::light::Light::caustic_source`]). Everything else is [`li`]'s estimate,
/// unregularised.
pub fn li_without_caustics(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
) -> SampledSpectrum {
    li_observed::<_, true>(scene, ray, sampler, lambda, max_depth, false, &mut (), None)
}

/// The density with which the last bounce chose the ray's direction, as MIS against light
/// sampling needs it when the ray reaches a light. A layered BSDF's sample carries only a
/// proportional density; its MIS density is the BSDF's `pdf` estimate, a random walk of its
/// own, kept here unevaluated: most rays reach no light, and `pdf` is a deterministic function
/// of (wo, wi), so evaluating it later gives the same number. The BSDF itself waits beside it
/// (`deferred_bsdf` in [`li_observed`]): held in the enum, its 160 bytes were copied into
/// `p_b` at every bounce, `Known` or not.
#[derive(Clone, Copy)]
enum BouncePdf {
    /// The density, known when the direction was sampled.
    Known(f32),
    /// `bsdf.pdf(wo, wi)` of the BSDF kept for it, evaluated on demand.
    Deferred { wo: Vec3, wi: Vec3 },
}

impl BouncePdf {
    /// The density; `bsdf` is the BSDF kept for a `Deferred` one (always there for it).
    #[inline]
    fn value(&self, bsdf: &Option<Bsdf>) -> f32 {
        match (self, bsdf) {
            (BouncePdf::Known(p), _) => *p,
            (BouncePdf::Deferred { wo, wi }, Some(bsdf)) => deferred_pdf(bsdf, *wo, *wi),
            (BouncePdf::Deferred { .. }, None) => 0.0,
        }
    }
}

/// A layered BSDF's MIS density, out of line. Inlined, LLVM hoisted the start of `pdf` (the
/// frame's `to_local` of `wo` and `wi`) to the loop's back edge, where it ran on every bounce
/// on the `Deferred` payload even when `p_b` was `Known`: stale stack bytes, often denormal
/// floats whose multiplies take microcode assists (cbox: `li` fell from 31 % to 15 % of the
/// cpu-clock samples out of line, renders byte-identical).
#[cold]
#[inline(never)]
fn deferred_pdf(bsdf: &Bsdf, wo: Vec3, wi: Vec3) -> f32 {
    bsdf.pdf(wo, wi, TransportMode::Radiance)
}

/// Receives the vertices of a path as [`li_observed`] follows it.
pub trait PathObserver {
    /// Called at each surface the path meets, after the bounce was decided.
    fn vertex(&mut self, v: PathVertex);
}

/// Observes nothing: [`li`]'s observer, compiled away.
impl PathObserver for () {
    #[inline(always)]
    fn vertex(&mut self, _: PathVertex) {}
}

/// Records every vertex (`--check-nan`).
impl PathObserver for Vec<PathVertex> {
    fn vertex(&mut self, v: PathVertex) {
        self.push(v);
    }
}

/// [`li`], reporting each vertex of the path to `obs`; with `NO_CAUSTICS`,
/// [`li_without_caustics`] (compiled away otherwise); `first`, when given, is the camera
/// ray's nearest hit in the scene's BVHs, already found (by [`Scene::intersect_packet`], with
/// the camera rays of the pixel's other samples: the tile loop's case).
#[allow(clippy::too_many_arguments)] // li's, and the two ways of running it
pub fn li_observed<O: PathObserver, const NO_CAUSTICS: bool>(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    regularize: bool,
    obs: &mut O,
    mut first: Option<&Nearest>,
) -> SampledSpectrum {
    // The path's own copy of its wavelengths, which a dispersive surface may terminate.
    let mut wavelengths = lambda.copied();
    let mut l = SampledSpectrum::ZERO;
    let mut beta = SampledSpectrum::ONE;
    let mut ray = *ray;
    let mut depth = 0u32;
    let mut specular_bounce = false;
    let mut p_b = BouncePdf::Known(1.0);
    let mut deferred_bsdf: Option<Bsdf> = None;
    let mut prev_ctx: Option<LightSampleContext> = None;
    let mut eta_scale = 1.0f32;
    let mut any_non_specular = false;
    // NO_CAUSTICS: the path so far is E D S* (its first bounce non-specular, every later one
    // specular); a light met after at least one S is light tracing's (E D S⁺ L).
    let mut caustic_chain = false;
    // Constant spectra at the path's wavelengths, evaluated once (spectral mode).
    let mut memo = PathSpectra::new();
    let mut diff = None; // the ray's differentials after specular bounces (filtered textures)
    loop {
        // Bound by reference, here and for the BSDF: moving the records out of the returned
        // Options copied them with wide loads right after the callee's narrower stores, which
        // stalled on store forwarding.
        let mut found = match first.take() {
            Some(n) => scene.intersect_from(&ray, n),
            None => scene.intersect(&ray),
        };
        if diff.is_some() {
            specular_differentials::apply(&mut found, diff.as_ref());
        }
        // E D S⁺ met a light: its caustic sources are light tracing's.
        let caustic = NO_CAUSTICS && caustic_chain && depth >= 2;
        let Some(hit) = &found else {
            // Environment light: counted in full where no light sampling could have found it
            // (camera rays, specular bounces), otherwise weighted against light sampling.
            let mut p_b_value = None;
            for &i in scene.infinite_lights() {
                let (i, light) = (i as usize, &scene.lights()[i as usize]);
                let le = scene.environment_radiance(i, wavelengths.as_ref(), ray.d);
                if le == SampledSpectrum::ZERO
                    || (caustic && light.caustic_source(-normalize(ray.d)))
                {
                    continue;
                }
                match (depth == 0 || specular_bounce, prev_ctx) {
                    (false, Some(ctx)) => {
                        let p_l = scene.light_sampler().pmf(&ctx, i)
                            * light.pdf_li(&ctx, normalize(ray.d), None);
                        let p_b = *p_b_value.get_or_insert_with(|| p_b.value(&deferred_bsdf));
                        l += beta * power_heuristic(p_b, p_l) * le;
                    }
                    _ => l += beta * le,
                }
            }
            break;
        };
        let si = &hit.si;
        let wo = si.wo;
        // An area light hit by a BSDF-sampled ray: weighted against the chance that light
        // sampling picked the same point.
        let mut le = memo.emitted(scene, hit, wo, wavelengths.as_ref());
        if caustic
            && (scene.prim(hit.prim).emission)
                .is_some_and(|e| scene.lights()[e.light as usize].caustic_source(-wo))
        {
            le = SampledSpectrum::ZERO;
        }
        if le != SampledSpectrum::ZERO {
            match (
                depth == 0 || specular_bounce,
                prev_ctx,
                scene.prim(hit.prim).emission,
            ) {
                (false, Some(ctx), Some(e)) => {
                    let light = &scene.lights()[e.light as usize];
                    let p_l = scene.light_sampler().pmf(&ctx, e.light as usize)
                        * light.pdf_li(&ctx, normalize(ray.d), Some((si.p, si.n)));
                    l += beta * power_heuristic(p_b.value(&deferred_bsdf), p_l) * le;
                }
                _ => l += beta * le,
            }
        }
        let mut scattering = bsdf_at_memo(scene, hit, wavelengths.as_ref(), Some(&mut memo));
        let Some((bsdf, disperses)) = &mut scattering else {
            // An interface between media: no surface, the ray goes on unchanged.
            ray = si.spawn_ray(ray.d);
            continue;
        };
        // A dispersive dielectric bends each wavelength its own way: the path keeps only its
        // hero wavelength, weighting what it has gathered and will gather by HERO_ONLY
        // (pbrt-v4's TerminateSecondary, see [`crate::spectrum::hero`]), once.
        if let Some(lam) = wavelengths
            .as_mut()
            .filter(|l| *disperses && !l.secondary_terminated())
        {
            lam.terminate_secondary();
            l *= HERO_ONLY;
            beta *= HERO_ONLY;
        }
        if regularize && any_non_specular {
            bsdf.bxdf.regularize();
        }
        if depth == max_depth {
            break;
        }
        depth += 1;
        let ctx = LightSampleContext::at(si);
        let flags = bsdf.flags();
        // wo in the shading frame, once for f, pdf and the sample.
        let wo_l = bsdf.frame.to_local(wo);
        if flags.is_non_specular() && !scene.lights().is_empty() {
            // Next-event estimation: one light chosen by the scene's light sampler, one point on it.
            let ul = sampler.get_1d();
            let u = sampler.get_2d();
            if let Some((i, pmf)) = scene.light_sampler().sample(&ctx, ul) {
                let light = &scene.lights()[i];
                if let Some(ls) = scene.sample_li(light, &ctx, u).filter(|ls| ls.pdf > 0.0) {
                    let unoccluded = || !scene.intersect_p(&si.spawn_ray_to(ls.p_light));
                    // A layered BSDF's f is a random walk, dearer than the shadow ray: the ray
                    // goes first for it, after f for the others (f is often zero for them).
                    let walk = bsdf.bxdf.is_stochastic();
                    // wi in the shading frame: its z is wi·ns, the cosine (the frame's z is ns).
                    let wi_l = bsdf.frame.to_local(ls.wi);
                    let f = if walk && !unoccluded() {
                        SampledSpectrum::ZERO
                    } else {
                        bsdf.f_lo(wo_l, wi_l, TransportMode::Radiance) * wi_l.z.abs()
                    };
                    if f != SampledSpectrum::ZERO && (walk || unoccluded()) {
                        let p_l = pmf * ls.pdf;
                        let w = if light.is_delta() {
                            1.0
                        } else {
                            power_heuristic(p_l, bsdf.pdf_lo(wo_l, wi_l, TransportMode::Radiance))
                        };
                        l += beta
                            * f
                            * memo.light_radiance(
                                scene,
                                i,
                                wavelengths.as_ref(),
                                ls.l,
                                ls.factor,
                                ls.wi,
                            )
                            * (w / p_l);
                    }
                }
            }
        } else {
            // Keep the sampler's dimensions aligned whatever the BSDF.
            sampler.get_1d();
            sampler.get_2d();
        }
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let bs = bsdf.sample_f_lo(wo_l, uc, u, TransportMode::Radiance);
        obs.vertex(PathVertex {
            depth,
            prim: hit.prim,
            p: si.p,
            n: si.n,
            ns: si.shading.n,
            wo,
            wi: bs.as_ref().map(|b| b.wi),
            f: bs.as_ref().map(|b| b.f),
            pdf: bs.as_ref().map(|b| b.pdf),
            beta,
            l,
        });
        let Some(bs) = bs else {
            break;
        };
        beta *= bs.f * bs.wi.dot(si.shading.n).abs() / bs.pdf;
        // A layered BSDF's sample density is only proportional to the true one; MIS needs the
        // density the light-sampling side will also use, evaluated if a light is reached.
        p_b = if bs.pdf_is_proportional {
            deferred_bsdf = Some(*bsdf);
            BouncePdf::Deferred { wo, wi: bs.wi }
        } else {
            BouncePdf::Known(bs.pdf)
        };
        specular_bounce = bs.flags.is_specular();
        any_non_specular |= !specular_bounce;
        if NO_CAUSTICS {
            caustic_chain = if depth == 1 {
                !specular_bounce
            } else {
                caustic_chain && specular_bounce
            };
        }
        if bs.flags.has(crate::material::BxdfFlags::TRANSMISSION) {
            eta_scale *= bs.eta * bs.eta;
        }
        prev_ctx = Some(ctx);
        // Ray differentials through specular bounces, only where textures filter over
        // footprints (`spawn` tests that first; one loop for every scene: a copy of the loop
        // per case doubled its code and pushed the BSDF sample out of line, a stall per bounce).
        diff = specular_differentials::spawn(scene, &ray, diff.as_ref(), hit, &bs);
        ray = si.spawn_ray(bs.wi);
        // Refracted into a subsurface material: a BSSRDF picks where the light leaves.
        if bs.is_transmission() {
            match subsurface::exit(scene, hit, sampler, wavelengths.as_ref(), &mut beta, &mut l) {
                subsurface::Exit::NotSubsurface => {}
                subsurface::Exit::Lost => break,
                subsurface::Exit::Left {
                    ray: exit_ray,
                    p_b: exit_pdf,
                    ctx: exit_ctx,
                } => {
                    ray = exit_ray;
                    diff = None;
                    p_b = BouncePdf::Known(exit_pdf);
                    prev_ctx = Some(exit_ctx);
                    specular_bounce = false;
                    any_non_specular = true;
                    caustic_chain = false;
                }
            }
        }
        // Russian roulette once the path carries little.
        let rr = beta * eta_scale;
        let m = rr.max_element();
        if m < 1.0 && depth > super::RR_AFTER_DEPTH {
            let q = (1.0 - m).max(0.0);
            if sampler.get_1d() < q {
                break;
            }
            beta /= 1.0 - q;
        }
        if !beta.is_finite() || beta == SampledSpectrum::ZERO {
            break;
        }
    }
    l
}
