//! BxDFs in the local shading frame (normal = +z) and the [`Bsdf`] that places them in the world.
//!
//! Each kind of scattering is a small `Copy` struct implementing [`Scatter`] (in
//! [`super::diffuse`], [`super::conductor`], [`super::dielectric`], [`super::layered`]); the
//! closed set of them is the enum [`BxDF`], matched per call: no allocation and no dynamic
//! dispatch per ray.

use super::bssrdf::NormalizedFresnelBxdf;
use super::conductor::ConductorBxdf;
use super::dielectric::{DielectricBxdf, ThinDielectricBxdf};
use super::diffuse::{DiffuseBxdf, DiffuseTransmissionBxdf};
use super::hair::HairBxdf;
use super::layered::{CoatedConductorBxdf, CoatedDiffuseBxdf};
use super::measured::MeasuredBxdf;
use super::scatter::{BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode};
use crate::math::{Frame, SampledSpectrum, Vec2, Vec3};

/// A BxDF in its local frame: directions have the shading normal as +z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BxDF {
    /// Lambertian reflection.
    Diffuse(DiffuseBxdf),
    /// A conductor: smooth mirror or rough microfacet reflection with complex Fresnel.
    Conductor(ConductorBxdf),
    /// A dielectric interface: smooth or rough reflection and refraction.
    Dielectric(DielectricBxdf),
    /// A thin dielectric slab: specular reflection and straight-through transmission.
    ThinDielectric(ThinDielectricBxdf),
    /// Lambertian reflection and Lambertian transmission.
    DiffuseTransmission(DiffuseTransmissionBxdf),
    /// A dielectric coating over a diffuse base, evaluated by random walks.
    CoatedDiffuse(CoatedDiffuseBxdf),
    /// A dielectric coating over a conductor, evaluated by random walks.
    CoatedConductor(CoatedConductorBxdf),
    /// A hair fibre (pbrt-v4's `HairBxDF`).
    Hair(HairBxdf),
    /// The exit lobe of a BSSRDF.
    NormalizedFresnel(NormalizedFresnelBxdf),
    /// A tabulated BRDF (pbrt-v4's `MeasuredBxDF`).
    Measured(MeasuredBxdf),
}

/// Calls `$body` with `$b` bound to the variant's inner BxDF, whatever the variant.
macro_rules! dispatch {
    ($self:expr, $b:ident => $body:expr) => {
        match $self {
            BxDF::Diffuse($b) => $body,
            BxDF::Conductor($b) => $body,
            BxDF::Dielectric($b) => $body,
            BxDF::ThinDielectric($b) => $body,
            BxDF::DiffuseTransmission($b) => $body,
            BxDF::CoatedDiffuse($b) => $body,
            BxDF::CoatedConductor($b) => $body,
            BxDF::Hair($b) => $body,
            BxDF::NormalizedFresnel($b) => $body,
            BxDF::Measured($b) => $body,
        }
    };
}

impl BxDF {
    /// Lambert with albedo `r`.
    #[inline]
    pub fn diffuse(r: SampledSpectrum) -> BxDF {
        BxDF::Diffuse(DiffuseBxdf { r })
    }

    /// True for the BxDFs whose f and pdf are random-walk estimates (the layered ones), far
    /// dearer to evaluate than a shadow ray.
    #[inline]
    pub fn is_stochastic(&self) -> bool {
        matches!(self, BxDF::CoatedDiffuse(_) | BxDF::CoatedConductor(_))
    }

    /// The kinds of lobes this BxDF has.
    pub fn flags(&self) -> BxdfFlags {
        dispatch!(self, b => b.flags())
    }

