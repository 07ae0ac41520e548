//! pbrt-v4's teaching integrators: `randomwalk` (directions uniform over the sphere, no light
//! sampling), `simplepath` (a path tracer without MIS: light sampling or BSDF sampling, each
//! optional) and `simplevolpath` (delta tracking through media, no light sampling). All are
//! unbiased and slow; they are here to check the others against.

use super::emission::environment;
use super::volpath::{Collision, collision, hero_lane, medium_after, seeded_rng};
use super::whitted::light_sample;
use super::{bsdf_at, emitted, keep_hero_only};
use crate::material::TransportMode;
use crate::math::{SampledSpectrum, Vec2, normalize};
use crate::medium::sample_t_maj;
use crate::ray::Ray;
use crate::sampling::{
    Sampler, sample_uniform_hemisphere, sample_uniform_sphere, uniform_hemisphere_pdf,
    uniform_sphere_pdf,
};
use crate::scene::Scene;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// pbrt-v4's `randomwalk`: at each surface a direction uniform over the sphere, weighted by
/// f·|cos θ|·4π; emission is counted where the walk meets it. L = Le + f·|cos|·L_next / (1/4π).
pub fn random_walk(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
) -> SampledSpectrum {
    let mut wavelengths = lambda.copied();
    let (mut l, mut beta) = (SampledSpectrum::ZERO, SampledSpectrum::ONE);
    let mut ray = *ray;
    let mut depth = 0;
    loop {
        let Some(hit) = scene.intersect(&ray) else {
            l += beta * environment(scene, ray.d, wavelengths.as_ref());
            break;
        };
        let si = &hit.si;
        l += beta * emitted(scene, &hit, si.wo, wavelengths.as_ref());
        if depth == max_depth {
            break;
        }
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, wavelengths.as_ref()) else {
            break;
        };
        if keep_hero_only(&mut wavelengths, disperses) {
            l *= HERO_ONLY;
            beta *= HERO_ONLY;
        }
        let wi = sample_uniform_sphere(sampler.get_2d());
        let fcos = bsdf.f(si.wo, wi, TransportMode::Radiance) * wi.dot(si.shading.n).abs();
        if fcos == SampledSpectrum::ZERO {
            break;
        }
        beta *= fcos / uniform_sphere_pdf();
        ray = si.spawn_ray(wi);
        depth += 1;
    }
    l
}

/// pbrt-v4's `simplepath`: with `sample_lights`, one light chosen uniformly and sampled at
/// each surface (emission met by the path then counts only after specular bounces); with
/// `sample_bsdf` the path goes on by BSDF sampling, else by directions uniform over the
/// hemisphere (the sphere for a BSDF that both reflects and transmits).
pub fn simple_path(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    sample_lights: bool,
    sample_bsdf: bool,
) -> SampledSpectrum {
    let mut wavelengths = lambda.copied();
    let (mut l, mut beta) = (SampledSpectrum::ZERO, SampledSpectrum::ONE);
    let mut ray = *ray;
    let mut depth = 0;
    let mut specular_bounce = true;
    let n_lights = scene.lights().len();
    loop {
        let Some(hit) = scene.intersect(&ray) else {
            if !sample_lights || specular_bounce {
                l += beta * environment(scene, ray.d, wavelengths.as_ref());
            }
            break;
        };
        let si = &hit.si;
        if !sample_lights || specular_bounce {
            l += beta * emitted(scene, &hit, si.wo, wavelengths.as_ref());
        }
        if depth == max_depth {
            break;
        }
        depth += 1;
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, wavelengths.as_ref()) else {
            specular_bounce = true;
            ray = si.spawn_ray(ray.d);
            continue;
        };
        if keep_hero_only(&mut wavelengths, disperses) {
            l *= HERO_ONLY;
            beta *= HERO_ONLY;
        }
        let wo = si.wo;
        if sample_lights && n_lights > 0 {
            // A light chosen uniformly (p = 1/n), a point on it: L += β·f·|cos|·Li / (p·pdf).
            let ul = sampler.get_1d();
            let i = ((ul * n_lights as f32) as usize).min(n_lights - 1);
            let u = sampler.get_2d();
            l +=
                beta * light_sample(scene, si, &bsdf, i, u, wavelengths.as_ref()) * n_lights as f32;
        }
        if sample_bsdf {
            let uc = sampler.get_1d();
            let Some(bs) = bsdf.sample_f(wo, uc, sampler.get_2d(), TransportMode::Radiance) else {
                break;
            };
            beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
            specular_bounce = bs.is_specular();
            ray = si.spawn_ray(bs.wi);
        } else {
            let flags = bsdf.flags();
            let u = sampler.get_2d();
            let (wi, pdf) = if flags.is_reflection() && flags.is_transmission() {
                (sample_uniform_sphere(u), uniform_sphere_pdf())
            } else {
                // The hemisphere on the side the BSDF scatters to.
                let local = sample_uniform_hemisphere(u);
                let mut wi = crate::math::Frame::from_z(si.n).from_local(local);
                let same_side = wo.dot(si.n) * wi.dot(si.n) > 0.0;
                if (flags.is_reflection() && !same_side) || (flags.is_transmission() && same_side) {
                    wi = -wi;
                }
                (wi, uniform_hemisphere_pdf())
            };
            beta *= bsdf.f(wo, wi, TransportMode::Radiance) * (wi.dot(si.shading.n).abs() / pdf);
            specular_bounce = false;
            ray = si.spawn_ray(wi);
        }
        if !beta.is_finite() || beta == SampledSpectrum::ZERO {
            break;
        }
    }
    l
}

