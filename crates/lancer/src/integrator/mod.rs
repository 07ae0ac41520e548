//! Integrators: how much light arrives along a camera ray.

/// Russian roulette starts once a path has made this many bounces (its `depth` exceeds it).
/// pbrt-v4 starts after the first bounce (1), Mitsuba after four. Measured on the Cornell box
/// at 64 spp over three seeds, instructions × relmse (lower is better), spectral / RGB:
/// 1 → 0.0551 / 0.0405, 2 → 0.0544 / 0.0402, 4 → 0.0564 / 0.0414, never → 0.0630 / 0.0470.
/// Starting after the second bounce is the most efficient, and 8–11 % less noisy per sample
/// than pbrt-v4's choice; the images' expectation is unchanged.
///
/// Measured again (seeds 0–4, 64 spp, spectral / RGB), 1 against 2: relmse +8.7 % / +11.3 %,
/// instructions −6.5 % / −9.6 %, so instructions × relmse 1.017 / 1.006 of 2's; and with 1
/// the Cornell box's relmse is 1.22× / 1.34× Mitsuba's (spectral.sh's bar is 1.2×; with 2,
/// 1.11× / 1.20×). On Bitterli's veach-mis (320×180, 64 spp, seeds 1–20) 1 has 5.6 % fewer
/// instructions and a far lower median relmse (0.034 against 0.257) but a higher mean (0.734
/// against 0.333): 13 seeds of 20 are nearly free of fireflies, but the 7 that catch some are
/// far worse (relmse 0.08–6.9; a survivor's weight doubles). 1 would fail the Cornell box
/// noise bar, and the mean relmse favours 2 on both scenes.
pub const RR_AFTER_DEPTH: u32 = 2;

pub mod bdpt;
pub mod caustics;
mod debug;
mod desc;
mod emission;
pub mod lightpath;
pub mod mlt;
mod path;
pub(crate) use path::li_observed;
mod path_spectra;
mod simple;
pub mod specular_differentials;
pub mod sppm;
mod subsurface;
#[cfg(test)]
pub(crate) mod test_scenes;
pub mod vcm;
mod volpath;
mod whitted;

use crate::light::LightSampleContext;
use crate::material::{
    Bsdf, BumpedMaterial, BxDF, DiffuseMaterial, Material, MixMaterial, TransportMode, rgb_colour,
};
use crate::math::{Rgb, SampledSpectrum, Vec3, rgb_lanes};
use crate::ray::Ray;
use crate::sampling::{Sampler, power_heuristic};
use crate::scene::{Scene, SceneHit};
use crate::shape::SurfaceInteraction;
use crate::spectrum::sampled::{ColourKind, SampledWavelengths, albedo_at};
use crate::texture::SpectrumTex;
pub use desc::Integrator;
pub(crate) use emission::emitted;
use path_spectra::PathSpectra;

/// Where light paths put what they bring to the camera: a film point (raster space) and the
/// radiance arriving there, in the lanes the integrator works in (spectral or RGB). The film
/// adds it, filtered, to the pixels around that point.
pub type Splat<'a> = &'a mut dyn FnMut(crate::math::Vec2, SampledSpectrum);

impl Integrator {
    /// [`Integrator::li`], with what light paths bring to other points of the film given to
    /// `splat` (film point in raster space, radiance in the same lanes as the result). For
    /// the integrators that do not splat, the same as `li`.
    pub fn li_splatting(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splat: Splat<'_>,
    ) -> SampledSpectrum {
        match *self {
            Integrator::LightPath { max_depth } => {
                lightpath::li(scene, ray, sampler, lambda, max_depth, splat)
            }
            Integrator::PathCaustics { max_depth, paths } => {
                caustics::li(scene, ray, sampler, lambda, max_depth, paths, splat)
            }
            Integrator::Bdpt {
                max_depth,
                regularize,
                ..
            } => bdpt::li(
                scene,
                ray,
                sampler,
                lambda,
                bdpt::BdptOptions {
                    max_depth,
                    regularize,
                },
                splat,
                None,
            ),
            // Outside its chains (which `crate::render` runs over a whole film), mlt's
            // estimate for one camera ray is the bdpt estimate it samples from.
            Integrator::Mlt(o) => bdpt::li(
                scene,
                ray,
                sampler,
                lambda,
                bdpt::BdptOptions {
                    max_depth: o.max_depth,
                    regularize: o.regularize,
                },
                splat,
                None,
            ),
            _ => self.li(scene, ray, sampler, lambda),
        }
    }

