//! The course's ray tracer (Whitted 1980): what is visible, how the lights light it, shadows,
//! and perfect mirror reflection and refraction.

use super::emission::environment;
use super::{bsdf_at, emitted};
use crate::light::LightSampleContext;
use crate::material::{Bsdf, BxDF, TransportMode, fresnel_complex, fresnel_dielectric, refract};
use crate::math::{Rgb, SampledSpectrum, Vec2, Vec3};
use crate::ray::Ray;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::shape::SurfaceInteraction;
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
        return environment(scene, ray.d, lambda);
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
    if bsdf.flags().is_non_specular() {
        for i in 0..scene.lights().len() {
            l += light_sample(scene, si, &bsdf, i, sampler.get_2d(), lambda);
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

/// Light from light `i` that the surface `si` (BSDF `bsdf`) reflects towards `si.wo`, by one
/// sample `u` of the light and without MIS: f(wo, wi)·Li·|cos θi| / p, zero when the shadow
/// ray from the point to the light is blocked. Whitted's shading of every light, and
/// `simplepath`'s of one light chosen at random.
pub(super) fn light_sample(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    i: usize,
    u: Vec2,
    lambda: Option<&SampledWavelengths>,
) -> SampledSpectrum {
    let ctx = LightSampleContext::at(si);
    let Some(ls) = scene.sample_li(&scene.lights()[i], &ctx, u) else {
        return SampledSpectrum::ZERO;
    };
    if ls.pdf == 0.0 || ls.l == Rgb::ZERO {
        return SampledSpectrum::ZERO;
    }
    let f = bsdf.f(si.wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(si.shading.n).abs();
    if f == SampledSpectrum::ZERO || scene.intersect_p(&si.spawn_ray_to(ls.p_light)) {
        return SampledSpectrum::ZERO;
    }
    f * scene.light_radiance(i, lambda, ls.l, ls.factor, ls.wi) / ls.pdf
}
