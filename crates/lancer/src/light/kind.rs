//! What every kind of light does (the family's operations, [`LightKind`]) and what every kind
//! of light description does ([`LightDescKind`]): a leaf module, so that each kind's file
//! implements them without importing the family's list ([`super::Light`]).

use super::bounds::LightExtent;
use super::sample::{LightLiSample, LightSampleContext};
use crate::image::Image;
use crate::math::{Rgb, SampledSpectrum, Vec2, Vec3};
use crate::ray::Ray;
use crate::shape::{Shape, TriangleMesh};
use crate::spectrum::sampled::SampledWavelengths;
use std::sync::Arc;

/// How a light emits, as pbrt-v4's `LightType` says: what light transport can and cannot do
/// with it (a delta light cannot be hit by a ray, an infinite one is reached by escaping rays).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LightType {
    /// All its light leaves one point (point, spot, goniometric, projection lights).
    DeltaPosition,
    /// All its light travels along one direction (the distant light).
    DeltaDirection,
    /// A surface that emits (area lights): rays can hit it.
    Area,
    /// Infinitely far away in many directions (environment lights): rays that leave the scene
    /// see it.
    Infinite,
}

impl LightType {
    /// True for the lights only sampling can reach (points and directions).
    #[inline]
    pub fn is_delta(self) -> bool {
        matches!(self, LightType::DeltaPosition | LightType::DeltaDirection)
    }
}

/// The sphere bounding the scene: where distant and environment lights start the rays they
/// emit ([`LightKind::sample_le`]), and the radius their power is measured over.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SceneSphere {
    /// Centre, world space.
    pub centre: Vec3,
    /// Radius.
    pub radius: f32,
}

/// A ray of light leaving a light (pbrt-v4's `LightLeSample`), for methods that trace paths
/// from the lights (light tracing, bidirectional path tracing, photon mapping).
///
/// The ray's density is `pdf_pos · pdf_dir`: `pdf_pos` per unit area of where the ray starts
/// (1 for a point light, whose position is not sampled), `pdf_dir` per unit solid angle of
/// its direction (1 for the distant light, whose direction is not sampled). On an area
/// light, `pdf_pos` is per unit area of the surface, whose normal `n` is given, so that the
/// flux the ray carries is `l · |n·w| / (pdf_pos · pdf_dir)`; elsewhere `n` is zero and the
/// ray carries `l / (pdf_pos · pdf_dir)` (for distant and environment lights `pdf_pos` is per
/// unit area of a disk perpendicular to `w`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightLeSample {
    /// Radiance along the ray (for a light at a point: its intensity in direction `w`).
    pub l: Rgb,
    /// `l` divided by the light's constant colour ([`LightKind::constant_colour`]), as
    /// [`LightLiSample::factor`]: spectral mode multiplies the colour's prepared spectrum by
    /// it.
    pub factor: f32,
    /// Where the ray starts, world space (on the light's surface for an area light: spawn the
    /// ray off the surface along `n`).
    pub p: Vec3,
    /// Bound on the rounding error of `p` (zero for a light at a point, whose position is
    /// given), by which the ray is spawned off it.
    pub p_error: Vec3,
    /// Unit direction the light travels.
    pub w: Vec3,
    /// Geometric normal of the emitting surface at `p` (area lights), else zero.
    pub n: Vec3,
    /// Density of `p`, per unit area.
    pub pdf_pos: f32,
    /// Density of `w`, per unit solid angle.
    pub pdf_dir: f32,
}

impl LightLeSample {
    /// |n·w| on an emitting surface, 1 elsewhere: the ray carries l·|n·w|/(p_pos·p_dir).
    #[inline]
    pub fn abs_cos(&self) -> f32 {
        if self.n == Vec3::ZERO {
            1.0
        } else {
            self.n.dot(self.w).abs()
        }
    }

    /// The ray itself, spawned off `p` (along the surface's normal on an area light, along
    /// `w` elsewhere) by `p_error`.
    #[inline]
    pub fn ray(&self) -> Ray {
        let n = if self.n == Vec3::ZERO { self.w } else { self.n };
        Ray::spawn(self.p, self.p_error, n, self.w)
    }
}

/// A conservative bound on the rounding error of a point computed on a light's surface or on
/// the scene's disk (a [`LightLeSample::p`]): 64 ulps of its largest coordinate.
pub fn point_error(p: Vec3) -> Vec3 {
    Vec3::splat(p.abs().max_element() * 64.0 * f32::EPSILON)
}

/// The densities with which [`LightKind::sample_le`] would emit a given ray (pbrt-v4's
/// `PDF_Le`): of its start per unit area, of its direction per unit solid angle. A delta
/// component (a point light's position, a distant light's direction) has density 0 here: it
/// cannot be reached by chance.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LightLePdf {
    /// Density of the ray's start, per unit area.
    pub pos: f32,
    /// Density of the ray's direction, per unit solid angle.
    pub dir: f32,
}

