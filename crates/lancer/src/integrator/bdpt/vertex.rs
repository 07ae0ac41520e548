//! A vertex of a bidirectional subpath (pbrt-v4's BDPT `Vertex`): where it is, what it
//! carries, and the densities with which either subpath would have reached it, per unit area
//! (the measure in which the strategies' densities compare).
//!
//! A vertex in a medium scatters by its phase function; as in pbrt-v4, its densities count
//! only the direction (the phase function's), converted to area by 1/d² (no cosine: it has no
//! surface), not the density of the distance at which delta tracking stopped there: the MIS
//! weights are still a partition of unity over a path's strategies, so every estimate stays
//! unbiased.

use super::super::emission::{emission_at, environment, reached_from_infinity};
use super::super::volpath::avg;
use crate::light::{LightSampleContext, LightType};
use crate::material::{Bsdf, TransportMode};
use crate::math::{PI, SampledSpectrum, Vec2, Vec3, normalize};
use crate::medium::HgPhaseFunction;
use crate::ray::Ray;
use crate::scene::Scene;
use crate::spectrum::sampled::SampledWavelengths;

/// What a vertex is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Kind {
    /// The camera's lens.
    Camera,
    /// A point on light `0` (index into the scene's lights): the start of a light subpath, or
    /// the light sampled for a camera subpath.
    Light(u32),
    /// The environment, seen by a camera subpath that left the scene.
    Escaped,
    /// A surface point with a BSDF (it may emit too).
    Surface,
    /// A point where the subpath scattered in a medium (by [`Vertex::phase`]).
    Medium,
}

/// One vertex of a camera or light subpath.
#[derive(Clone, Copy, Debug)]
pub(super) struct Vertex {
    /// What it is.
    pub kind: Kind,
    /// Position.
    pub p: Vec3,
    /// Bound on the rounding error of `p`.
    pub p_error: Vec3,
    /// Geometric normal; zero off surfaces (points, directions, a pinhole).
    pub ng: Vec3,
    /// Shading normal (the geometric one where there is no other).
    pub ns: Vec3,
    /// Direction back towards the vertex the subpath came from (surfaces).
    pub wo: Vec3,
    /// Surface coordinates (for image emitters).
    pub uv: Vec2,
    /// Primitive (surfaces).
    pub prim: u32,
    /// The BSDF (surfaces).
    pub bsdf: Option<Bsdf>,
    /// The phase function (medium vertices).
    pub phase: HgPhaseFunction,
    /// The medium the vertex is in: the camera's, a light's (for the lights other than area
    /// lights), the one a medium vertex scattered in, the one the ray reaching a surface
    /// travelled in (`None`: vacuum).
    pub medium: Option<u32>,
    /// The subpath's throughput up to this vertex.
    pub beta: SampledSpectrum,
    /// Per lane, the density with which the subpath's distances through media were sampled
    /// at that lane's coefficients over the density at the hero lane's (which sampled them):
    /// Π σ(λ)·T_maj(λ) / (σ(h)·T_maj(h)) over its collisions and crossings (1 everywhere
    /// without media). A strategy's contribution is divided by the lanes' average of its two
    /// subpaths' product: the one-sample balance heuristic across lanes, as `volpath`'s r_u.
    pub r: SampledSpectrum,
    /// Scattered by a specular lobe (no connection can reach it).
    pub delta: bool,
    /// Density of this vertex per unit area, sampled from its subpath's previous vertex.
    pub pdf_fwd: f32,
    /// Density of this vertex per unit area, were it sampled from the other direction.
    pub pdf_rev: f32,
}

impl Vertex {
    /// A vertex of `kind` at `p` with normal `n` (zero off surfaces) carrying `beta`.
    pub fn endpoint(kind: Kind, p: Vec3, p_error: Vec3, n: Vec3, beta: SampledSpectrum) -> Self {
        Vertex {
            kind,
            p,
            p_error,
            ng: n,
            ns: n,
            wo: Vec3::ZERO,
            uv: Vec2::ZERO,
            prim: 0,
            bsdf: None,
            phase: HgPhaseFunction { g: 0.0 },
            medium: None,
            beta,
            r: SampledSpectrum::ONE,
            delta: false,
            pdf_fwd: 0.0,
            pdf_rev: 0.0,
        }
    }

    /// True on a surface (a normal defines the area measure there).
    pub fn is_on_surface(&self) -> bool {
        self.ng != Vec3::ZERO
    }

    /// The light this vertex is on, if any: a light vertex's own, or a surface's emission.
    fn light(&self, scene: &Scene) -> Option<u32> {
        match self.kind {
            Kind::Light(i) => Some(i),
            Kind::Surface => scene.prim(self.prim).emission.map(|e| e.light),
            _ => None,
        }
    }

