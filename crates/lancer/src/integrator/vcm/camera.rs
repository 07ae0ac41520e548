//! The camera subpath of a `vcm` pixel sample and every strategy it completes: emission hit
//! (s = 0), next-event estimation (s = 1), connections to the light subpath of its pixel
//! (s ≥ 2) and merges with the iteration's light vertices, each weighted by the balance
//! heuristic from the subpaths' running sums ([`Mis`]).

use super::super::emission::{light_normal, reached_from_infinity};
use super::super::{bsdf_at, emitted, keep_hero_only};
use super::grid::MergeGrid;
use super::{
    Iteration, LightVertex, Mis, from_infinity, hero_weight, light_densities, scatter, survives,
};
use crate::light::{LightSampleContext, LightType};
use crate::material::{Bsdf, TransportMode};
use crate::math::{SampledSpectrum, Vec3, normalize};
use crate::ray::Ray;
use crate::sampling::SampleSource;
use crate::shape::SurfaceInteraction;

/// The light vertices of an iteration, hashed for merging.
#[derive(Clone, Copy)]
pub struct Merging<'a> {
    /// Every stored light vertex of the iteration.
    pub vertices: &'a [LightVertex],
    /// Their grid for the iteration's radius; `None` when there is none.
    pub grid: Option<&'a MergeGrid>,
}

/// What the camera subpath knows at a non-specular vertex.
struct At<'a> {
    si: &'a SurfaceInteraction,
    bsdf: &'a Bsdf,
    wo: Vec3,
    beta: SampledSpectrum,
    mis: Mis,
    length: u32,
    hero_only: bool,
    lambda: Option<&'a crate::spectrum::sampled::SampledWavelengths>,
}

/// Radiance of the camera sample whose ray is `ray` in iteration `it`: its camera subpath
/// (drawing from `u`) and the strategies at each of its vertices, with `light_path` the
/// stored vertices of its own pixel's light subpath (in order along it) and `merging` the
/// iteration's vertices for merges. Counts the merges into `merges`.
pub fn camera_path<S: SampleSource + ?Sized>(
    it: &Iteration<'_>,
    ray: &Ray,
    u: &mut S,
    light_path: &[LightVertex],
    merging: Merging<'_>,
    merges: &mut u64,
) -> SampledSpectrum {
    let scene = it.scene;
    let mut lambda = it.lambda;
    let mut l = SampledSpectrum::ZERO;
    let (_, pdf_cam) = scene.camera().pdf_we(ray.o, normalize(ray.d));
    // dVCM = N / p_cam per pixel = 1/(k·p_cam) (p_cam per unit solid angle over the image).
    let mut mis = Mis {
        vcm: if pdf_cam > 0.0 {
            1.0 / (it.splat_scale * pdf_cam)
        } else {
            0.0
        },
        vc: 0.0,
        vm: 0.0,
    };
    let mut beta = SampledSpectrum::ONE;
    let mut eta_scale = 1.0f32;
    let mut hero_only = false;
    let mut ray = *ray;
    let mut from = ray.o;
    let mut length = 1u32;
    loop {
        let Some(hit) = scene.intersect(&ray) else {
            l += beta
                * environment(it, lambda.as_ref(), from, ray.d, &mis, length)
                * hero_weight(hero_only);
            break;
        };
        let si = &hit.si;
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, lambda.as_ref()) else {
            ray = si.spawn_ray(ray.d);
            continue;
        };
        hero_only |= keep_hero_only(&mut lambda, disperses);
        let wo = si.wo;
        mis.arrive((si.p - from).length_squared(), si.shading.n.dot(wo), false);
        let le = emitted(scene, &hit, wo, lambda.as_ref());
        if le != SampledSpectrum::ZERO {
            // s = 0: 1/(1 + p_direct·dVCM + p_emit·dVC) against the strategies that
            // sampled the light's point (directly seen: the only strategy, 1).
            let w = match scene.prim(hit.prim).emission {
                Some(e) if length > 1 => {
                    let i = e.light as usize;
                    let pick = scene.light_distribution().pmf(i);
                    let (direct, emission) = light_densities(scene, i, pick, si.p, si.n, wo);
                    1.0 / (1.0 + direct * mis.vcm + emission * mis.vc)
                }
                _ => 1.0,
            };
            l += beta * le * w * hero_weight(hero_only);
        }
        if length >= it.max_length {
            break;
        }
        if bsdf.flags().is_non_specular() {
            let at = At {
                si,
                bsdf: &bsdf,
                wo,
                beta,
                mis,
                length,
                hero_only,
                lambda: lambda.as_ref(),
            };
            l += next_event(it, &at, u);
            for v in light_path {
                if v.length + length + 1 > it.max_length {
                    break;
                }
                l += connect(it, &at, v);
            }
            l += merge(it, &at, merging, merges);
        }
        let Some((bs, cos_out)) = scatter(
            &bsdf,
            wo,
            si.shading.n,
            u,
            TransportMode::Radiance,
            &mut mis,
            it.eta,
        ) else {
            break;
        };
        beta *= bs.f * (cos_out / bs.pdf);
        if bs.is_transmission() {
            eta_scale *= bs.eta * bs.eta;
        }
        // Russian roulette as the path tracer's.
        if length > super::super::RR_AFTER_DEPTH
            && !survives(u, (beta * eta_scale).max_element(), &mut beta)
        {
            break;
        }
        if beta == SampledSpectrum::ZERO || !beta.is_finite() {
            break;
        }
        ray = si.spawn_ray(bs.wi);
        from = si.p;
        length += 1;
    }
    l
}

