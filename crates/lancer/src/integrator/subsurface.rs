//! The subsurface step of path tracing (pbrt-v4's `VolPathIntegrator` after a BSDF sample
//! refracts into a `subsurface` material): instead of following the ray inside, a BSSRDF
//! ([`TabulatedBssrdf`]) picks where the light leaves.
//!
//! 1. A probe segment through the object from the profile of one lane chosen at random
//!    (uniformly of the four; the density used is the average of the lanes' densities, a
//!    one-sample mixture, so every lane's estimate stays unbiased — pbrt-v4 samples with the
//!    hero wavelength and reweights with its spectral MIS, which amounts to the same).
//! 2. Every surface of the same material along the segment is a candidate exit; one is kept
//!    by reservoir sampling (probability 1/n).
//! 3. The throughput takes S_p / (pdf / n); the exit lobe ([`NormalizedFresnelBxdf`]) is lit by
//!    next-event estimation and sampled for the path's next direction (the depth does not
//!    grow, as in pbrt-v4).

use super::direct_light;
use crate::light::LightSampleContext;
use crate::material::{Bsdf, BxDF, NormalizedFresnelBxdf, TransportMode};
use crate::math::{SampledSpectrum, Vec3};
use crate::ray::Ray;
use crate::sampling::{Sampler, hash_u64, u32_to_unit_f32};
use crate::scene::{Scene, SceneHit};
use crate::spectrum::sampled::SampledWavelengths;

/// Most surfaces a probe segment is followed through (a bound against pathological scenes).
const MAX_PROBE_HITS: u32 = 256;

/// What the subsurface step did.
pub(super) enum Exit {
    /// The material has no BSSRDF: the path goes on as it was.
    NotSubsurface,
    /// No exit point or no exit direction: the path ends.
    Lost,
    /// The light left at an exit point: the path goes on along `ray`.
    Left {
        /// The ray leaving the exit point.
        ray: Ray,
        /// The density of its direction (for MIS at the next emitter).
        p_b: f32,
        /// The exit point, for that MIS.
        ctx: LightSampleContext,
    },
}

/// The subsurface step at `hit` after a transmission was sampled there: updates `beta` and
/// adds the exit point's direct light to `l`.
pub(super) fn exit(
    scene: &Scene,
    hit: &SceneHit,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    beta: &mut SampledSpectrum,
    l: &mut SampledSpectrum,
) -> Exit {
    let m = scene.prim(hit.prim).material;
    let material = scene.material(m);
    let tex = scene.textures();
    let tc = Scene::tex_coord_with_footprint(hit);
    let spectral = lambda.map(|lambda| scene.spectral_colours(m, lambda));
    let Some(bssrdf) = material.bssrdf(&tex, &tc, spectral, hit.si.p, hit.si.shading.n) else {
        return Exit::NotSubsurface;
    };
    let u_axis = sampler.get_1d();
    let u_disk = sampler.get_2d();
    let u_lane = sampler.get_1d();
    let u_reservoir = sampler.get_1d();
    let lane = ((u_lane * 4.0) as usize).min(3);
    let Some(seg) = bssrdf.sample_sp(u_axis, u_disk, lane) else {
        return Exit::Lost;
    };
    // Candidates along the segment, one kept uniformly (reservoir of weight 1 each).
    let seed = u_reservoir.to_bits() as u64;
    let mut count = 0u32;
    let mut chosen: Option<SceneHit> = None;
    // The probe, like every ray of the path, at the path's time.
    let mut ray = Ray::spawn_to(seg.p0, Vec3::ZERO, Vec3::ZERO, seg.p1).at_time(hit.si.time);
    for _ in 0..MAX_PROBE_HITS {
        if ray.d == Vec3::ZERO {
            break;
        }
        let Some(h) = scene.intersect(&ray) else {
            break;
        };
        if scene.prim(h.prim).material == m {
            count += 1;
            let u = u32_to_unit_f32(hash_u64(&[seed, count as u64]) as u32);
            if u * count as f32 <= 1.0 {
                chosen = Some(h);
            }
        }
        ray = h.si.spawn_ray_to(seg.p1);
    }
    let Some(pi) = chosen else {
        return Exit::Lost;
    };
    let sp = bssrdf.sp(pi.si.p);
    // The one-sample mixture over the lanes that may have drawn the radius.
    let pdf = bssrdf.pdf_sp(pi.si.p, pi.si.n).element_sum() * 0.25;
    if sp == SampledSpectrum::ZERO || pdf.is_nan() || pdf <= 0.0 {
        return Exit::Lost;
    }
    *beta *= sp * (count as f32 / pdf);
    // The exit lobe, seen from along the shading normal.
    let si = &pi.si;
    let sw = Bsdf::new(
        BxDF::NormalizedFresnel(NormalizedFresnelBxdf { eta: bssrdf.eta }),
        si.shading.n,
        si.shading.dpdu,
    );
    let wo = si.shading.n;
    let ctx = LightSampleContext::at(si);
    *l += *beta * direct_light(scene, &pi.si, &sw, wo, &ctx, sampler, lambda);
    let uc = sampler.get_1d();
    let u = sampler.get_2d();
    let Some(bs) = sw.sample_f(wo, uc, u, TransportMode::Radiance) else {
        return Exit::Lost;
    };
    *beta *= bs.f * bs.wi.dot(si.shading.n).abs() / bs.pdf;
    Exit::Left {
        ray: si.spawn_ray(bs.wi),
        p_b: bs.pdf,
        ctx,
    }
}
