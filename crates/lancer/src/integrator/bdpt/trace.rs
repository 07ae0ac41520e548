//! Light tracing through participating media (pbrt-v4's `lightpath`, which itself ignores
//! media): the light subpath of [`super::walk`] (delta tracking, medium vertices) and each of
//! its vertices joined to the lens by bdpt's t = 1 join ([`super::connect::to_camera`]),
//! unweighted: with one strategy there is nothing to weigh it against. The light's own
//! surface seen directly is splatted as `lightpath` does, attenuated by the transmittance to
//! the lens.

use super::super::Splat;
use super::connect::{Segment, to_camera};
use super::vertex::{Vertex, lane_balance};
use super::walk::{PATHS, Walk};
use crate::math::SampledSpectrum;
use crate::ray::Ray;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::sampled::SampledWavelengths;

/// Traces one light path of at most `max_depth` bounces through the scene's media, splatting
/// what each vertex sends to the camera; `ray` (the camera ray) only chooses the hero lane in
/// RGB mode. Returns the camera ray's own radiance: zero.
pub fn li(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    splat: Splat<'_>,
) -> SampledSpectrum {
    PATHS.with(|paths| {
        let (_, light) = &mut *paths.borrow_mut();
        let mut walk = Walk::new(scene, ray, lambda, false);
        walk.light_subpath(sampler, max_depth as usize + 1, light);
        let weight = walk.spectral_weight();
        let seg = Segment {
            scene,
            lambda: walk.lambda.as_ref(),
            hero: walk.hero,
        };
        if let Some(v0) = light.first()
            && let Some((p, l)) = seen_directly(seg, v0, sampler)
        {
            splat(p, l * weight);
        }
        for qs in light.iter().skip(1) {
            if let Some((_, p, l)) = to_camera(seg, qs, sampler)
                && l != SampledSpectrum::ZERO
            {
                splat(p, lane_balance(l, qs.r) * weight);
            }
        }
        SampledSpectrum::ZERO
    })
}

/// The light subpath's first vertex, on an area light's surface, seen from a point sampled on
/// the lens: Le·We·|cos θ_light|·Tr / (p_l·p_pos·p_c) (p_l·p_pos is the vertex's forward
/// density, Le its β) times the splat scale, and where it lands; `None` for lights without a
/// surface, or the side an one-sided light does not emit from.
fn seen_directly(
    seg: Segment<'_>,
    v0: &Vertex,
    sampler: &mut Sampler,
) -> Option<(crate::math::Vec2, SampledSpectrum)> {
    let scene = seg.scene;
    if !v0.is_on_surface() {
        return None;
    }
    let super::vertex::Kind::Light(i) = v0.kind else {
        return None;
    };
    crate::counters::count_connection();
    let camera = scene.camera();
    let cs = camera.sample_wi(v0.p, sampler.get_2d())?;
    let cos = v0.ng.dot(cs.wi);
    let two_sided = scene.lights()[i as usize]
        .as_area()
        .is_some_and(|a| a.two_sided);
    if !(cos > 0.0 || two_sided) {
        return None;
    }
    let mut lens = Vertex::endpoint(
        super::vertex::Kind::Camera,
        cs.p_lens,
        crate::math::Vec3::ZERO,
        cs.n_lens,
        SampledSpectrum::ONE,
    );
    lens.medium = scene.camera_medium();
    let tr = seg.tr(v0, &lens);
    if tr == SampledSpectrum::ZERO {
        return None;
    }
    let l = v0.beta * tr * (cs.wi_importance * cos.abs() / (v0.pdf_fwd * cs.pdf));
    Some((cs.p_raster, l * camera.splat_scale()))
}