/// The environment seen along `d` from `from` by a camera subpath of `length` segments, each
/// light's radiance weighted against the strategies that sample it (s = 0 as
/// [`camera_path`]'s emission hits; those of light subpaths only where their rays reach
/// `from`).
fn environment(
    it: &Iteration<'_>,
    lambda: Option<&crate::spectrum::sampled::SampledWavelengths>,
    from: Vec3,
    d: Vec3,
    mis: &Mis,
    length: u32,
) -> SampledSpectrum {
    let scene = it.scene;
    let mut l = SampledSpectrum::ZERO;
    for &i in scene.infinite_lights() {
        let i = i as usize;
        let le = scene.environment_radiance(i, lambda, d);
        if le == SampledSpectrum::ZERO {
            continue;
        }
        let w = if length > 1 {
            let pick = scene.light_distribution().pmf(i);
            let w_out = -normalize(d);
            let (direct, mut emission) =
                light_densities(scene, i, pick, Vec3::ZERO, Vec3::ZERO, w_out);
            if !reached_from_infinity(scene, from, w_out) {
                emission = 0.0;
            }
            1.0 / (1.0 + direct * mis.vcm + emission * mis.vc)
        } else {
            1.0
        };
        l += le * w;
    }
    l
}

/// Next-event estimation at `at` (s = 1): a light chosen by power, a point on it by its
/// `sample_li`, weighted by 1/(w_light + 1 + w_camera) with w_light = p_bsdf/p_direct (0
/// for a delta light) and w_camera = p_emit·|cos θ_x|/(p_direct·|cos θ_light|) ·
/// (η + dVCM + dVC·p⃖_bsdf).
fn next_event<S: SampleSource + ?Sized>(
    it: &Iteration<'_>,
    at: &At<'_>,
    u: &mut S,
) -> SampledSpectrum {
    let scene = it.scene;
    let si = at.si;
    let Some((i, pick)) = scene.light_distribution().sample(u.get_1d()) else {
        return SampledSpectrum::ZERO;
    };
    let ctx = LightSampleContext::at(si);
    let u2 = u.get_2d();
    let light = &scene.lights()[i];
    let Some(ls) = light
        .sample_li(&ctx, u2, scene.shapes(), scene.meshes())
        .filter(|ls| ls.pdf > 0.0)
    else {
        return SampledSpectrum::ZERO;
    };
    let f = at.bsdf.f(at.wo, ls.wi, TransportMode::Radiance);
    let cos_x = ls.wi.dot(si.shading.n).abs();
    if f == SampledSpectrum::ZERO || cos_x == 0.0 || pick == 0.0 {
        return SampledSpectrum::ZERO;
    }
    let le = scene.light_radiance(i, at.lambda, ls.l, ls.factor, ls.wi);
    if le == SampledSpectrum::ZERO {
        return SampledSpectrum::ZERO;
    }
    let kind = light.light_type();
    // The light point's normal and cosine, and the d² that turns its density per area into
    // one per solid angle here (none for lights at infinity).
    let (n_light, cos_light, dist2) = match kind {
        LightType::Area => {
            let n = light_normal(scene, i, ls.p_light, (si.p, si.p_error, si.n));
            (n, n.dot(ls.wi).abs(), (ls.p_light - si.p).length_squared())
        }
        LightType::DeltaPosition => (Vec3::ZERO, 1.0, (ls.p_light - si.p).length_squared()),
        LightType::Infinite | LightType::DeltaDirection => (Vec3::ZERO, 1.0, 1.0),
    };
    if cos_light == 0.0 {
        return SampledSpectrum::ZERO;
    }
    let (direct_a, mut emission) = light_densities(scene, i, pick, ls.p_light, n_light, -ls.wi);
    // Light subpaths from infinity never reach a point beyond the scene's disk (lancer's
    // infinite planes): no strategy of theirs to weigh against.
    if from_infinity(kind) && !reached_from_infinity(scene, si.p, ls.wi) {
        emission = 0.0;
    }
    let direct = direct_a * dist2 / cos_light;
    let pdf_fwd = if kind.is_delta() {
        0.0
    } else {
        at.bsdf.pdf(at.wo, ls.wi, TransportMode::Radiance)
    };
    let pdf_rev = at.bsdf.pdf(ls.wi, at.wo, TransportMode::Importance);
    let w_light = pdf_fwd / direct;
    let w_camera =
        emission * cos_x / (direct * cos_light) * (it.eta + at.mis.vcm + at.mis.vc * pdf_rev);
    let weight = 1.0 / (w_light + 1.0 + w_camera);
    let c = at.beta * f * le * (weight * cos_x / (pick * ls.pdf));
    if c == SampledSpectrum::ZERO || !c.is_finite() || !weight.is_finite() {
        return SampledSpectrum::ZERO;
    }
    let ray = Ray::spawn_to(si.p, si.p_error, si.n, ls.p_light);
    if scene.intersect_p(&ray) {
        return SampledSpectrum::ZERO;
    }
    c * hero_weight(at.hero_only)
}