    /// [`Integrator::li`], recording the path's vertices in `path` (path tracing only; the
    /// other integrators record nothing).
    pub fn li_traced(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        path: &mut Vec<PathVertex>,
    ) -> SampledSpectrum {
        match *self {
            Integrator::Path {
                max_depth,
                regularize,
            } => path::li_observed::<_, false>(
                scene, ray, sampler, lambda, max_depth, regularize, path, None,
            ),
            // Without media, volpath is the path tracer (see `volpath`), vertices included.
            Integrator::VolPath {
                max_depth,
                regularize,
            } if scene.media().is_empty() => path::li_observed::<_, false>(
                scene, ray, sampler, lambda, max_depth, regularize, path, None,
            ),
            _ => self.li(scene, ray, sampler, lambda),
        }
    }

    /// The path tracer's settings (maximum depth, regularisation) when this integrator is the
    /// path tracer on `scene`: `path`, and `volpath` on a scene without media. Its camera rays
    /// may then be traced a pixel's samples at a time, each path going on from its first hit
    /// ([`path::li_observed`]).
    pub fn path_tracer(&self, scene: &Scene) -> Option<(u32, bool)> {
        match *self {
            Integrator::Path {
                max_depth,
                regularize,
            } => Some((max_depth, regularize)),
            Integrator::VolPath {
                max_depth,
                regularize,
            } if scene.media().is_empty() => Some((max_depth, regularize)),
            _ => None,
        }
    }

    /// Radiance arriving at the camera along `ray`. With `lambda` (spectral mode, radiance
    /// integrators only) the result's lanes are the radiance at those four wavelengths;
    /// otherwise they are linear sRGB as (r, g, b, b) ([`rgb_lanes`]).
    pub fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
    ) -> SampledSpectrum {
        match *self {
            Integrator::Whitted { max_depth } => {
                whitted::li(scene, ray, sampler, lambda, 0, max_depth)
            }
            Integrator::Path {
                max_depth,
                regularize,
            } => path::li(scene, ray, sampler, lambda, max_depth, regularize),
            Integrator::VolPath {
                max_depth,
                regularize,
            } => volpath::li(scene, ray, sampler, lambda, max_depth, regularize),
            Integrator::SimplePath {
                max_depth,
                sample_lights,
                sample_bsdf,
            } => simple::simple_path(
                scene,
                ray,
                sampler,
                lambda,
                max_depth,
                sample_lights,
                sample_bsdf,
            ),
            Integrator::RandomWalk { max_depth } => {
                simple::random_walk(scene, ray, sampler, lambda, max_depth)
            }
            Integrator::SimpleVolPath { max_depth } => {
                simple::simple_vol_path(scene, ray, sampler, lambda, max_depth)
            }
            // One camera ray has no photon map: a film renders sppm by its iterations
            // (`crate::render::sppm`); a caller asking for one ray alone (`--check-nan`'s
            // replay of a camera sample) gets that ray's path-traced radiance, the same
            // light that sppm's Ld and photons estimate together.
            Integrator::Sppm(o) => path::li(scene, ray, sampler, lambda, o.max_depth, false),
            // vcm likewise: its light subpaths and merges are an iteration's, over a film
            // (`crate::render::vcm`); one camera ray alone is path traced.
            Integrator::Vcm(o) => path::li(scene, ray, sampler, lambda, o.max_depth, false),
            // Without a film to splat into, the light-path integrators give only what reaches
            // the camera ray's own pixel (bdpt's t ≥ 2 strategies, nothing for lightpath): a
            // film renders them through `li_splatting`.
            Integrator::LightPath { .. }
            | Integrator::PathCaustics { .. }
            | Integrator::Bdpt { .. }
            | Integrator::Mlt(_) => self.li_splatting(scene, ray, sampler, lambda, &mut |_, _| {}),
            // The debug views are RGB quantities, as lanes (r, g, b, b).
            Integrator::Normals => rgb_lanes(debug::normals(scene, ray)),
            Integrator::Depth => rgb_lanes(debug::depth(scene, ray)),
            Integrator::AmbientOcclusion {
                cos_sample,
                max_distance,
            } => rgb_lanes(debug::ambient_occlusion(
                scene,
                ray,
                sampler,
                cos_sample,
                max_distance,
            )),
        }
    }
}

