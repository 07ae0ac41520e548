//! Vertex connection and merging (lancer's `vcm`; Georgiev, Křivánek, Davidovič and Slusallek
//! 2012, "Light transport simulation with vertex connection and merging", the same estimator
//! as Hachisuka et al.'s unified path sampling): bidirectional path tracing's connections and
//! photon mapping's merges, combined by multiple importance sampling, so that one integrator
//! renders what paths from the camera find (diffuse light), what light paths joined to the
//! camera find (caustics seen directly), and what only merging finds (caustics seen through
//! glass, specular–diffuse–specular paths).
//!
//! Each iteration (one per sample per pixel; the film loop is `crate::render::vcm`) traces
//! one light subpath per pixel of the whole render ([`light_path`]): every non-specular
//! vertex it reaches is stored and joined to the camera (t = 1, splatted). The stored
//! vertices are hashed into a grid of the iteration's radius r, and each pixel's camera
//! subpath ([`camera::camera_path`]) then gathers, at every non-specular vertex: emission it
//! hits, next-event estimation (s = 1), connections to the vertices of the light subpath of
//! its own pixel, and merges with the stored vertices within r (kernel 1/(π r²)).
//!
//! The MIS weights are the balance heuristic over all these strategies, computed by the
//! paper's recursion (its technical report's dVCM, dVC, dVM, as in its reference
//! implementation SmallVCM): each subpath carries three running sums of density ratios, so
//! that a strategy's weight costs O(1) whatever the path length. A merge counts as a
//! strategy of density p_VC · η with η = π r² · N (N the light subpaths of the iteration).
//!
//! Next-event estimation samples a light point by the light's `sample_li` (which may sample
//! by solid angle), but the weights compare the strategies with the density of a point
//! chosen on the light by area (the light's `pdf_le` position density): a fixed function of
//! the path in every strategy's weight, so the weights of a path still sum to one and the
//! estimate stays unbiased. Russian roulette (after [`super::RR_AFTER_DEPTH`] bounces, as the
//! path tracer's) is likewise left out of the weights.
//!
//! Surfaces only: a scene with participating media is rendered with `volpath` (the scene
//! reader warns).

pub mod camera;
pub mod grid;
#[cfg(test)]
mod tests;

pub use super::desc::VcmOptions;

use super::{bsdf_at, keep_hero_only};
use crate::light::LightType;
use crate::material::{Bsdf, BsdfSample, TransportMode};
use crate::math::{PI, SampledSpectrum, Vec2, Vec3};
use crate::ray::Ray;
use crate::sampling::SampleSource;
use crate::scene::Scene;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// The merge radius of the first iteration when the scene gives none, as a fraction of the
/// radius of the scene's bounding sphere (SmallVCM's default).
pub const DEFAULT_RADIUS_FRACTION: f32 = 0.003;

/// The merge radius of iteration `k` (from 0): r_1 · (k + 1)^((α − 1)/2).
pub fn radius_at(r1: f32, alpha: f32, k: u32) -> f32 {
    r1 * ((k as f64 + 1.0).powf((alpha as f64 - 1.0) * 0.5)) as f32
}

/// The first iteration's merge radius of `options` in `scene`.
pub fn initial_radius(scene: &Scene, options: &VcmOptions) -> f32 {
    options.radius.unwrap_or_else(|| {
        let (_, r) = scene.bounds().bounding_sphere();
        DEFAULT_RADIUS_FRACTION * r
    })
}

/// What every path of one iteration shares.
#[derive(Clone, Copy, Debug)]
pub struct Iteration<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The iteration's wavelengths (spectral mode), shared by its light and camera paths.
    pub lambda: Option<SampledWavelengths>,
    /// Longest path, in segments: `maxdepth` + 1.
    pub max_length: u32,
    /// The merge radius r.
    pub radius: f32,
    /// η_VCM = π r² · N, N the light subpaths of the iteration: a merge's density over a
    /// connection's (the paper's vertex-merging weight factor).
    pub eta: f32,
    /// The camera's splat scale k (full image over rendered pixels): light subpaths are N =
    /// (rendered pixels), camera samples k·N per image.
    pub splat_scale: f32,
}

impl<'a> Iteration<'a> {
    /// Iteration of radius `radius` with `light_paths` light subpaths, paths of at most
    /// `max_depth` bounces, at `lambda`.
    pub fn new(
        scene: &'a Scene,
        lambda: Option<SampledWavelengths>,
        max_depth: u32,
        radius: f32,
        light_paths: u64,
    ) -> Self {
        Iteration {
            scene,
            lambda,
            max_length: max_depth + 1,
            radius,
            eta: PI * radius * radius * light_paths as f32,
            splat_scale: scene.camera().splat_scale(),
        }
    }

