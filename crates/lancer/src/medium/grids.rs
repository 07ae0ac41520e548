//! The heterogeneous media as one closed set: their descriptions as a scene reader makes them
//! ([`GridMediumDesc`]), the media ready to render ([`GridMedium`]), and the majorant
//! segments of a ray through any of them ([`GridMajorants`]).

use super::cloud::{CloudDesc, CloudMedium};
use super::coeff::PointProperties;
use super::majorant::{DdaMajorantIterator, MajorantSegment};
use super::nanovdb::{NanoVdbDesc, NanoVdbMedium};
use super::rgb_grid::{RgbGridDesc, RgbGridMedium};
use super::uniform_grid::{UniformGridDesc, UniformGridMedium};
use crate::math::Vec3;
use crate::ray::Ray;
use crate::spectrum::sampled::SampledWavelengths;

/// A heterogeneous medium as described by a scene (pbrt-v4's `uniformgrid`, `rgbgrid`, `cloud`
/// and `nanovdb`).
// A scene holds a handful of media, each built once: the cloud's smaller size is not worth a box.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub enum GridMediumDesc {
    /// `uniformgrid`.
    Uniform(UniformGridDesc),
    /// `rgbgrid`.
    Rgb(RgbGridDesc),
    /// `cloud`.
    Cloud(CloudDesc),
    /// `nanovdb`.
    NanoVdb(NanoVdbDesc),
}

impl GridMediumDesc {
    /// pbrt-v4's name of the medium type.
    pub fn kind(&self) -> &'static str {
        match self {
            GridMediumDesc::Uniform(_) => "uniformgrid",
            GridMediumDesc::Rgb(_) => "rgbgrid",
            GridMediumDesc::Cloud(_) => "cloud",
            GridMediumDesc::NanoVdb(_) => "nanovdb",
        }
    }
}

/// A heterogeneous medium ready to render.
// Few media per scene, read in the hot loop: kept inline rather than boxed.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum GridMedium {
    /// `uniformgrid`.
    Uniform(UniformGridMedium),
    /// `rgbgrid`.
    Rgb(RgbGridMedium),
    /// `cloud`.
    Cloud(CloudMedium),
    /// `nanovdb`.
    NanoVdb(NanoVdbMedium),
}

/// The majorant segments of a ray through a [`GridMedium`].
#[derive(Clone, Debug)]
pub enum GridMajorants<'a> {
    /// One segment per majorant-grid cell.
    Dda(DdaMajorantIterator<'a>),
    /// At most one segment (the cloud's box).
    Single(std::option::IntoIter<MajorantSegment>),
}

impl Iterator for GridMajorants<'_> {
    type Item = MajorantSegment;
    #[inline]
    fn next(&mut self) -> Option<MajorantSegment> {
        match self {
            GridMajorants::Dda(it) => it.next(),
            GridMajorants::Single(it) => it.next(),
        }
    }
}

impl GridMedium {
    /// Prepares a described medium (spectra, majorant grids).
    pub fn new(desc: GridMediumDesc) -> GridMedium {
        match desc {
            GridMediumDesc::Uniform(d) => GridMedium::Uniform(UniformGridMedium::new(d)),
            GridMediumDesc::Rgb(d) => GridMedium::Rgb(RgbGridMedium::new(d)),
            GridMediumDesc::Cloud(d) => GridMedium::Cloud(CloudMedium::new(d)),
            GridMediumDesc::NanoVdb(d) => GridMedium::NanoVdb(NanoVdbMedium::new(d)),
        }
    }

    /// pbrt-v4's name of the medium type.
    pub fn kind(&self) -> &'static str {
        match self {
            GridMedium::Uniform(_) => "uniformgrid",
            GridMedium::Rgb(_) => "rgbgrid",
            GridMedium::Cloud(_) => "cloud",
            GridMedium::NanoVdb(_) => "nanovdb",
        }
    }

    /// The Henyey–Greenstein asymmetry g of its phase function.
    pub fn g(&self) -> f32 {
        match self {
            GridMedium::Uniform(m) => m.g(),
            GridMedium::Rgb(m) => m.g(),
            GridMedium::Cloud(m) => m.g(),
            GridMedium::NanoVdb(m) => m.g(),
        }
    }

    /// True if it emits light.
    pub fn is_emissive(&self) -> bool {
        match self {
            GridMedium::Uniform(m) => m.is_emissive(),
            GridMedium::Rgb(m) => m.is_emissive(),
            GridMedium::Cloud(_) => false,
            GridMedium::NanoVdb(m) => m.is_emissive(),
        }
    }

    /// Bytes held by its grids (0 for the procedural cloud).
    pub fn bytes(&self) -> usize {
        match self {
            GridMedium::Uniform(m) => m.bytes(),
            GridMedium::Rgb(m) => m.bytes(),
            GridMedium::Cloud(_) => 0,
            GridMedium::NanoVdb(m) => m.bytes(),
        }
    }

    /// σ_a, σ_s and L_e at render-space point `p` (pbrt-v4's `SamplePoint`); `lambda` is
    /// `None` in RGB mode.
    #[inline]
    pub fn properties(&self, p: Vec3, lambda: Option<&SampledWavelengths>) -> PointProperties {
        match self {
            GridMedium::Uniform(m) => m.properties(p, lambda),
            GridMedium::Rgb(m) => m.properties(p, lambda),
            GridMedium::Cloud(m) => m.properties(p, lambda),
            GridMedium::NanoVdb(m) => m.properties(p, lambda),
        }
    }

    /// The majorant segments of render-space `ray` over t ∈ [0, t_max] (pbrt-v4's
    /// `SampleRay`), in the ray's own parameter (pbrt-v4 normalises `ray.d` first and scales
    /// `t_max` to match; either way works).
    #[inline]
    pub fn majorants(
        &self,
        ray: &Ray,
        t_max: f32,
        lambda: Option<&SampledWavelengths>,
    ) -> GridMajorants<'_> {
        match self {
            GridMedium::Uniform(m) => GridMajorants::Dda(m.majorants(ray, t_max, lambda)),
            GridMedium::Rgb(m) => GridMajorants::Dda(m.majorants(ray, t_max, lambda)),
            GridMedium::Cloud(m) => {
                GridMajorants::Single(m.majorant(ray, t_max, lambda).into_iter())
            }
            GridMedium::NanoVdb(m) => GridMajorants::Dda(m.majorants(ray, t_max, lambda)),
        }
    }
}