/// One surface a path met, as `--check-nan` reports it: where, the geometry, and the state of
/// the path when its next direction was sampled there.
#[derive(Clone, Copy, Debug)]
pub struct PathVertex {
    /// Bounce number (1 at the first surface).
    pub depth: u32,
    /// Primitive hit.
    pub prim: u32,
    /// Hit point.
    pub p: Vec3,
    /// Geometric normal.
    pub n: Vec3,
    /// Shading normal.
    pub ns: Vec3,
    /// Direction back along the incoming ray.
    pub wo: Vec3,
    /// Sampled next direction, if the BSDF gave one.
    pub wi: Option<Vec3>,
    /// BSDF value for it.
    pub f: Option<SampledSpectrum>,
    /// Its density.
    pub pdf: Option<f32>,
    /// Path throughput before this bounce.
    pub beta: SampledSpectrum,
    /// Radiance gathered so far.
    pub l: SampledSpectrum,
}

/// At a surface that `disperses`, a spectral path keeps only its hero wavelength (see
/// [`crate::spectrum::hero`]): terminates the secondary wavelengths of `wavelengths`, once, and
/// says whether it did so now, when the caller weights what the path carries by
/// [`crate::spectrum::hero::HERO_ONLY`].
#[inline]
pub(crate) fn keep_hero_only(
    wavelengths: &mut Option<SampledWavelengths>,
    disperses: bool,
) -> bool {
    match wavelengths {
        Some(w) if disperses && !w.secondary_terminated() => {
            w.terminate_secondary();
            true
        }
        _ => false,
    }
}

/// Next-event estimation at a surface `si` seen from `wo`, as the path tracer does: one light
/// chosen by the scene's light sampler (p_l), one point on it (pdf), weighted against BSDF
/// sampling by the power heuristic unless the light is a delta light:
/// f(wo, wi)·|cos θi|·Le·w/(p_l·pdf), zero when the shadow ray is blocked. The sampler's
/// dimensions (1 + 2) are drawn whatever the BSDF, so that a path's layout does not depend on
/// it; a BSDF without a non-specular lobe gets nothing (a light sample cannot find its delta
/// lobes). `sppm`'s camera paths and a subsurface path's exit point.
pub(crate) fn direct_light(
    scene: &Scene,
    si: &SurfaceInteraction,
    bsdf: &Bsdf,
    wo: Vec3,
    ctx: &LightSampleContext,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
) -> SampledSpectrum {
    let ul = sampler.get_1d();
    let u = sampler.get_2d();
    if scene.lights().is_empty() || !bsdf.flags().is_non_specular() {
        return SampledSpectrum::ZERO;
    }
    let Some((i, pmf)) = scene.light_sampler().sample(ctx, ul) else {
        return SampledSpectrum::ZERO;
    };
    let light = &scene.lights()[i];
    let Some(ls) = scene.sample_li(light, ctx, u) else {
        return SampledSpectrum::ZERO;
    };
    let f = bsdf.f(wo, ls.wi, TransportMode::Radiance) * ls.wi.dot(si.shading.n).abs();
    if ls.pdf.is_nan()
        || ls.pdf <= 0.0
        || f == SampledSpectrum::ZERO
        || scene.intersect_p(&si.spawn_ray_to(ls.p_light))
    {
        return SampledSpectrum::ZERO;
    }
    let p_l = pmf * ls.pdf;
    let w = if light.is_delta() {
        1.0
    } else {
        power_heuristic(p_l, bsdf.pdf(wo, ls.wi, TransportMode::Radiance))
    };
    f * scene.light_radiance(i, lambda, ls.l, ls.factor, ls.wi) * (w / p_l)
}