    /// The merge kernel's normalisation 1/(π r² · N) = 1/η.
    #[inline]
    pub fn merge_norm(&self) -> f32 {
        1.0 / self.eta
    }
}

/// A light subpath's non-specular vertex: what connections and merges join to.
#[derive(Clone, Copy, Debug)]
pub struct LightVertex {
    /// Position.
    pub p: Vec3,
    /// Bound on the rounding error of `p`.
    pub p_error: Vec3,
    /// Geometric normal.
    pub ng: Vec3,
    /// Shading normal.
    pub ns: Vec3,
    /// Direction back towards the previous vertex (where the light came from).
    pub wo: Vec3,
    /// The surface's BSDF.
    pub bsdf: Bsdf,
    /// Throughput of the subpath up to here (flux of one light path).
    pub beta: SampledSpectrum,
    /// Segments from the light to here (1 at the first surface).
    pub length: u32,
    /// The subpath kept only its hero wavelength (a dispersive surface on the way).
    pub hero_only: bool,
    /// The MIS running sums (the paper's dVCM, dVC, dVM) at this vertex.
    pub mis: Mis,
}

/// A subpath's MIS running sums after its last vertex (Georgiev et al.'s technical report,
/// balance heuristic): with p⃗ᵢ and p⃖ᵢ the densities per area with which the subpath and the
/// other direction sample vertex i, dVCM = p⃖ᵢ₋₁ / p⃗ᵢ … (the ratio of the strategy that
/// connects here to the one that sampled this vertex), and dVC, dVM the sums of the ratios of
/// the connections and merges further back, each updated in O(1) per bounce.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Mis {
    /// dVCM.
    pub vcm: f32,
    /// dVC.
    pub vc: f32,
    /// dVM.
    pub vm: f32,
}

impl Mis {
    /// Arriving at a surface `dist2` away whose cosine with the incoming ray is `cos`
    /// (shading normal): dVCM ·= d² (unless the segment came from infinity: `from_infinity`),
    /// and all three ÷= |cos θ|, turning the solid-angle densities into area ones.
    #[inline]
    pub fn arrive(&mut self, dist2: f32, cos: f32, from_infinity: bool) {
        if !from_infinity {
            self.vcm *= dist2;
        }
        let inv = 1.0 / cos.abs();
        self.vcm *= inv;
        self.vc *= inv;
        self.vm *= inv;
    }

    /// A bounce leaving with cosine `cos_out`, sampled with density `pdf_fwd` (solid angle),
    /// `pdf_rev` that of the reverse direction:
    /// specular: dVCM = 0, dVC ·= cos, dVM ·= cos;
    /// otherwise dVC = cos/p⃗ · (dVC·p⃖ + dVCM + η), dVM = cos/p⃗ · (dVM·p⃖ + dVCM/η + 1),
    /// dVCM = 1/p⃗.
    #[inline]
    pub fn scatter(&mut self, cos_out: f32, pdf_fwd: f32, pdf_rev: f32, specular: bool, eta: f32) {
        if specular {
            self.vcm = 0.0;
            self.vc *= cos_out;
            self.vm *= cos_out;
        } else {
            let c = cos_out / pdf_fwd;
            self.vc = c * (self.vc * pdf_rev + self.vcm + eta);
            self.vm = c * (self.vm * pdf_rev + self.vcm / eta + 1.0);
            self.vcm = 1.0 / pdf_fwd;
        }
    }
}

/// Russian roulette: the path ends with probability q = max(0, 1 − `level`) (false), else
/// `beta` is divided by 1 − q (true), so that the estimate keeps its expectation.
pub(super) fn survives<S: SampleSource + ?Sized>(
    u: &mut S,
    level: f32,
    beta: &mut SampledSpectrum,
) -> bool {
    let q = (1.0 - level).max(0.0);
    if u.get_1d() < q {
        return false;
    }
    *beta /= 1.0 - q;
    true
}