/// The operations every kind of light has (one file per kind implements them; [`super::Light`]
/// calls them through one `match`, statically). `shapes` and `meshes` are the scene's, where
/// area lights find their surface; the other kinds ignore them.
pub trait LightKind {
    /// How the light emits (pbrt-v4's `LightType`).
    fn light_type(&self) -> LightType;

    /// Samples incident light at `ctx` with the 2D sample `u`; `None` when the light
    /// contributes nothing there (pbrt-v4's `SampleLi`).
    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        shapes: &[Shape],
        meshes: &[TriangleMesh],
    ) -> Option<LightLiSample>;

    /// Density per solid angle with which [`LightKind::sample_li`] picks direction `wi` at
    /// `ctx`, 0 for delta lights; for area lights `hit` is where `wi` meets the light and its
    /// geometric normal (pbrt-v4's `PDF_Li`).
    fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, hit: Option<(Vec3, Vec3)>) -> f32 {
        let _ = (ctx, wi, hit);
        0.0
    }

    /// Total emitted power Φ, averaged over the channels, by which lights are chosen
    /// (pbrt-v4's `Phi`).
    fn power(&self) -> f32;

    /// Where the light is, how much and where it emits, for the light BVH (pbrt-v4's
    /// `Bounds`).
    fn extent(&self, shapes: &[Shape], meshes: &[TriangleMesh]) -> LightExtent;

    /// The constant colour the emission is a multiple of (intensity or radiance), `None`
    /// when it varies in colour over directions or points (an image).
    fn constant_colour(&self) -> Option<Rgb>;

    /// Radiance arriving along a ray that escapes the scene in direction `d` (environment
    /// lights; `d` need not be normalised).
    fn le(&self, d: Vec3) -> Rgb {
        let _ = d;
        Rgb::ZERO
    }

    /// Spectral radiance at the path's wavelengths arriving along `wi` (towards the light),
    /// for a light spectral by nature (the sun and sky); `None` for the others, whose colour
    /// spectral mode uplifts.
    fn le_spectral(&self, wi: Vec3, lambda: &SampledWavelengths) -> Option<SampledSpectrum> {
        let _ = (wi, lambda);
        None
    }

    /// Samples a ray of light leaving the light (pbrt-v4's `SampleLe`) with two 2D samples:
    /// `u1` for the position (the direction for lights at a point), `u2` for the direction
    /// (the position on the scene's disk for distant and environment lights). `None` when
    /// the sample carries nothing.
    fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        shapes: &[Shape],
        meshes: &[TriangleMesh],
    ) -> Option<LightLeSample>;

    /// True when light leaving along unit world direction `w` (the way it travels) is
    /// concentrated enough that a path from the camera cannot find it by BSDF sampling
    /// through a specular surface, so that `path` with `caustics`
    /// ([`crate::integrator::caustics`]) renders its caustics by light tracing: all of a
    /// delta light's light (the default), the sun of a sky; no area or environment light.
    fn caustic_source(&self, w: Vec3) -> bool {
        let _ = w;
        self.light_type().is_delta()
    }

    /// The densities with which [`LightKind::sample_le`] emits the ray leaving `p` in unit
    /// direction `w` (the way the light travels). For an area light `p` is the point on its
    /// surface and `n` the geometric normal there (as the hit gives it); the other kinds
    /// ignore `n`, and all but the portal light ignore `p` (pbrt-v4's two `PDF_Le`).
    fn pdf_le(&self, p: Vec3, n: Vec3, w: Vec3) -> LightLePdf;

    /// The image the light reads, for memory accounting (each shared image is counted once).
    fn image(&self) -> Option<&Arc<Image>> {
        None
    }

    /// Bytes the light holds outside its record in the scene's list (its box and sampling
    /// tables; its image is in [`LightKind::image`]).
    fn heap_bytes(&self) -> usize {
        0
    }
}

/// What every kind of light description does: its name, its rules, its build.
pub trait LightDescKind {
    /// The runtime light it builds.
    type Light;

    /// The pbrt-v4 name of the light (`LightSource "…"`).
    fn pbrt_name(&self) -> &'static str;

    /// The kind as `lancer info` counts it (the pbrt-v4 name unless two kinds share it).
    fn count_name(&self) -> &'static str {
        self.pbrt_name()
    }

    /// Checks the rules without which the light means nothing, and returns the first one
    /// broken (one message per rule, the same whoever asks: the readers and the build).
    fn validate(&self) -> Result<(), String>;

    /// The light, for a scene bounded by `scene` (checked first by
    /// [`LightDescKind::validate`]).
    fn build(&self, scene: &SceneSphere) -> Result<Self::Light, String>;
}
