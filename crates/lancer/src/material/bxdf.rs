//! BxDFs in the local shading frame (normal = +z) and the [`Bsdf`] that places them in the world.
//!
//! Each kind of scattering is a small `Copy` struct implementing [`Scatter`] (in
//! [`super::diffuse`], [`super::conductor`], [`super::dielectric`], [`super::layered`]); the
//! closed set of them is the enum [`BxDF`], matched per call: no allocation and no dynamic
//! dispatch per ray.

use super::conductor::ConductorBxdf;
use super::dielectric::{DielectricBxdf, ThinDielectricBxdf};
use super::diffuse::{DiffuseBxdf, DiffuseTransmissionBxdf};
use super::layered::{CoatedConductorBxdf, CoatedDiffuseBxdf};
use crate::math::{Frame, Rgb, Vec2, Vec3};

/// Whether radiance (from the camera) or importance (from lights) is carried: refraction scales
/// radiance by 1/η², not importance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Paths traced from the camera.
    Radiance,
    /// Paths traced from lights.
    Importance,
}

impl TransportMode {
    /// The adjoint mode: what a path traced the other way carries.
    #[inline]
    pub fn flip(self) -> TransportMode {
        match self {
            TransportMode::Radiance => TransportMode::Importance,
            TransportMode::Importance => TransportMode::Radiance,
        }
    }
}

/// What kind of scattering a BxDF (or a sampled lobe) does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BxdfFlags(pub u8);

impl BxdfFlags {
    /// No scattering at all.
    pub const NONE: BxdfFlags = BxdfFlags(0);
    /// Scatters into the hemisphere of the normal.
    pub const REFLECTION: BxdfFlags = BxdfFlags(1);
    /// Scatters through the surface.
    pub const TRANSMISSION: BxdfFlags = BxdfFlags(2);
    /// A smooth lobe with a density.
    pub const DIFFUSE: BxdfFlags = BxdfFlags(4);
    /// A rough lobe with a density.
    pub const GLOSSY: BxdfFlags = BxdfFlags(8);
    /// A Dirac delta: only sampling can find it.
    pub const SPECULAR: BxdfFlags = BxdfFlags(16);

    /// True when any flag of `o` is set.
    #[inline]
    pub fn has(self, o: BxdfFlags) -> bool {
        self.0 & o.0 != 0
    }

    /// True for a perfectly specular lobe.
    #[inline]
    pub fn is_specular(self) -> bool {
        self.has(Self::SPECULAR)
    }

    /// True when some lobe has a density that light sampling can evaluate.
    #[inline]
    pub fn is_non_specular(self) -> bool {
        self.has(BxdfFlags(Self::DIFFUSE.0 | Self::GLOSSY.0))
    }

    /// True when some lobe reflects.
    #[inline]
    pub fn is_reflection(self) -> bool {
        self.has(Self::REFLECTION)
    }

    /// True when some lobe transmits.
    #[inline]
    pub fn is_transmission(self) -> bool {
        self.has(Self::TRANSMISSION)
    }

    /// True when some lobe is diffuse.
    #[inline]
    pub fn is_diffuse(self) -> bool {
        self.has(Self::DIFFUSE)
    }

    /// True when some lobe is glossy.
    #[inline]
    pub fn is_glossy(self) -> bool {
        self.has(Self::GLOSSY)
    }
}

impl std::ops::BitOr for BxdfFlags {
    type Output = BxdfFlags;
    fn bitor(self, o: BxdfFlags) -> BxdfFlags {
        BxdfFlags(self.0 | o.0)
    }
}

impl std::ops::BitOrAssign for BxdfFlags {
    fn bitor_assign(&mut self, o: BxdfFlags) {
        self.0 |= o.0;
    }
}

/// Which halves of the sphere a sampling or density query may consider (pbrt's
/// `BxDFReflTransFlags`): layered BSDFs ask an interface for its transmission alone, say.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReflTrans(u8);

impl ReflTrans {
    /// Only reflection.
    pub const REFLECTION: ReflTrans = ReflTrans(1);
    /// Only transmission.
    pub const TRANSMISSION: ReflTrans = ReflTrans(2);
    /// Both.
    pub const ALL: ReflTrans = ReflTrans(3);

    /// Reflection is allowed.
    #[inline]
    pub fn reflection(self) -> bool {
        self.0 & 1 != 0
    }

    /// Transmission is allowed.
    #[inline]
    pub fn transmission(self) -> bool {
        self.0 & 2 != 0
    }
}

