//! Unidirectional path tracing with next-event estimation and multiple importance sampling.

use super::{bsdf_at, emitted};
use crate::light::LightSampleContext;
use crate::material::TransportMode;
use crate::math::Rgb;
use crate::ray::Ray;
use crate::sampling::{Sampler, power_heuristic};
use crate::scene::Scene;

/// Radiance along a camera ray, by path tracing up to `max_depth` bounces.
pub fn li(scene: &Scene, ray: &Ray, sampler: &mut Sampler, max_depth: u32) -> Rgb {
    let mut l = Rgb::ZERO;
    let mut beta = Rgb::ONE;
    let mut ray = *ray;
    let mut depth = 0u32;
    let mut specular_bounce = false;
    let mut p_b = 1.0f32;
    let mut prev_ctx: Option<LightSampleContext> = None;
    let mut eta_scale = 1.0f32;
    let n_lights = scene.lights.len().max(1) as f32;
    loop {
        let Some(hit) = scene.intersect(&ray) else {
            for light in &scene.lights {
                let le = light.le(ray.d);
                if le == Rgb::ZERO {
                    continue;
                }
                match (depth == 0 || specular_bounce, prev_ctx) {
                    (false, Some(ctx)) => {
                        let p_l = light.pdf_li(&ctx, ray.d.normalize()) / n_lights;
                        l += beta * power_heuristic(p_b, p_l) * le;
                    }
                    _ => l += beta * le,
                }
            }
            break;
        };
        let si = hit.si;
        let wo = si.wo;
        // Area lights are not sampled by next-event estimation yet: their emission is counted
        // where paths hit them.
        l += beta * emitted(scene, &hit, wo);
        let Some(bsdf) = bsdf_at(scene, &hit) else {
            specular_bounce = true;
            ray = si.spawn_ray(ray.d);
            continue;
        };
        if depth == max_depth {
            break;
        }
        depth += 1;
        let ctx = LightSampleContext {
            p: si.p,
            n: si.n,
            ns: si.shading.n,
        };
        let flags = bsdf.flags();
        if flags.is_non_specular() && !scene.lights.is_empty() {
            // Next-event estimation: one light chosen uniformly.
            let ul = sampler.get_1d();
            let u = sampler.get_2d();
            let li = ((ul * n_lights) as usize).min(scene.lights.len() - 1);
            let light = &scene.lights[li];
            if let Some(ls) = light.sample_li(&ctx, u) {
                let f = bsdf.f(wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(si.shading.n).abs();
                if ls.pdf > 0.0
                    && f != Rgb::ZERO
                    && !scene.intersect_p(&si.spawn_ray_to(ls.p_light))
                {
                    let p_l = ls.pdf / n_lights;
                    let w = if light.is_delta() {
                        1.0
                    } else {
                        power_heuristic(p_l, bsdf.pdf(wo, ls.wi, TransportMode::Radiance))
                    };
                    l += beta * f * ls.l * (w / p_l);
                }
            }
        } else {
            // Keep the sampler's dimensions aligned whatever the BSDF.
            sampler.get_1d();
            sampler.get_2d();
        }
        let uc = sampler.get_1d();
        let u = sampler.get_2d();
        let Some(bs) = bsdf.sample_f(wo, uc, u, TransportMode::Radiance) else {
            break;
        };
        beta *= bs.f * bs.wi.dot(si.shading.n).abs() / bs.pdf;
        // A layered BSDF's sample density is only proportional to the true one; MIS needs the
        // density the light-sampling side will also use.
        p_b = if bs.pdf_is_proportional {
            bsdf.pdf(wo, bs.wi, TransportMode::Radiance)
        } else {
            bs.pdf
        };
        specular_bounce = bs.flags.is_specular();
        if bs.flags.has(crate::material::BxdfFlags::TRANSMISSION) {
            eta_scale *= bs.eta * bs.eta;
        }
        prev_ctx = Some(ctx);
        ray = si.spawn_ray(bs.wi);
        // Russian roulette once the path carries little.
        let rr = beta * eta_scale;
        let m = rr.max_element();
        if m < 1.0 && depth > 1 {
            let q = (1.0 - m).max(0.0);
            if sampler.get_1d() < q {
                break;
            }
            beta /= 1.0 - q;
        }
        if !beta.is_finite() || beta == Rgb::ZERO {
            break;
        }
    }
    l
}