    /// f(wo, wi) for a pair of local directions (zero for specular lobes).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        dispatch!(self, b => b.f(wo, wi, mode))
    }

    /// Density of [`BxDF::sample_f`] choosing `wi` (zero for specular lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        dispatch!(self, b => b.pdf(wo, wi, mode, ReflTrans::ALL))
    }

    /// Samples an incident direction for outgoing `wo`, with `uc` choosing a lobe and `u` the
    /// direction within it.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        // A visible normal drawn at the very edge of its disk can lie in the surface plane,
        // where D = 0: such a sample has no density and is no sample at all.
        dispatch!(self, b => b.sample_f(wo, uc, u, mode, ReflTrans::ALL)).filter(|s| s.pdf > 0.0)
    }

    /// pbrt-v4's regularisation: widens near-specular microfacet lobes (see
    /// [`super::TrowbridgeReitz::regularize`]); other BxDFs are unchanged.
    pub fn regularize(&mut self) {
        match self {
            BxDF::Conductor(c) => c.distrib.regularize(),
            BxDF::Dielectric(d) => d.distrib.regularize(),
            BxDF::CoatedDiffuse(l) => l.top.distrib.regularize(),
            BxDF::CoatedConductor(l) => {
                l.top.distrib.regularize();
                l.bottom.distrib.regularize();
            }
            BxDF::Diffuse(_)
            | BxDF::ThinDielectric(_)
            | BxDF::DiffuseTransmission(_)
            | BxDF::Hair(_)
            | BxDF::NormalizedFresnel(_)
            | BxDF::Measured(_) => {}
        }
    }
}

/// A BxDF placed at a surface point: its shading frame and the geometric normal, used to keep
/// light from leaking through surfaces whose shading normals disagree with their geometry.
#[derive(Clone, Copy, Debug)]
pub struct Bsdf {
    /// The local scattering function.
    pub bxdf: BxDF,
    /// Shading frame (z = shading normal).
    pub frame: Frame,
}

impl Bsdf {
    /// A BSDF with shading normal `ns` and tangent `dpdus`.
    pub fn new(bxdf: BxDF, ns: Vec3, dpdus: Vec3) -> Bsdf {
        Bsdf {
            bxdf,
            frame: Frame::from_xz(dpdus, ns),
        }
    }

    /// Lobe kinds.
    pub fn flags(&self) -> BxdfFlags {
        self.bxdf.flags()
    }

    /// f(wo, wi) for world-space directions.
    #[inline]
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        self.f_lo(self.frame.to_local(wo), self.frame.to_local(wi), mode)
    }

    /// [`Bsdf::f`] with `wo` and `wi` already in the local frame (`frame.to_local`), for
    /// callers that ask f, pdf and a sample for the same directions and transform them once.
    #[inline]
    pub fn f_lo(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if wo.z == 0.0 {
            return SampledSpectrum::ZERO;
        }
        // Lambert, the commonest BxDF, inline (see `sample_f_lo`).
        match &self.bxdf {
            BxDF::Diffuse(d) => d.f(wo, wi, mode),
            b => b.f(wo, wi, mode),
        }
    }

    /// Density of sampling world-space `wi` given `wo`.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        self.pdf_lo(self.frame.to_local(wo), self.frame.to_local(wi), mode)
    }

    /// [`Bsdf::pdf`] with `wo` and `wi` in the local frame.
    #[inline]
    pub fn pdf_lo(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        if wo.z == 0.0 {
            return 0.0;
        }
        match &self.bxdf {
            BxDF::Diffuse(d) => d.pdf(wo, wi, mode, ReflTrans::ALL),
            b => b.pdf(wo, wi, mode),
        }
    }

    /// Samples a world-space incident direction.
    #[inline]
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        self.sample_f_lo(self.frame.to_local(wo), uc, u, mode)
    }

    /// [`Bsdf::sample_f`] with `wo` in the local frame (the sample's `wi` is in the world).
    /// Always inlined: out of line, its sample comes back through memory (a stall per bounce).
    #[inline(always)]
    pub fn sample_f_lo(
        &self,
        wo_l: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        if wo_l.z == 0.0 {
            return None;
        }
        // Lambert, the commonest BxDF, inline: through the out-of-line dispatch its sample came
        // back in memory, written in narrow stores and read in wide loads (a store-forwarding
        // stall per bounce). `BxDF::sample_f`'s pdf > 0 filter is the test below.
        let mut s = match &self.bxdf {
            BxDF::Diffuse(d) => d.sample_f(wo_l, uc, u, mode, ReflTrans::ALL)?,
            b => b.sample_f(wo_l, uc, u, mode)?,
        };
        if s.pdf <= 0.0 || !s.f.is_finite() || s.f == SampledSpectrum::ZERO || s.wi.z == 0.0 {
            return None;
        }
        s.wi = self.frame.from_local(s.wi);
        Some(s)
    }
}
