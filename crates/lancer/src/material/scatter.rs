//! The vocabulary every BxDF speaks: the [`Scatter`] interface, lobe flags, hemisphere masks,
//! sampled directions, transport modes and the local-frame trigonometry (a leaf module: the
//! BxDF files and the enum listing them all depend on it, it on none of them).

use crate::math::{SampledSpectrum, Vec2, Vec3};

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
    pub f: SampledSpectrum,
    /// The sampled incident direction.
    pub wi: Vec3,
    /// Its density (solid angle); for a specular lobe, the discrete probability of the lobe.
    pub pdf: f32,
    /// The lobe sampled.
    pub flags: BxdfFlags,
    /// Relative index of refraction crossed (1 for reflection).
    pub eta: f32,
    /// True when `f/pdf` is a correct weight but `pdf` is not the density of `wi` (layered
    /// BSDFs, sampled by a random walk): MIS must then ask [`Bsdf::pdf`](super::Bsdf::pdf) instead.
    pub pdf_is_proportional: bool,
}

impl BsdfSample {
    /// A sample with exact density and no refraction.
    #[inline]
    pub fn new(f: SampledSpectrum, wi: Vec3, pdf: f32, flags: BxdfFlags) -> BsdfSample {
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
        self.f != SampledSpectrum::ZERO && self.pdf > 0.0 && self.wi.z != 0.0
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
    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum;

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

    /// `(f(wo, wi), pdf(wo, wi, mask))` together, for callers that need both of one pair (the
    /// layered walks' connections through an interface); a BxDF whose two share work
    /// overrides it, with the same values.
    #[inline]
    fn f_pdf(
        &self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> (SampledSpectrum, f32) {
        (self.f(wo, wi, mode), self.pdf(wo, wi, mode, mask))
    }
}
