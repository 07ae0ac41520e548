//! Light tracing (pbrt-v4's `lightpath`): paths start at the lights and every vertex they
//! reach is connected to the camera, its contribution splatted where it lands on the film.
//! The camera's own ray brings nothing back.
//!
//! One light path per camera sample: a light chosen in proportion to its power (p_l), a ray
//! leaving it (densities p_pos, p_dir), so that the path carries
//! β = Le·|cos θ₀| / (p_l·p_pos·p_dir) and, after each bounce, β·f·|cos θ|/p. At a vertex x
//! with the lens point sampled for it (density p_c per solid angle at x, importance We), the
//! film receives β·f(x, towards the lens)·|cos θ_x|·We/p_c.

use super::{Splat, bsdf_at, keep_hero_only};
use crate::material::{Bsdf, TransportMode};
use crate::math::{SampledSpectrum, Vec2, Vec3};
use crate::ray::Ray;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::shape::SurfaceInteraction;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// Traces one light path of at most `max_depth` bounces, splatting what each vertex sends to
/// the camera into `splat`; returns the (zero) radiance of the camera ray. A scene with media
/// is traced by [`super::bdpt::light_trace`] (delta tracking, transmittance to the lens),
/// which `ray` gives its hero lane.
pub fn li(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    splat: Splat<'_>,
) -> SampledSpectrum {
    if !scene.media().is_empty() {
        return super::bdpt::light_trace(scene, ray, sampler, lambda, max_depth, splat);
    }
    let camera = &scene.camera();
    let scale = camera.splat_scale();
    let mut wavelengths = lambda.copied();
    let Some((light, p_l)) = scene.light_distribution().sample(sampler.get_1d()) else {
        return SampledSpectrum::ZERO;
    };
    let (u1, u2) = (sampler.get_2d(), sampler.get_2d());
    let emitter = &scene.lights()[light];
    let Some(les) = emitter.sample_le(u1, u2, scene.shapes(), scene.meshes()) else {
        return SampledSpectrum::ZERO;
    };
    crate::counters::count_light_path();
    let le = scene.light_radiance(light, wavelengths.as_ref(), les.l, les.factor, -les.w);
    // The light's own surface, seen directly: Le·We·|cos θ_light| / (p_l·p_pos·p_c), with
    // p_pos = 1/A the density of the point on the light.
    if les.n != Vec3::ZERO {
        crate::counters::count_connection();
        if let Some(cs) = camera.sample_wi(les.p, sampler.get_2d()) {
            let cos = les.n.dot(cs.wi);
            let two_sided = emitter.as_area().is_some_and(|a| a.two_sided);
            if (cos > 0.0 || two_sided)
                && !scene.intersect_p(&Ray::spawn_to(les.p, les.p_error, les.n, cs.p_lens))
            {
                let l = le * (cs.wi_importance * cos.abs() / (p_l * les.pdf_pos * cs.pdf));
                splat(cs.p_raster, l * scale);
            }
        }
    }
    let mut beta = le * (les.abs_cos() / (p_l * les.pdf_pos * les.pdf_dir));
    let mut ray = les.ray();
    let mut depth = 0;
    while let Some(hit) = scene.intersect(&ray) {
        let si = &hit.si;
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, wavelengths.as_ref()) else {
            // An interface between media: the ray goes on.
            ray = si.spawn_ray(ray.d);
            continue;
        };
        if keep_hero_only(&mut wavelengths, disperses) {
            beta *= HERO_ONLY;
        }
        if depth == max_depth {
            break;
        }
        depth += 1;
        to_camera(scene, si, &bsdf, beta, sampler.get_2d(), splat);
        let uc = sampler.get_1d();
        let Some(bs) = bsdf.sample_f(si.wo, uc, sampler.get_2d(), TransportMode::Importance) else {
            break;
        };
        beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
        if !beta.is_finite() || beta == SampledSpectrum::ZERO {
            break;
        }
        ray = si.spawn_ray(bs.wi);
    }
    SampledSpectrum::ZERO
}

/// Joins surface point `si` (BSDF `bsdf`), reached by a light path carrying `beta`, to a lens
/// point sampled from `u`: unless the lens is hidden, splats β·f·|cos θ|·We/p_c (times the
/// camera's splat scale) where the ray lands.
pub(crate) fn to_camera(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    beta: SampledSpectrum,
    u: Vec2,
    splat: Splat<'_>,
) {
    crate::counters::count_connection();
    let camera = scene.camera();
    if let Some(cs) = camera.sample_wi(si.p, u) {
        let f = bsdf.f(si.wo, cs.wi, TransportMode::Importance);
        let l = beta * f * (cs.wi.dot(si.shading.n).abs() * cs.wi_importance / cs.pdf);
        if l != SampledSpectrum::ZERO && !scene.intersect_p(&si.spawn_ray_to(cs.p_lens)) {
            splat(cs.p_raster, l * camera.splat_scale());
        }
    }
}