/// A subpath's next direction at a surface of shading normal `ns`, by BSDF sampling in
/// `mode`, with the running MIS quantities updated for it ([`Mis::scatter`], p⃗ the
/// sampled direction's density, p⃖ the reverse one, in the adjoint mode): the sample and
/// |cos θ_out|.
#[allow(clippy::too_many_arguments)] // the surface, the sampler, and what the walk carries
pub(super) fn scatter<S: SampleSource + ?Sized>(
    bsdf: &Bsdf,
    wo: Vec3,
    ns: Vec3,
    u: &mut S,
    mode: TransportMode,
    mis: &mut Mis,
    eta: f32,
) -> Option<(BsdfSample, f32)> {
    let uc = u.get_1d();
    let bs = bsdf.sample_f(wo, uc, u.get_2d(), mode)?;
    let cos_out = bs.wi.dot(ns).abs();
    let pdf_fwd = if bs.pdf_is_proportional {
        bsdf.pdf(wo, bs.wi, mode)
    } else {
        bs.pdf
    };
    let specular = bs.is_specular();
    let pdf_rev = if specular {
        pdf_fwd
    } else {
        bsdf.pdf(bs.wi, wo, mode.flip())
    };
    mis.scatter(cos_out, pdf_fwd, pdf_rev, specular, eta);
    Some((bs, cos_out))
}

/// The densities, for the MIS weights, of light `i` (chosen with probability `pick`) emitting
/// from `p` (geometric normal `n`) in unit direction `w`: that of choosing the point as next
/// event estimation compares it (per unit area: the light's position density; per unit solid
/// angle for an environment: its direction density; 1 for a delta light's point or
/// direction), and that of emitting the ray (position × direction), both times `pick`.
pub fn light_densities(
    scene: &Scene,
    i: usize,
    pick: f32,
    p: Vec3,
    n: Vec3,
    w: Vec3,
) -> (f32, f32) {
    let light = &scene.lights()[i];
    // The side the light leaves by (a one-sided light emits on one only, and the caller
    // asks about light it emitted; the normals given may face either way).
    let n = if n.dot(w) < 0.0 { -n } else { n };
    let pdf = light.pdf_le(p, n, w);
    let (direct, pos, dir) = match light.light_type() {
        LightType::Area => (pdf.pos, pdf.pos, pdf.dir),
        LightType::Infinite => (pdf.dir, pdf.pos, pdf.dir),
        LightType::DeltaPosition => (1.0, 1.0, pdf.dir),
        LightType::DeltaDirection => (1.0, pdf.pos, 1.0),
    };
    (pick * direct, pick * pos * dir)
}

/// True for lights whose rays come from infinity (environments, the distant light): the
/// first segment of their subpaths has no d² in its density.
pub fn from_infinity(t: LightType) -> bool {
    matches!(t, LightType::Infinite | LightType::DeltaDirection)
}

/// The weight of a contribution of paths of which one (or both) kept only its hero
/// wavelength.
#[inline]
pub fn hero_weight(hero_only: bool) -> SampledSpectrum {
    if hero_only {
        HERO_ONLY
    } else {
        SampledSpectrum::ONE
    }
}

/// What a light subpath's t = 1 connection brings to the film: the raster point and the
/// weighted radiance (splat scale included).
pub type CameraSplat = (Vec2, SampledSpectrum);