    /// True where a path may end on a light: light vertices, the environment, emitters.
    pub fn is_light(&self, scene: &Scene) -> bool {
        match self.kind {
            Kind::Light(_) | Kind::Escaped => true,
            Kind::Surface => self.light(scene).is_some(),
            Kind::Camera | Kind::Medium => false,
        }
    }

    /// A light vertex of a point or directional light (no area to hit).
    pub fn is_delta_light(&self, scene: &Scene) -> bool {
        matches!(self.kind, Kind::Light(i) if scene.lights()[i as usize].is_delta())
    }

    /// The environment, an environment light's vertex or a distant light's: lights at
    /// infinity, whose densities are per unit solid angle rather than area.
    pub fn is_infinite_light(&self, scene: &Scene) -> bool {
        match self.kind {
            Kind::Escaped => true,
            Kind::Light(i) => {
                let l = &scene.lights()[i as usize];
                l.is_infinite() || l.light_type() == LightType::DeltaDirection
            }
            _ => false,
        }
    }

    /// True where a connection can join this vertex: not a specular surface, not a distant
    /// light (whose single direction no other vertex can aim at).
    pub fn is_connectible(&self, scene: &Scene) -> bool {
        match self.kind {
            Kind::Camera | Kind::Escaped | Kind::Medium => true,
            Kind::Light(i) => scene.lights()[i as usize].light_type() != LightType::DeltaDirection,
            Kind::Surface => self.bsdf.is_some_and(|b| b.flags().is_non_specular()),
        }
    }

    /// The BSDF's value from this vertex towards `next` (surfaces), the phase function's
    /// (medium vertices); zero elsewhere.
    pub fn f(&self, next: &Vertex, mode: TransportMode) -> SampledSpectrum {
        let w = next.p - self.p;
        match (self.kind, &self.bsdf) {
            (Kind::Surface, Some(bsdf)) if w.length_squared() > 0.0 => {
                bsdf.f(self.wo, normalize(w), mode)
            }
            (Kind::Medium, _) if w.length_squared() > 0.0 => {
                SampledSpectrum::splat(self.phase.p(self.wo, normalize(w)))
            }
            _ => SampledSpectrum::ZERO,
        }
    }

    /// The medium a ray leaving this vertex in direction `w` starts in: a surface's far side
    /// when its interface is a transition, else the vertex's own medium; an area light's side
    /// of its interface.
    pub fn medium_towards(&self, scene: &Scene, w: Vec3) -> Option<u32> {
        match self.kind {
            Kind::Light(i) => scene.light_medium(i as usize, self.ng, w),
            Kind::Surface => scene.medium_past(self.prim, self.ng, w, self.medium),
            Kind::Camera | Kind::Medium | Kind::Escaped => self.medium,
        }
    }

    /// Radiance this light vertex (or emitting surface, or environment) sends towards `v`.
    pub fn le(
        &self,
        scene: &Scene,
        v: &Vertex,
        lambda: Option<&SampledWavelengths>,
    ) -> SampledSpectrum {
        let w = v.p - self.p;
        if w.length_squared() == 0.0 || !self.is_light(scene) {
            return SampledSpectrum::ZERO;
        }
        let w = normalize(w);
        if self.is_infinite_light(scene) {
            // The environment along −w (the direction the camera subpath left in).
            return environment(scene, -w, lambda);
        }
        match emission_at(scene, self.prim, self.ng, self.uv, w) {
            Some((i, c)) => scene.light_radiance(i, lambda, c, 1.0, -w),
            None => SampledSpectrum::ZERO,
        }
    }

    /// Turns `pdf`, a density per unit solid angle at this vertex, into a density per unit
    /// area at `next`: p·|cos θ_next|/d² (no change when `next` is at infinity).
    pub fn convert_density(&self, pdf: f32, next: &Vertex, scene: &Scene) -> f32 {
        if next.is_infinite_light(scene) {
            return pdf;
        }
        let w = next.p - self.p;
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let inv_d2 = 1.0 / d2;
        let mut pdf = pdf;
        if next.is_on_surface() {
            pdf *= next.ng.dot(w * inv_d2.sqrt()).abs();
        }
        pdf * inv_d2
    }

