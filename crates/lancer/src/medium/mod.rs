//! Participating media: what fills the space between surfaces (fog, smoke, ink), as pbrt-v4
//! models it.
//!
//! # The sampling contract (pbrt-v4's `SampleT_maj`)
//!
//! A medium is described to the integrator by two questions, and a new kind of medium (a grid,
//! a cloud, a NanoVDB volume) plugs in by answering them as a new variant of [`Medium`] and of
//! [`MajorantIter`]:
//!
//! 1. **Majorant segments along a ray** ([`Medium::sample_ray`]). Given a ray with a *unit*
//!    direction, world space, and a distance `t_max`, the medium yields consecutive
//!    [`MajorantSegment`]s `(t_min, t_max, σ_maj)` covering the part of `[0, t_max]` where it may
//!    be non-empty, in increasing `t`, with `σ_maj ≥ σ_t = σ_a + σ_s` at every point of the
//!    segment and every lane. A homogeneous medium gives one segment `[0, t_max]` with
//!    `σ_maj = σ_t`; a grid medium gives the ray's cells of a coarse majorant grid, found by a
//!    3D DDA, each with the largest density of its cell times the medium's σ_t. Parts of the
//!    ray outside the medium's bounds may simply be skipped (no segment): they transmit fully.
//!    The iterator is a plain value (no allocation), made per ray.
//! 2. **Properties at a point** ([`Medium::sample_point`]): σ_a, σ_s, the emitted radiance `Le`
//!    and the phase function at a world-space point, at the path's wavelengths
//!    ([`MediumProperties`]).
//!
//! Coefficients are evaluated at the path's wavelengths in spectral mode (`lambda` is `Some`)
//! and are the colour's lanes (r, g, b, b) in RGB mode (`lambda` is `None`), as everywhere in
//! lancer. [`sample_t_maj`] turns those two answers into delta tracking: it samples tentative
//! collisions with density `σ_maj[h]·exp(−σ_maj[h]·t)` (lane `h` the path's hero lane) and hands
//! each one to the integrator, with the majorant transmittance since the previous one.
//!
//! Shapes say which medium is on each side with a [`MediumInterface`]: indices into
//! [`crate::Scene::media`] (`None` is vacuum). A ray leaving a surface on the side its normal
//! faces is in `outside`, otherwise in `inside`.

pub mod cloud;
pub mod coeff;
pub mod grid;
pub mod grids;
mod homogeneous;
pub mod majorant;
pub mod nanovdb;
mod phase;
mod properties;
pub mod rgb_grid;
pub mod uniform_grid;
pub mod vdb;

pub use homogeneous::{HomogeneousDesc, HomogeneousMedium};
pub use majorant::MajorantSegment;
pub use phase::{HgPhaseFunction, PhaseSample, henyey_greenstein};
pub use properties::MediumProperties;

use grids::{GridMajorants, GridMedium, GridMediumDesc};

use crate::math::{SampledSpectrum, Vec3};
use crate::ray::Ray;
use crate::sampling::Pcg32;
use crate::spectrum::sampled::SampledWavelengths;

/// The media on the two sides of a surface, as indices into the scene's media (`None`:
/// vacuum).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MediumInterface {
    /// The medium on the side opposite the surface normal.
    pub inside: Option<u32>,
    /// The medium on the side the normal faces.
    pub outside: Option<u32>,
}

impl MediumInterface {
    /// True when the two sides differ: only then does crossing the surface change the medium
    /// a ray travels in (pbrt-v4 keeps the ray's own medium otherwise).
    pub fn is_transition(&self) -> bool {
        self.inside != self.outside
    }

    /// The medium a ray leaving the surface in direction `d` enters: `outside` when
    /// `d · n > 0` (n the geometric normal), `inside` otherwise.
    #[inline]
    pub fn towards(&self, n: Vec3, d: Vec3) -> Option<u32> {
        if d.dot(n) > 0.0 {
            self.outside
        } else {
            self.inside
        }
    }
}

/// A medium as a scene describes it (plain data); [`Medium::from_desc`] makes the renderer's.
#[derive(Clone, Debug, PartialEq)]
pub enum MediumDesc {
    /// pbrt-v4's `homogeneous`: the same coefficients everywhere.
    Homogeneous(HomogeneousDesc),
    /// pbrt-v4's `uniformgrid`, `rgbgrid`, `cloud` and `nanovdb`: coefficients that vary in
    /// space, with a majorant grid (or box) for delta tracking.
    Grid(Box<GridMediumDesc>),
}

/// A medium ready to render.
#[derive(Clone, Debug)]
pub enum Medium {
    /// The same coefficients everywhere.
    Homogeneous(HomogeneousMedium),
    /// Coefficients that vary in space ([`grids`]).
    Grid(Box<GridMedium>),
}

/// The majorant segments of one ray through one medium ([`Medium::sample_ray`]).
#[derive(Clone, Debug)]
pub enum MajorantIter<'a> {
    /// A single segment, given once.
    Single(Option<MajorantSegment>),
    /// The segments of a grid medium (DDA over its majorant grid).
    Grid(GridMajorants<'a>),
}

impl Iterator for MajorantIter<'_> {
    type Item = MajorantSegment;

    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            MajorantIter::Single(seg) => seg.take(),
            MajorantIter::Grid(it) => it.next(),
        }
    }
}

impl Medium {
    /// The renderer's medium for a description.
    pub fn from_desc(desc: &MediumDesc) -> Medium {
        match *desc {
            MediumDesc::Grid(ref d) => Medium::Grid(Box::new(GridMedium::new((**d).clone()))),
            MediumDesc::Homogeneous(ref d) => Medium::Homogeneous(d.build()),
        }
    }