/// Traces one light subpath of iteration `it` drawing from `u`, appending its non-specular
/// vertices to `out` (those that a merge or a connection within `maxdepth` can use); with
/// `splat`, also joins each of them to a lens point (t = 1) and gives what reaches the film
/// to it.
pub fn light_path<S: SampleSource + ?Sized>(
    it: &Iteration<'_>,
    u: &mut S,
    out: &mut Vec<LightVertex>,
    mut splat: Option<&mut dyn FnMut(CameraSplat)>,
) {
    let scene = it.scene;
    crate::counters::count_light_path();
    let Some((light, pick)) = scene.light_distribution().sample(u.get_1d()) else {
        return;
    };
    let (u0, u1) = (u.get_2d(), u.get_2d());
    let Some(les) = scene.lights()[light].sample_le(u0, u1, scene.shapes(), scene.meshes()) else {
        return;
    };
    if pick == 0.0 {
        return;
    }
    let mut lambda = it.lambda;
    let le = scene.light_radiance(light, lambda.as_ref(), les.l, les.factor, -les.w);
    // β = Le·|cos θ| / (p_l·p_pos·p_dir).
    let mut beta = le * (les.abs_cos() / (pick * les.pdf_pos * les.pdf_dir));
    if beta == SampledSpectrum::ZERO || !beta.is_finite() {
        return;
    }
    let kind = scene.lights()[light].light_type();
    let (direct, emission) = light_densities(scene, light, pick, les.p, les.n, les.w);
    if emission <= 0.0 || !emission.is_finite() {
        return;
    }
    let infinite = from_infinity(kind);
    // dVCM = p_direct/p_emit; dVC = |cos θ_light|/p_emit (0 for a delta light, which no path
    // can hit); dVM = dVC/η.
    let vc = if kind.is_delta() {
        0.0
    } else if infinite {
        1.0 / emission
    } else {
        les.abs_cos() / emission
    };
    let mut mis = Mis {
        vcm: direct / emission,
        vc,
        vm: vc / it.eta,
    };
    let beta0 = beta.max_element();
    let mut hero_only = false;
    let mut ray = les.ray();
    // The previous vertex (an interface between media is not one).
    let mut from = ray.o;
    let mut length = 1u32;
    while let Some(hit) = scene.intersect(&ray) {
        let si = &hit.si;
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, lambda.as_ref()) else {
            // An interface between media: the ray goes on.
            ray = si.spawn_ray(ray.d);
            continue;
        };
        hero_only |= keep_hero_only(&mut lambda, disperses);
        let wo = si.wo;
        let dist2 = (si.p - from).length_squared();
        mis.arrive(dist2, si.shading.n.dot(wo), length == 1 && infinite);
        if bsdf.flags().is_non_specular() {
            let v = LightVertex {
                p: si.p,
                p_error: si.p_error,
                ng: si.n,
                ns: si.shading.n,
                wo,
                bsdf,
                beta,
                length,
                hero_only,
                mis,
            };
            if length < it.max_length {
                out.push(v);
                // The lens sample is drawn whether or not this path splats (a part of a
                // split render splats only its own pixels' paths), so that the path's
                // next dimensions do not depend on it.
                let u_lens = u.get_2d();
                if let Some(splat) = splat.as_deref_mut()
                    && let Some(s) = to_camera(it, &v, u_lens)
                {
                    splat(s);
                }
            }
        }
        if length + 2 > it.max_length {
            break;
        }
        let Some((bs, cos_out)) = scatter(
            &bsdf,
            wo,
            si.shading.n,
            u,
            TransportMode::Importance,
            &mut mis,
            it.eta,
        ) else {
            break;
        };
        beta *= bs.f * (cos_out / bs.pdf);
        // Russian roulette on the throughput relative to the light's emission.
        if length > super::RR_AFTER_DEPTH && !survives(u, beta.max_element() / beta0, &mut beta) {
            break;
        }
        if beta == SampledSpectrum::ZERO || !beta.is_finite() {
            break;
        }
        ray = si.spawn_ray(bs.wi);
        from = si.p;
        length += 1;
    }
}

/// The t = 1 connection of light vertex `v` to a point sampled on the lens (from `u_lens`):
/// where it lands
/// and β·f·|cos θ|·We/p_lens times the splat scale, weighted by
/// 1/(1 + k·p_cam · (η + dVCM + dVC·p⃖)) with p_cam the density with which a camera ray
/// would have reached `v` (per unit area) and k the splat scale (light subpaths are fewer
/// than camera samples by k); `None` when the camera does not see `v`.
fn to_camera(it: &Iteration<'_>, v: &LightVertex, u_lens: Vec2) -> Option<CameraSplat> {
    let scene = it.scene;
    crate::counters::count_connection();
    let camera = scene.camera();
    let cs = camera.sample_wi(v.p, u_lens)?;
    let f = v.bsdf.f(v.wo, cs.wi, TransportMode::Importance);
    let cos = cs.wi.dot(v.ns).abs();
    if f == SampledSpectrum::ZERO || cos == 0.0 {
        return None;
    }
    let (_, pdf_dir) = camera.pdf_we(cs.p_lens, -cs.wi);
    let dist2 = (cs.p_lens - v.p).length_squared();
    let p_cam = pdf_dir * cos / dist2;
    let pdf_rev = v.bsdf.pdf(cs.wi, v.wo, TransportMode::Radiance);
    let w_light = it.splat_scale * p_cam * (it.eta + v.mis.vcm + v.mis.vc * pdf_rev);
    let weight = 1.0 / (1.0 + w_light);
    let l = v.beta * f * (cos * cs.wi_importance / cs.pdf * it.splat_scale * weight);
    if l == SampledSpectrum::ZERO || !l.is_finite() {
        return None;
    }
    let ray = Ray::spawn_to(v.p, v.p_error, v.ng, cs.p_lens);
    if scene.intersect_p(&ray) {
        return None;
    }
    Some((cs.p_raster, l * hero_weight(v.hero_only)))
}