    /// Density per unit area with which this vertex, reached from `prev`, samples `next`
    /// (pbrt-v4's `Vertex::PDF`).
    pub fn pdf(&self, scene: &Scene, prev: Option<&Vertex>, next: &Vertex) -> f32 {
        if let Kind::Light(_) = self.kind {
            return self.pdf_light(scene, next);
        }
        let wn = next.p - self.p;
        if wn.length_squared() == 0.0 {
            return 0.0;
        }
        let wn = normalize(wn);
        let pdf = match (self.kind, &self.bsdf, prev) {
            (Kind::Camera, _, _) => scene.camera().pdf_we(self.p, wn).1,
            (Kind::Surface, Some(bsdf), Some(prev)) => {
                let wp = prev.p - self.p;
                if wp.length_squared() == 0.0 {
                    return 0.0;
                }
                bsdf.pdf(normalize(wp), wn, TransportMode::Radiance)
            }
            (Kind::Medium, _, Some(prev)) => {
                let wp = prev.p - self.p;
                if wp.length_squared() == 0.0 {
                    return 0.0;
                }
                self.phase.pdf(normalize(wp), wn)
            }
            _ => 0.0,
        };
        self.convert_density(pdf, next, scene)
    }

    /// Density per unit area with which this light vertex's light, emitting a ray, reaches
    /// `v`: p_dir/d² (times |cos θ_v| on a surface); an infinite light's rays are spread over
    /// the scene's disk: 1/(π r²).
    pub fn pdf_light(&self, scene: &Scene, v: &Vertex) -> f32 {
        let w = v.p - self.p;
        let d2 = w.length_squared();
        if d2 == 0.0 {
            return 0.0;
        }
        let inv_d2 = 1.0 / d2;
        let w = w * inv_d2.sqrt();
        let mut pdf = if self.is_infinite_light(scene) {
            if !reached_from_infinity(scene, v.p, w) {
                // The MIS ratios read a density of 0 as a delta vertex's (remapped to 1, as
                // pbrt-v4 does); this one is a path no light subpath makes: the smallest
                // positive density, so that its strategies weigh nothing.
                return f32::MIN_POSITIVE;
            }
            scene_disk_density(scene)
        } else {
            let Some(i) = self.light(scene) else {
                return 0.0;
            };
            scene.lights()[i as usize].pdf_le(self.p, self.ng, w).dir * inv_d2
        };
        if v.is_on_surface() {
            pdf *= v.ng.dot(w).abs();
        }
        pdf
    }

    /// Density with which a light subpath starts at this vertex, aimed at `v`: the light's
    /// choice times its position's density (per unit area); for lights at infinity, the
    /// density of the direction (see [`infinite_light_density`]).
    pub fn pdf_light_origin(&self, scene: &Scene, v: &Vertex) -> f32 {
        let w = v.p - self.p;
        if w.length_squared() == 0.0 {
            return 0.0;
        }
        let w = normalize(w);
        if self.is_infinite_light(scene) {
            return infinite_light_density(scene, w);
        }
        let Some(i) = self.light(scene) else {
            return 0.0;
        };
        scene.light_distribution().pmf(i as usize)
            * scene.lights()[i as usize].pdf_le(self.p, self.ng, w).pos
    }

    /// The ray leaving this vertex towards `target` for a visibility test.
    pub fn shadow_ray(&self, target: Vec3) -> Ray {
        Ray::spawn_to(self.p, self.p_error, self.ng, target)
    }
}

/// Density per unit area with which a light at infinity starts its rays on the scene's disk,
/// whichever light it is (pbrt-v4's `PDFLight` for them): 1/(π r²), r the radius of the
/// scene's bounding sphere, as the lights' own `pdf_le` gives it. (Only for points its rays
/// reach: beyond, on lancer's infinite planes, a far point's light sampling got an MIS weight
/// of almost 0 against light paths that never come: a black horizon.)
fn scene_disk_density(scene: &Scene) -> f32 {
    let (_, r) = scene.bounds().bounding_sphere();
    1.0 / (PI * r * r)
}

/// Density, per unit solid angle, with which the environment lights (chosen by power) emit
/// light paths arriving along −`w`: Σ pmf(light)·pdf(light, −w).
pub(super) fn infinite_light_density(scene: &Scene, w: Vec3) -> f32 {
    let ctx = LightSampleContext::in_medium(Vec3::ZERO);
    scene
        .infinite_lights()
        .iter()
        .map(|&i| {
            scene.light_distribution().pmf(i as usize)
                * scene.lights()[i as usize].pdf_li(&ctx, -w, None)
        })
        .sum()
}

/// `l`, a contribution whose lanes' density ratios are `r`, over their average: the one-sample
/// balance heuristic across lanes. Untouched when r is 1 (no medium).
pub(super) fn lane_balance(l: SampledSpectrum, r: SampledSpectrum) -> SampledSpectrum {
    if r == SampledSpectrum::ONE {
        return l;
    }
    let a = avg(r);
    if a > 0.0 && a.is_finite() {
        l / a
    } else {
        SampledSpectrum::ZERO
    }
}