    /// pbrt-v4's name for the kind of medium (`homogeneous`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            Medium::Homogeneous(_) => "homogeneous",
            Medium::Grid(m) => m.kind(),
        }
    }

    /// Heap bytes the medium holds beyond its own size.
    pub fn heap_bytes(&self) -> usize {
        match self {
            Medium::Homogeneous(_) => 0,
            Medium::Grid(m) => m.bytes(),
        }
    }

    /// True when the medium emits light somewhere.
    pub fn is_emissive(&self) -> bool {
        match self {
            Medium::Homogeneous(m) => m.is_emissive(),
            Medium::Grid(m) => m.is_emissive(),
        }
    }

    /// Properties at world-space point `p` (see the module's contract).
    #[inline]
    pub fn sample_point(&self, p: Vec3, lambda: Option<&SampledWavelengths>) -> MediumProperties {
        match self {
            Medium::Homogeneous(m) => m.properties(lambda),
            Medium::Grid(m) => {
                let pp = m.properties(p, lambda);
                MediumProperties {
                    sigma_a: pp.sigma_a,
                    sigma_s: pp.sigma_s,
                    le: pp.le,
                    phase: HgPhaseFunction { g: m.g() },
                }
            }
        }
    }

    /// The transmittance exp(−σ_t·|d|·t_max) of the segment `t ∈ [0, t_max]` of a ray of
    /// direction `d`, when the medium's σ_t is the same everywhere (homogeneous): what ratio
    /// tracking estimates, without its noise. `None` for media that vary in space.
    #[inline]
    pub fn uniform_transmittance(
        &self,
        d: Vec3,
        t_max: f32,
        lambda: Option<&SampledWavelengths>,
    ) -> Option<SampledSpectrum> {
        match self {
            Medium::Homogeneous(m) => Some(majorant_transmittance(
                m.sigma_t(lambda),
                t_max * d.length(),
            )),
            Medium::Grid(_) => None,
        }
    }

    /// The majorant segments of the ray `o + t·d` (`d` unit length) for `t ∈ [0, t_max]` (see
    /// the module's contract).
    #[inline]
    pub fn sample_ray(
        &self,
        o: Vec3,
        d: Vec3,
        t_max: f32,
        lambda: Option<&SampledWavelengths>,
    ) -> MajorantIter<'_> {
        match self {
            Medium::Homogeneous(m) => MajorantIter::Single(Some(MajorantSegment {
                t_min: 0.0,
                t_max,
                sigma_maj: m.sigma_t(lambda),
            })),
            Medium::Grid(m) => MajorantIter::Grid(m.majorants(&Ray::new(o, d), t_max, lambda)),
        }
    }
}

/// exp(−σ·dt) lane-wise, with an infinite `dt` taken as the largest float so that a zero
/// σ gives 1 rather than NaN.
#[inline]
pub fn majorant_transmittance(sigma: SampledSpectrum, dt: f32) -> SampledSpectrum {
    let dt = if dt.is_finite() { dt } else { f32::MAX };
    (-sigma * dt).map(f32::exp)
}

/// Delta tracking against the majorant along the ray `o + t·d` (`d` need not be unit length;
/// `t_max` is in its units), pbrt-v4's `SampleT_maj`. Tentative collisions are drawn with
/// density σ_maj[h]·exp(−σ_maj[h]·t) per segment (h = `hero`, the lane that drives sampling),
/// the first with `u`, the others with `rng`. At each, `callback(p, properties, σ_maj, T_maj,
/// rng)` gets the majorant transmittance T_maj = exp(−σ_maj·Δt) since the previous collision
/// (and the same generator, for its own choices); it returns false to stop. Returns T_maj from the last collision to the end of the ray (or 1
/// when the callback stopped).
#[allow(clippy::too_many_arguments)]
pub fn sample_t_maj<F>(
    medium: &Medium,
    o: Vec3,
    d: Vec3,
    t_max: f32,
    mut u: f32,
    rng: &mut Pcg32,
    lambda: Option<&SampledWavelengths>,
    hero: usize,
    mut callback: F,
) -> SampledSpectrum
where
    F: FnMut(Vec3, &MediumProperties, SampledSpectrum, SampledSpectrum, &mut Pcg32) -> bool,
{
    // Work with a unit direction: t becomes a distance.
    let len = d.length();
    let t_max = t_max * len;
    let d = d / len;
    let mut t_maj = SampledSpectrum::ONE;
    for seg in medium.sample_ray(o, d, t_max, lambda) {
        let s = seg.sigma_maj[hero];
        if s == 0.0 {
            // Nothing to collide with: the segment only attenuates (by exactly 1 in the hero
            // lane).
            t_maj *= majorant_transmittance(seg.sigma_maj, seg.t_max - seg.t_min);
            continue;
        }
        let mut t_min = seg.t_min;
        loop {
            // t = t_min − ln(1 − u)/σ_maj: an exponential step.
            let t = t_min - (1.0 - u).ln() / s;
            u = rng.uniform();
            if t < seg.t_max {
                t_maj *= majorant_transmittance(seg.sigma_maj, t - t_min);
                let p = o + d * t;
                let mp = medium.sample_point(p, lambda);
                if !callback(p, &mp, seg.sigma_maj, t_maj, rng) {
                    return SampledSpectrum::ONE;
                }
                t_maj = SampledSpectrum::ONE;
                t_min = t;
            } else {
                t_maj *= majorant_transmittance(seg.sigma_maj, seg.t_max - t_min);
                break;
            }
        }
    }
    t_maj
}

#[cfg(test)]
mod tests;