/// pbrt-v4's `simplevolpath`: one wavelength (spectral mode's hero λ₀, the others terminated;
/// in RGB mode one lane chosen per camera ray), carried by delta tracking through media at that
/// wavelength's coefficients. At each tentative collision, with probabilities σ_a/σ_maj,
/// σ_s/σ_maj and the rest: absorption ends the path and adds the medium's emission, L += β·Le;
/// scattering (at most `max_depth` times) samples the phase function, β ← β·p/pdf (= β); a
/// null collision goes on. Emission is added where the walk meets an emitter or leaves the
/// scene. Surfaces only pass rays between media (`interface`): a surface that scatters ends
/// the path (pbrt-v4 stops with an error there). The lane's radiance is returned times 4 in
/// its lane, 0 in the others (an unbiased estimate of every lane's, as [`HERO_ONLY`]).
pub fn simple_vol_path(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
) -> SampledSpectrum {
    let h = hero_lane(ray, lambda);
    let wavelengths = lambda.map(|w| {
        let mut w = *w;
        w.terminate_secondary();
        w
    });
    let lambda = wavelengths.as_ref();
    let (mut l, mut beta) = (0.0f32, 1.0f32);
    let mut depth = 0;
    let mut ray = *ray;
    let mut medium = scene.camera_medium();
    loop {
        let hit = scene.intersect(&ray);
        let (mut scattered, mut terminated) = (None, false);
        if let Some(m) = medium {
            let mut rng = seeded_rng(sampler.get_1d(), sampler.get_1d());
            let t_max = hit.as_ref().map_or(f32::INFINITY, |h| h.si.t);
            let u = sampler.get_1d();
            let mut u_mode = sampler.get_1d();
            let wo = -normalize(ray.d);
            sample_t_maj(
                scene.medium(m),
                ray.o,
                ray.d,
                t_max,
                u,
                &mut rng,
                lambda,
                h,
                |p, mp, sigma_maj, _, rng| match collision(mp, sigma_maj, h, u_mode) {
                    Collision::Absorb => {
                        l += beta * mp.le[h];
                        terminated = true;
                        false
                    }
                    Collision::Scatter => {
                        if depth >= max_depth {
                            terminated = true;
                            return false;
                        }
                        depth += 1;
                        let u = Vec2::new(rng.uniform(), rng.uniform());
                        match mp.phase.sample(wo, u) {
                            Some(ps) => {
                                beta *= ps.p / ps.pdf;
                                scattered = Some(Ray::new(p, ps.wi).at_time(ray.time));
                            }
                            None => terminated = true,
                        }
                        false
                    }
                    Collision::Null => {
                        u_mode = rng.uniform();
                        true
                    }
                },
            );
        }
        if terminated {
            break;
        }
        if let Some(next) = scattered {
            ray = next;
            continue;
        }
        let Some(hit) = hit else {
            l += beta * environment(scene, ray.d, lambda)[h];
            break;
        };
        let si = &hit.si;
        l += beta * emitted(scene, &hit, si.wo, lambda)[h];
        if bsdf_at(scene, &hit, lambda).is_some() {
            break;
        }
        medium = medium_after(scene, &hit, ray.d, medium);
        ray = si.spawn_ray(ray.d);
    }
    let mut out = SampledSpectrum::ZERO;
    out[h] = HERO_ONLY[0] * l;
    out
}