/// A sampled scattering direction.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// BSDF value f(wo, wi) (for layered BSDFs, an unbiased estimate of f·pdf-ratio; see
    /// `pdf_is_proportional`).
    pub f: Rgb,
    /// The sampled incident direction.
    pub wi: Vec3,
    /// Its density (solid angle); for a specular lobe, the discrete probability of the lobe.
    pub pdf: f32,
    /// The lobe sampled.
    pub flags: BxdfFlags,
    /// Relative index of refraction crossed (1 for reflection).
    pub eta: f32,
    /// True when `f/pdf` is a correct weight but `pdf` is not the density of `wi` (layered
    /// BSDFs, sampled by a random walk): MIS must then ask [`Bsdf::pdf`] instead.
    pub pdf_is_proportional: bool,
}

impl BsdfSample {
    /// A sample with exact density and no refraction.
    #[inline]
    pub fn new(f: Rgb, wi: Vec3, pdf: f32, flags: BxdfFlags) -> BsdfSample {
        BsdfSample {
            f,
            wi,
            pdf,
            flags,
            eta: 1.0,
            pdf_is_proportional: false,
        }
    }

    /// True when the sampled lobe reflects.
    #[inline]
    pub fn is_reflection(&self) -> bool {
        self.flags.is_reflection()
    }

    /// True when the sampled lobe transmits.
    #[inline]
    pub fn is_transmission(&self) -> bool {
        self.flags.is_transmission()
    }

    /// True when the sampled lobe is a delta.
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.flags.is_specular()
    }

    /// A sample a random walk can continue from: non-zero value and density, and a direction
    /// off the surface plane.
    #[inline]
    pub(crate) fn is_usable(&self) -> bool {
        self.f != Rgb::ZERO && self.pdf > 0.0 && self.wi.z != 0.0
    }
}

/// cos θ of a local direction.
#[inline]
pub(crate) fn cos_theta(w: Vec3) -> f32 {
    w.z
}

/// |cos θ| of a local direction.
#[inline]
pub(crate) fn abs_cos_theta(w: Vec3) -> f32 {
    w.z.abs()
}

/// True when both directions are on the same side of the surface.
#[inline]
pub(crate) fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}

/// The interface every local scattering function implements (pbrt-v4's BxDF concept).
/// Directions are local (z = shading normal), both point away from the surface.
pub trait Scatter {
    /// The kinds of lobes present.
    fn flags(&self) -> BxdfFlags;

    /// f(wo, wi); zero for specular lobes.
    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb;

    /// Samples `wi` given `wo`, with `uc` choosing a lobe and `u` the direction within it,
    /// restricted to the halves `mask` allows.
    fn sample_f(
        &self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample>;

    /// Density with which [`Scatter::sample_f`] (with the same `mask`) returns `wi`; zero for
    /// specular lobes.
    fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode, mask: ReflTrans) -> f32;
}

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
        }
    };
}

impl BxDF {
    /// Lambert with albedo `r`.
    #[inline]
    pub fn diffuse(r: Rgb) -> BxDF {
        BxDF::Diffuse(DiffuseBxdf { r: r.into() })
    }

    /// The kinds of lobes this BxDF has.
    pub fn flags(&self) -> BxdfFlags {
        dispatch!(self, b => b.flags())
    }

    /// f(wo, wi) for a pair of local directions (zero for specular lobes).
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
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
            BxDF::Diffuse(_) | BxDF::ThinDielectric(_) | BxDF::DiffuseTransmission(_) => {}
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
    pub fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Rgb {
        let (wo, wi) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if wo.z == 0.0 {
            return Rgb::ZERO;
        }
        self.bxdf.f(wo, wi, mode)
    }

    /// Density of sampling world-space `wi` given `wo`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        let (wo, wi) = (self.frame.to_local(wo), self.frame.to_local(wi));
        if wo.z == 0.0 {
            return 0.0;
        }
        self.bxdf.pdf(wo, wi, mode)
    }

    /// Samples a world-space incident direction.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        let wo_l = self.frame.to_local(wo);
        if wo_l.z == 0.0 {
            return None;
        }
        let mut s = self.bxdf.sample_f(wo_l, uc, u, mode)?;
        if s.pdf <= 0.0 || !s.f.is_finite() || s.f == Rgb::ZERO || s.wi.z == 0.0 {
            return None;
        }
        s.wi = self.frame.from_local(s.wi);
        Some(s)
    }
}
