//! BxDFs in the local shading frame (normal = +z) and the [`Bsdf`] that places them in the world.

use super::fresnel::{fresnel_complex, fresnel_dielectric, refract};
use crate::math::{Frame, INV_PI, Rgb, Vec2, Vec3};
use crate::sampling::sample_cosine_hemisphere;

/// Whether radiance (from the camera) or importance (from lights) is carried: refraction scales
/// radiance by 1/η², not importance.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TransportMode {
    /// Paths traced from the camera.
    Radiance,
    /// Paths traced from lights.
    Importance,
}

/// What kind of scattering a BxDF (or a sampled lobe) does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BxdfFlags(pub u8);

impl BxdfFlags {
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
}

impl std::ops::BitOr for BxdfFlags {
    type Output = BxdfFlags;
    fn bitor(self, o: BxdfFlags) -> BxdfFlags {
        BxdfFlags(self.0 | o.0)
    }
}

/// A sampled scattering direction.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    /// BSDF value f(wo, wi).
    pub f: Rgb,
    /// The sampled incident direction.
    pub wi: Vec3,
    /// Its density (solid angle); for a specular lobe, the discrete probability of the lobe.
    pub pdf: f32,
    /// The lobe sampled.
    pub flags: BxdfFlags,
    /// Relative index of refraction crossed (1 for reflection).
    pub eta: f32,
}

/// A BxDF in its local frame: directions have the shading normal as +z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BxDF {
    /// Lambert: f = ρ/π.
    Diffuse {
        /// Albedo.
        r: Rgb,
    },
    /// A perfectly smooth conductor: a mirror whose reflectance is the Fresnel term of
    /// `eta + i·k`.
    Conductor {
        /// Real index, per channel.
        eta: Rgb,
        /// Absorption, per channel.
        k: Rgb,
    },
    /// A perfectly smooth dielectric: Fresnel-weighted specular reflection and refraction.
    Dielectric {
        /// Relative index inside/outside.
        eta: f32,
    },
}

#[inline]
fn cos_theta(w: Vec3) -> f32 {
    w.z
}

#[inline]
fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}

impl BxDF {
    /// The kinds of lobes this BxDF has.
    pub fn flags(&self) -> BxdfFlags {
        match self {
            BxDF::Diffuse { r } => {
                if *r == Rgb::ZERO {
                    BxdfFlags(0)
                } else {
                    BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE
                }
            }
            BxDF::Conductor { .. } => BxdfFlags::REFLECTION | BxdfFlags::SPECULAR,
            BxDF::Dielectric { eta } => {
                if *eta == 1.0 {
                    BxdfFlags::TRANSMISSION | BxdfFlags::SPECULAR
                } else {
                    BxdfFlags::REFLECTION | BxdfFlags::TRANSMISSION | BxdfFlags::SPECULAR
                }
            }
        }
    }

    /// f(wo, wi) for a pair of local directions (zero for specular lobes).
    pub fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> Rgb {
        match self {
            BxDF::Diffuse { r } => {
                if same_hemisphere(wo, wi) {
                    *r * INV_PI
                } else {
                    Rgb::ZERO
                }
            }
            BxDF::Conductor { .. } | BxDF::Dielectric { .. } => Rgb::ZERO,
        }
    }

    /// Density of [`BxDF::sample_f`] choosing `wi` (zero for specular lobes).
    pub fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> f32 {
        match self {
            BxDF::Diffuse { .. } => {
                if same_hemisphere(wo, wi) {
                    wi.z.abs() * INV_PI
                } else {
                    0.0
                }
            }
            BxDF::Conductor { .. } | BxDF::Dielectric { .. } => 0.0,
        }
    }

    /// Samples an incident direction for outgoing `wo`, with `uc` choosing a lobe and `u` the
    /// direction within it.
    pub fn sample_f(&self, wo: Vec3, uc: f32, u: Vec2, mode: TransportMode) -> Option<BsdfSample> {
        match self {
            BxDF::Diffuse { r } => {
                if *r == Rgb::ZERO {
                    return None;
                }
                let mut wi = sample_cosine_hemisphere(u);
                if wo.z < 0.0 {
                    wi.z = -wi.z;
                }
                let pdf = wi.z.abs() * INV_PI;
                (pdf > 0.0).then_some(BsdfSample {
                    f: *r * INV_PI,
                    wi,
                    pdf,
                    flags: BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE,
                    eta: 1.0,
                })
            }
            BxDF::Conductor { eta, k } => {
                // Perfect mirror: wi = (−wo.x, −wo.y, wo.z); f = F/|cos θi| so that the
                // estimator f·|cos θ|/pdf returns the Fresnel reflectance.
                let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                let c = cos_theta(wi).abs();
                if c == 0.0 {
                    return None;
                }
                Some(BsdfSample {
                    f: fresnel_complex(c, *eta, *k) / c,
                    wi,
                    pdf: 1.0,
                    flags: BxdfFlags::REFLECTION | BxdfFlags::SPECULAR,
                    eta: 1.0,
                })
            }
            BxDF::Dielectric { eta } => {
                let r = fresnel_dielectric(cos_theta(wo), *eta);
                let t = 1.0 - r;
                if uc < r / (r + t) {
                    let wi = Vec3::new(-wo.x, -wo.y, wo.z);
                    let c = wi.z.abs();
                    if c == 0.0 {
                        return None;
                    }
                    Some(BsdfSample {
                        f: Rgb::splat(r / c),
                        wi,
                        pdf: r / (r + t),
                        flags: BxdfFlags::REFLECTION | BxdfFlags::SPECULAR,
                        eta: 1.0,
                    })
                } else {
                    let (wi, etap) = refract(wo, Vec3::Z, *eta)?;
                    let c = wi.z.abs();
                    if c == 0.0 {
                        return None;
                    }
                    let mut ft = t / c;
                    // Radiance is compressed into a smaller solid angle when entering a denser
                    // medium: L scales by 1/η².
                    if mode == TransportMode::Radiance {
                        ft /= etap * etap;
                    }
                    Some(BsdfSample {
                        f: Rgb::splat(ft),
                        wi,
                        pdf: t / (r + t),
                        flags: BxdfFlags::TRANSMISSION | BxdfFlags::SPECULAR,
                        eta: etap,
                    })
                }
            }
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
        if s.pdf <= 0.0 || !s.f.is_finite() || s.wi.z == 0.0 {
            return None;
        }
        s.wi = self.frame.from_local(s.wi);
        Some(s)
    }
}