/// The connection of `at` to light vertex `v`: β_c·f_c·G·f_l·β_l, weighted by
/// 1/(w_light + 1 + w_camera), w_light = p⃗_c→l · (η + dVCM_l + dVC_l·p⃖_l) and w_camera =
/// p⃗_l→c · (η + dVCM_c + dVC_c·p⃖_c) (the p⃗ turned into densities per area at the other
/// end).
fn connect(it: &Iteration<'_>, at: &At<'_>, v: &LightVertex) -> SampledSpectrum {
    crate::counters::count_connection();
    let si = at.si;
    let d = v.p - si.p;
    let dist2 = d.length_squared();
    if dist2 == 0.0 {
        return SampledSpectrum::ZERO;
    }
    let w = d / dist2.sqrt();
    let f_c = at.bsdf.f(at.wo, w, TransportMode::Radiance);
    let f_l = v.bsdf.f(v.wo, -w, TransportMode::Importance);
    let (cos_c, cos_l) = (w.dot(si.shading.n).abs(), w.dot(v.ns).abs());
    let g = cos_c * cos_l / dist2;
    let c = at.beta * f_c * f_l * v.beta * g;
    if c == SampledSpectrum::ZERO || !c.is_finite() {
        return SampledSpectrum::ZERO;
    }
    let p_cl = at.bsdf.pdf(at.wo, w, TransportMode::Radiance) * cos_l / dist2;
    let p_lc = v.bsdf.pdf(v.wo, -w, TransportMode::Importance) * cos_c / dist2;
    let rev_c = at.bsdf.pdf(w, at.wo, TransportMode::Importance);
    let rev_l = v.bsdf.pdf(-w, v.wo, TransportMode::Radiance);
    let w_light = p_cl * (it.eta + v.mis.vcm + v.mis.vc * rev_l);
    let w_camera = p_lc * (it.eta + at.mis.vcm + at.mis.vc * rev_c);
    let weight = 1.0 / (w_light + 1.0 + w_camera);
    let ray = Ray::spawn_to(si.p, si.p_error, si.n, v.p);
    if it.scene.intersect_p(&ray) {
        return SampledSpectrum::ZERO;
    }
    c * weight * hero_weight(at.hero_only || v.hero_only)
}

/// Merges at `at` with the light vertices within the radius: β_c · Σ f_c(wo, wᵢ)·β_l /
/// (π r² N), each weighted by 1/(w_light + 1 + w_camera), w_light = dVCM_l/η + dVM_l·p⃗_c and
/// w_camera = dVCM_c/η + dVM_c·p⃖_c (p⃗_c the camera BSDF's density of the light vertex's
/// incoming direction, p⃖_c that of the reverse).
fn merge(
    it: &Iteration<'_>,
    at: &At<'_>,
    merging: Merging<'_>,
    merges: &mut u64,
) -> SampledSpectrum {
    let Some(grid) = merging.grid else {
        return SampledSpectrum::ZERO;
    };
    let p = at.si.p;
    let mut sum = SampledSpectrum::ZERO;
    grid.for_each_near(p, |i| {
        let v = &merging.vertices[i as usize];
        if v.length + at.length > it.max_length {
            return;
        }
        let f = at.bsdf.f(at.wo, v.wo, TransportMode::Radiance);
        if f == SampledSpectrum::ZERO {
            return;
        }
        *merges += 1;
        let p_fwd = at.bsdf.pdf(at.wo, v.wo, TransportMode::Radiance);
        let p_rev = at.bsdf.pdf(v.wo, at.wo, TransportMode::Importance);
        let w_light = v.mis.vcm / it.eta + v.mis.vm * p_fwd;
        let w_camera = at.mis.vcm / it.eta + at.mis.vm * p_rev;
        let weight = 1.0 / (w_light + 1.0 + w_camera);
        let c = f * v.beta * weight * hero_weight(v.hero_only || at.hero_only);
        if c.is_finite() {
            sum += c;
        }
    });
    at.beta * sum * it.merge_norm()
}