/// The BSDF at a hit, with `Mix` materials resolved (the choice is a deterministic hash of the
/// hit, as pbrt does, so it needs no sampler dimension). `None` for `interface` materials,
/// which the ray passes straight through. With `lambda` (spectral mode) the material's colours
/// are evaluated at those wavelengths. The flag says whether the material disperses
/// ([`Material::disperses`]): a spectral path then keeps only its hero wavelength.
///
/// A diffuse material of constant colour (the commonest kind) is built inline, with the same
/// values as [`Material::bxdf`] gives it: out of line, the BSDF came back through memory, in
/// stores narrower than the caller's loads, a store-forwarding stall at every bounce.
#[inline]
pub(crate) fn bsdf_at(
    scene: &Scene,
    hit: &SceneHit,
    lambda: Option<&SampledWavelengths>,
) -> Option<(Bsdf, bool)> {
    bsdf_at_memo(scene, hit, lambda, None)
}

/// [`bsdf_at`], taking a constant diffuse reflectance from the path's `memo` when given.
#[inline(always)]
pub(crate) fn bsdf_at_memo(
    scene: &Scene,
    hit: &SceneHit,
    lambda: Option<&SampledWavelengths>,
    memo: Option<&mut PathSpectra>,
) -> Option<(Bsdf, bool)> {
    let m = scene.prim(hit.prim).material;
    let constant_diffuse = match (scene.material(m), hit.albedo()) {
        (Material::Diffuse(DiffuseMaterial { reflectance }), None) => match reflectance {
            SpectrumTex::Const(c) => Some(*c),
            SpectrumTex::Measured(s) => Some(s.rgb),
            SpectrumTex::Tex(_) => None,
        },
        _ => None,
    };
    if let Some(c) = constant_diffuse {
        // The reflectance as the diffuse material's BxDF reads it (an albedo, prepared once
        // per scene for a constant), without the texture look-up.
        let rho = match lambda {
            Some(lambda) => {
                let eval =
                    || DiffuseMaterial::prepared_reflectance(scene.spectral_colours(m, lambda));
                match memo {
                    Some(memo) => memo.material(m, eval),
                    None => eval(),
                }
            }
            None => rgb_colour(c, ColourKind::Albedo),
        };
        let bsdf = Bsdf::new(BxDF::diffuse(rho), hit.si.shading.n, hit.si.shading.dpdu);
        return Some((bsdf, false));
    }
    bsdf_at_general(scene, hit, lambda)
}

/// [`bsdf_at`] for every material.
#[inline(never)]
fn bsdf_at_general(
    scene: &Scene,
    hit: &SceneHit,
    lambda: Option<&SampledWavelengths>,
) -> Option<(Bsdf, bool)> {
    let mut m = scene.prim(hit.prim).material;
    let tex = scene.textures();
    let tc = Scene::tex_coord_with_footprint(hit);
    for _ in 0..16 {
        match scene.material(m) {
            Material::Mix(MixMaterial { materials, amount }) => {
                m = crate::material::mix::mix_pick(*materials, tex.float(*amount, &tc), hit.si.p);
            }
            // The bump map was applied at the hit (`crate::material::mix::apply_bump`).
            Material::Bumped(BumpedMaterial { base, .. }) => m = *base,
            mat => {
                let spectral = lambda.map(|lambda| scene.spectral_colours(m, lambda));
                let mut bxdf = mat.bxdf(&tex, &tc, spectral)?;
                // A shape's own colour (voxels) replaces a diffuse material's reflectance.
                if let (Some(c), Material::Diffuse(_)) = (hit.albedo(), mat) {
                    bxdf = crate::material::BxDF::diffuse(albedo_at(
                        lambda,
                        c.clamp(Rgb::ZERO, Rgb::ONE),
                    ));
                }
                let bsdf = Bsdf::new(bxdf, hit.si.shading.n, hit.si.shading.dpdu);
                return Some((bsdf, mat.disperses()));
            }
        }
    }
    None
}
