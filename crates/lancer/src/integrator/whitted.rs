//! The course's ray tracer (Whitted 1980): what is visible, how the lights light it, shadows,
//! and perfect mirror reflection and refraction.

use super::{bsdf_at, emitted};
use crate::light::LightSampleContext;
use crate::material::{BxDF, TransportMode, fresnel_complex, fresnel_dielectric, refract};
use crate::math::{Rgb, SampledSpectrum, Vec3};
use crate::ray::Ray;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// Radiance along `ray`:
///
/// L = Le + Σ_lights f(wo, wi) · Li · |cos θi| · V(p, light) + [specular: F·L(reflected) +
/// (1 − F)·L(refracted)], where V is 1 when the shadow ray reaches the light unobstructed.
/// With `lambda` (spectral mode) colours are evaluated at those wavelengths.
pub fn li(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    depth: u32,
    max_depth: u32,
) -> SampledSpectrum {
    let Some(hit) = scene.intersect(ray) else {
        return scene
            .infinite_lights()
            .iter()
            .map(|&i| scene.environment_radiance(i as usize, lambda, ray.d))
            .sum();
    };
    let si = &hit.si;
    let wo = si.wo;
    let mut l = emitted(scene, &hit, wo, lambda);
    let Some((bsdf, disperses)) = bsdf_at(scene, &hit, lambda) else {
        // No surface (interface material): continue the ray.
        return l + li(
            scene,
            &si.spawn_ray(ray.d),
            sampler,
            lambda,
            depth,
            max_depth,
        );
    };
    // A dispersive surface: the path keeps only its hero wavelength from here on (see
    // [`crate::spectrum::hero`]); the hit is traced again with terminated wavelengths, once.
    if let Some(lam) = lambda.filter(|l| disperses && !l.secondary_terminated()) {
        let mut hero = *lam;
        hero.terminate_secondary();
        return li(scene, ray, sampler, Some(&hero), depth, max_depth) * HERO_ONLY;
    }
    let ctx = LightSampleContext {
        p: si.p,
        n: si.n,
        ns: si.shading.n,
    };
    if bsdf.flags().is_non_specular() {
        for (i, light) in scene.lights().iter().enumerate() {
            let u = sampler.get_2d();
            let Some(ls) = scene.sample_li(light, &ctx, u) else {
                continue;
            };
            if ls.pdf == 0.0 || ls.l == Rgb::ZERO {
                continue;
            }
            let f = bsdf.f(wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(si.shading.n).abs();
            if f == SampledSpectrum::ZERO {
                continue;
            }
            // The shadow ray: is the segment from the point to the light free?
            if !scene.intersect_p(&si.spawn_ray_to(ls.p_light)) {
                l += f * scene.light_radiance(i, lambda, ls.l, ls.factor, ls.wi) / ls.pdf;
            }
        }
    }
    if depth + 1 < max_depth {
        let n = bsdf.frame.z;
        let wo_l = bsdf.frame.to_local(wo);
        let reflect = |w: Vec3| -w + 2.0 * w.dot(n) * n;
        match bsdf.bxdf {
            // The course's recursion follows perfect mirrors and refractions only; rough
            // interfaces are lit directly above and nothing more.
            BxDF::Conductor(c) if c.distrib.effectively_smooth() => {
                let f = fresnel_complex(wo_l.z.abs(), c.eta, c.k);
                l += f * li(
                    scene,
                    &si.spawn_ray(reflect(wo)),
                    sampler,
                    lambda,
                    depth + 1,
                    max_depth,
                );
            }
            BxDF::Dielectric(d) if d.distrib.effectively_smooth() => {
                let eta = d.eta;
                let r = fresnel_dielectric(wo_l.z, eta);
                if r > 0.0 {
                    l += r * li(
                        scene,
                        &si.spawn_ray(reflect(wo)),
                        sampler,
                        lambda,
                        depth + 1,
                        max_depth,
                    );
                }
                if let Some((wt, etap)) = refract(wo, n, eta) {
                    // Radiance entering a denser medium is compressed: scale by 1/η².
                    let t = (1.0 - r) / (etap * etap);
                    l += t * li(
                        scene,
                        &si.spawn_ray(wt),
                        sampler,
                        lambda,
                        depth + 1,
                        max_depth,
                    );
                }
            }
            _ => {}
        }
    }
    l
}
