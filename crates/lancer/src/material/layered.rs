//! Layered BSDFs (pbrt-v4's `LayeredBxDF`): a dielectric interface on top of another BxDF,
//! separated by a slab of thickness `thickness` that may hold a scattering medium. Nothing
//! about the light between the layers has a closed form, so f, the sampling and the density
//! are all estimated by random walks between the two interfaces (Guo et al. 2018, "Position-
//! free Monte Carlo simulation for arbitrary layered BSDFs").
//!
//! Each evaluation draws its random numbers from a [`Pcg32`] seeded by hashing its arguments,
//! as pbrt seeds its `RNG` with `Hash(seed, wo)`, `Hash(wi)`: the same query always returns
//! the same estimate, and nothing is allocated.
//!
//! Both sides of the surface are treated alike (pbrt's `twoSided = true`): a direction below
//! the surface is mirrored to above first, so light always enters through the top.

use super::conductor::ConductorBxdf;
use super::dielectric::DielectricBxdf;
use super::diffuse::DiffuseBxdf;
use super::scatter::{
    BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode, abs_cos_theta, same_hemisphere,
};
use crate::math::{INV_4PI, SampledSpectrum, Vec2, Vec3, lerp};
use crate::sampling::{
    Pcg32, hash_u64, henyey_greenstein, power_heuristic, sample_exponential,
    sample_henyey_greenstein,
};

/// A dielectric coating over a diffuse base (pbrt-v4's `coateddiffuse`).
pub type CoatedDiffuseBxdf = LayeredBxdf<DiffuseBxdf>;

/// A dielectric coating over a conductor (pbrt-v4's `coatedconductor`).
pub type CoatedConductorBxdf = LayeredBxdf<ConductorBxdf>;

/// A dielectric `top` over `bottom`, with a homogeneous medium of unit extinction, single-
/// scattering albedo `albedo` and Henyey–Greenstein asymmetry `g` between them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayeredBxdf<B> {
    /// The coating.
    pub top: DielectricBxdf,
    /// The base.
    pub bottom: B,
    /// Thickness of the slab, in units of the medium's mean free path.
    pub thickness: f32,
    /// Henyey–Greenstein asymmetry of the medium.
    pub g: f32,
    /// Single-scattering albedo of the medium (zero: the slab only absorbs, by e^(−d/|cos θ|));
    /// packed, as every colour of a BxDF.
    pub albedo: SampledSpectrum,
    /// Maximum number of scattering events in one random walk.
    pub max_depth: u32,
    /// Number of random walks averaged per evaluation.
    pub n_samples: u32,
}

/// One of the two interfaces of a layered BxDF, chosen during a walk.
enum Side<'a, B> {
    Top(&'a DielectricBxdf),
    Bottom(&'a B),
}

// Written out because the derive would demand `B: Copy` for what is only a reference.
impl<B> Clone for Side<'_, B> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<B> Copy for Side<'_, B> {}

impl<B: Scatter> Side<'_, B> {
    #[inline]
    fn flags(self) -> BxdfFlags {
        match self {
            Side::Top(t) => t.flags(),
            Side::Bottom(b) => b.flags(),
        }
    }

    #[inline]
    fn f(self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        match self {
            Side::Top(t) => t.f(wo, wi, mode),
            Side::Bottom(b) => b.f(wo, wi, mode),
        }
    }

    #[inline]
    fn sample_f(
        self,
        wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        match self {
            Side::Top(t) => t.sample_f(wo, uc, u, mode, mask),
            Side::Bottom(b) => b.sample_f(wo, uc, u, mode, mask),
        }
    }

    #[inline]
    fn pdf(self, wo: Vec3, wi: Vec3, mode: TransportMode, mask: ReflTrans) -> f32 {
        match self {
            Side::Top(t) => t.pdf(wo, wi, mode, mask),
            Side::Bottom(b) => b.pdf(wo, wi, mode, mask),
        }
    }

    #[inline]
    fn f_pdf(
        self,
        wo: Vec3,
        wi: Vec3,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> (SampledSpectrum, f32) {
        match self {
            Side::Top(t) => t.f_pdf(wo, wi, mode, mask),
            Side::Bottom(b) => b.f_pdf(wo, wi, mode, mask),
        }
    }
}

/// Transmittance through a vertical distance `dz` of the unit-extinction slab along `w`:
/// Tr = e^(−|dz / cos θ|) (1 when `dz` is zero).
#[inline]
fn tr(dz: f32, w: Vec3) -> f32 {
    if dz.abs() <= f32::MIN_POSITIVE {
        1.0
    } else {
        (-(dz / w.z).abs()).exp()
    }
}

/// A 64-bit hash of the bit patterns of some floats, to seed a walk's generator.
#[inline]
fn hash_floats<const N: usize>(v: [f32; N]) -> u64 {
    let mut words = [0u64; N];
    for (w, x) in words.iter_mut().zip(v) {
        *w = x.to_bits() as u64;
    }
    hash_u64(&words)
}

/// A sample only if a walk can go on from it.
#[inline]
fn usable(s: Option<BsdfSample>) -> Option<BsdfSample> {
    s.filter(BsdfSample::is_usable)
}

impl<B: Scatter> LayeredBxdf<B> {
    /// A layered BxDF; the thickness is kept above zero, as pbrt does, so that the two
    /// interfaces stay distinct heights.
    pub fn new(
        top: DielectricBxdf,
        bottom: B,
        thickness: f32,
        albedo: SampledSpectrum,
        g: f32,
        max_depth: u32,
        n_samples: u32,
    ) -> Self {
        LayeredBxdf {
            top,
            bottom,
            thickness: thickness.max(f32::MIN_POSITIVE),
            g,
            albedo,
            max_depth,
            n_samples: n_samples.max(1),
        }
    }

    /// True when the slab holds a scattering medium.
    #[inline]
    fn has_medium(&self) -> bool {
        self.albedo != SampledSpectrum::ZERO
    }
}

impl<B: Scatter> Scatter for LayeredBxdf<B> {
    /// Reflection always; specular if the coating is; diffuse if either layer or the medium is,
    /// else glossy if either layer is; transmission only if both layers transmit.
    fn flags(&self) -> BxdfFlags {
        let (top, bottom) = (self.top.flags(), self.bottom.flags());
        let mut fl = BxdfFlags::REFLECTION;
        if top.is_specular() {
            fl |= BxdfFlags::SPECULAR;
        }
        if top.is_diffuse() || bottom.is_diffuse() || self.has_medium() {
            fl |= BxdfFlags::DIFFUSE;
        } else if top.is_glossy() || bottom.is_glossy() {
            fl |= BxdfFlags::GLOSSY;
        }
        if top.is_transmission() && bottom.is_transmission() {
            fl |= BxdfFlags::TRANSMISSION;
        }
        fl
    }

    /// Stochastic estimate of f: the top's own reflection, plus `n_samples` random walks that
    /// enter through the top (sampled transmission), bounce between the interfaces and
    /// through the medium, and at each vertex connect to `wi` through the exit interface
    /// (next-event estimation along a pre-sampled exit direction and along the next sampled
    /// direction, combined by the power heuristic).
    fn f(&self, mut wo: Vec3, mut wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if wo.z < 0.0 {
            wo = -wo;
            wi = -wi;
        }
        let top = Side::<B>::Top(&self.top);
        let bottom = Side::Bottom(&self.bottom);
        // Light leaves through the top when wi is on wo's side, else through the bottom.
        let same = same_hemisphere(wo, wi);
        let (exit, non_exit, exit_z) = if same {
            (top, bottom, self.thickness)
        } else {
            (bottom, top, 0.0)
        };
        let n = self.n_samples as f32;
        let mut f = if same {
            n * self.top.f(wo, wi, mode)
        } else {
            SampledSpectrum::ZERO
        };
        let mut rng = Pcg32::new(
            hash_floats([wo.x, wo.y, wo.z]),
            hash_floats([wi.x, wi.y, wi.z]),
        );
        let mut r = || rng.uniform();
        let exit_specular = exit.flags().is_specular();
        let non_exit_specular = non_exit.flags().is_specular();

        for _ in 0..self.n_samples {
            // Enter through the top.
            let (uc, u) = (r(), Vec2::new(r(), r()));
            let Some(wos) = usable(top.sample_f(wo, uc, u, mode, ReflTrans::TRANSMISSION)) else {
                continue;
            };
            // A direction through the exit interface towards wi, for next-event estimation.
            let (uc, u) = (r(), Vec2::new(r(), r()));
            let Some(wis) = usable(exit.sample_f(wi, uc, u, mode.flip(), ReflTrans::TRANSMISSION))
            else {
                continue;
            };
            let mut beta = wos.f * abs_cos_theta(wos.wi) / wos.pdf;
            let mut z = self.thickness;
            let mut w = wos.wi;

            for depth in 0..self.max_depth {
                // Russian roulette once the walk carries little.
                if depth > 3 && beta.max_element() < 0.25 {
                    let q = (1.0 - beta.max_element()).max(0.0);
                    if r() < q {
                        break;
                    }
                    beta /= 1.0 - q;
                }
                if !self.has_medium() {
                    // Straight to the other interface, attenuated on the way.
                    z = if z == self.thickness {
                        0.0
                    } else {
                        self.thickness
                    };
                    beta *= tr(self.thickness, w);
                } else {
                    let dz = sample_exponential(r(), 1.0 / w.z.abs());
                    let zp = if w.z > 0.0 { z + dz } else { z - dz };
                    if zp == z {
                        continue;
                    }
                    if 0.0 < zp && zp < self.thickness {
                        // Scattering in the medium: connect to the exit along wis.
                        let p_wis = henyey_greenstein((-w).dot(-wis.wi), self.g);
                        let wt = if exit_specular {
                            1.0
                        } else {
                            power_heuristic(wis.pdf, p_wis)
                        };
                        f += beta * self.albedo * p_wis * wt * tr(zp - exit_z, wis.wi) * wis.f
                            / wis.pdf;
                        // Continue in a direction from the phase function.
                        let (wp, p) = sample_henyey_greenstein(-w, self.g, Vec2::new(r(), r()));
                        if p == 0.0 || wp.z == 0.0 {
                            continue;
                        }
                        // The phase function is sampled exactly: p/pdf = 1.
                        beta *= self.albedo;
                        w = wp;
                        z = zp;
                        // Heading for the exit: connect through it along w.
                        if ((z < exit_z && w.z > 0.0) || (z > exit_z && w.z < 0.0))
                            && !exit_specular
                        {
                            let (f_exit, exit_pdf) =
                                exit.f_pdf(-w, wi, mode, ReflTrans::TRANSMISSION);
                            if f_exit != SampledSpectrum::ZERO {
                                let wt = power_heuristic(p, exit_pdf);
                                f += beta * tr(zp - exit_z, wp) * f_exit * wt;
                            }
                        }
                        continue;
                    }
                    z = zp.clamp(0.0, self.thickness);
                }

                if z == exit_z {
                    // Reflection off the inside of the exit interface.
                    let (uc, u) = (r(), Vec2::new(r(), r()));
                    let Some(bs) = usable(exit.sample_f(-w, uc, u, mode, ReflTrans::REFLECTION))
                    else {
                        break;
                    };
                    beta *= bs.f * abs_cos_theta(bs.wi) / bs.pdf;
                    w = bs.wi;
                } else {
                    // At the other interface: connect to the exit along wis...
                    if !non_exit_specular {
                        let wt = if exit_specular {
                            1.0
                        } else {
                            power_heuristic(
                                wis.pdf,
                                non_exit.pdf(-w, -wis.wi, mode, ReflTrans::ALL),
                            )
                        };
                        f += beta
                            * non_exit.f(-w, -wis.wi, mode)
                            * abs_cos_theta(wis.wi)
                            * wt
                            * tr(self.thickness, wis.wi)
                            * wis.f
                            / wis.pdf;
                    }
                    // ...then scatter off it...
                    let (uc, u) = (r(), Vec2::new(r(), r()));
                    let Some(bs) =
                        usable(non_exit.sample_f(-w, uc, u, mode, ReflTrans::REFLECTION))
                    else {
                        break;
                    };
                    beta *= bs.f * abs_cos_theta(bs.wi) / bs.pdf;
                    w = bs.wi;
                    // ...and connect through the exit along the new direction.
                    if !exit_specular {
                        let (f_exit, exit_pdf) = exit.f_pdf(-w, wi, mode, ReflTrans::TRANSMISSION);
                        if f_exit != SampledSpectrum::ZERO {
                            let wt = if non_exit_specular {
                                1.0
                            } else {
                                power_heuristic(bs.pdf, exit_pdf)
                            };
                            f += beta * tr(self.thickness, bs.wi) * f_exit * wt;
                        }
                    }
                }
            }
        }
        f / n
    }

    /// Samples by following one random walk: reflection at the top is returned as is;
    /// otherwise the walk bounces between the layers (and scatters in the medium) until it
    /// leaves through an interface, its value and density being the products of those of
    /// its steps. f/pdf is then an unbiased weight but `pdf` is not the density of `wi`, so the
    /// sample is marked `pdf_is_proportional`.
    fn sample_f(
        &self,
        mut wo: Vec3,
        uc: f32,
        u: Vec2,
        mode: TransportMode,
        _mask: ReflTrans,
    ) -> Option<BsdfSample> {
        let flip = wo.z < 0.0;
        if flip {
            wo = -wo;
        }
        let mut bs = usable(self.top.sample_f(wo, uc, u, mode, ReflTrans::ALL))?;
        if bs.is_reflection() {
            if flip {
                bs.wi = -bs.wi;
            }
            bs.pdf_is_proportional = true;
            return Some(bs);
        }
        let mut w = bs.wi;
        let mut specular_path = bs.is_specular();
        let mut rng = Pcg32::new(hash_floats([wo.x, wo.y, wo.z]), hash_floats([uc, u.x, u.y]));
        let mut r = || rng.uniform();
        let mut f = bs.f * abs_cos_theta(bs.wi);
        let mut pdf = bs.pdf;
        let mut z = self.thickness;

        for depth in 0..self.max_depth {
            // Russian roulette on the walk's weight f/pdf.
            let rr_beta = f.max_element() / pdf;
            if depth > 3 && rr_beta < 0.25 {
                let q = (1.0 - rr_beta).max(0.0);
                if r() < q {
                    return None;
                }
                pdf *= 1.0 - q;
            }
            if w.z == 0.0 {
                return None;
            }
            if self.has_medium() {
                let dz = sample_exponential(r(), 1.0 / abs_cos_theta(w));
                let zp = if w.z > 0.0 { z + dz } else { z - dz };
                if zp == z {
                    return None;
                }
                if 0.0 < zp && zp < self.thickness {
                    let (wp, p) = sample_henyey_greenstein(-w, self.g, Vec2::new(r(), r()));
                    if p == 0.0 || wp.z == 0.0 {
                        return None;
                    }
                    f *= self.albedo * p;
                    pdf *= p;
                    specular_path = false;
                    w = wp;
                    z = zp;
                    continue;
                }
                z = zp.clamp(0.0, self.thickness);
            } else {
                z = if z == self.thickness {
                    0.0
                } else {
                    self.thickness
                };
                f *= tr(self.thickness, w);
            }
            let interface = if z == 0.0 {
                Side::Bottom(&self.bottom)
            } else {
                Side::Top(&self.top)
            };
            let (uc, u) = (r(), Vec2::new(r(), r()));
            let bs = usable(interface.sample_f(-w, uc, u, mode, ReflTrans::ALL))?;
            f *= bs.f;
            pdf *= bs.pdf;
            specular_path &= bs.is_specular();
            w = bs.wi;
            if bs.is_transmission() {
                // Out of the layers.
                let mut flags = if same_hemisphere(wo, w) {
                    BxdfFlags::REFLECTION
                } else {
                    BxdfFlags::TRANSMISSION
                };
                flags |= if specular_path {
                    BxdfFlags::SPECULAR
                } else {
                    BxdfFlags::GLOSSY
                };
                if flip {
                    w = -w;
                }
                return Some(BsdfSample {
                    pdf_is_proportional: true,
                    ..BsdfSample::new(f, w, pdf, flags)
                });
            }
            f *= abs_cos_theta(bs.wi);
        }
        None
    }

    /// An approximate density, good enough for MIS weights (pbrt-v4's estimate): the top's
    /// reflection density plus stochastic estimates of the transmit–reflect–transmit (same
    /// side) or transmit–transmit (other side) paths, mixed with a uniform density:
    /// pdf = 0.1/(4π) + 0.9·(estimate). It is positive everywhere, so MIS never divides a
    /// non-zero f by zero, but it does not integrate exactly to one.
    fn pdf(&self, mut wo: Vec3, mut wi: Vec3, mode: TransportMode, _mask: ReflTrans) -> f32 {
        if wo.z < 0.0 {
            wo = -wo;
            wi = -wi;
        }
        let mut rng = Pcg32::new(
            hash_floats([wi.x, wi.y, wi.z]),
            hash_floats([wo.x, wo.y, wo.z]),
        );
        let mut r = || rng.uniform();
        let same = same_hemisphere(wo, wi);
        let n = self.n_samples as f32;
        let mut pdf_sum = if same {
            n * self.top.pdf(wo, wi, mode, ReflTrans::REFLECTION)
        } else {
            0.0
        };
        let (top, bottom) = (&self.top, &self.bottom);
        for _ in 0..self.n_samples {
            if same {
                // Transmit through the top, reflect off the bottom, transmit back out.
                let (uc, u) = (r(), Vec2::new(r(), r()));
                let wos = top.sample_f(wo, uc, u, mode, ReflTrans::TRANSMISSION);
                let (uc, u) = (r(), Vec2::new(r(), r()));
                let wis = top.sample_f(wi, uc, u, mode.flip(), ReflTrans::TRANSMISSION);
                let (Some(wos), Some(wis)) = (wos, wis) else {
                    continue;
                };
                if wos.f == SampledSpectrum::ZERO
                    || wos.pdf <= 0.0
                    || wis.f == SampledSpectrum::ZERO
                    || wis.pdf <= 0.0
                {
                    continue;
                }
                if !top.flags().is_non_specular() {
                    pdf_sum += bottom.pdf(-wos.wi, -wis.wi, mode, ReflTrans::ALL);
                } else {
                    // Estimate the product of densities by MIS between the two ends.
                    let (uc, u) = (r(), Vec2::new(r(), r()));
                    let Some(rs) = bottom.sample_f(-wos.wi, uc, u, mode, ReflTrans::ALL) else {
                        continue;
                    };
                    if rs.f == SampledSpectrum::ZERO || rs.pdf <= 0.0 {
                        continue;
                    }
                    if !bottom.flags().is_non_specular() {
                        pdf_sum += top.pdf(-rs.wi, wi, mode, ReflTrans::ALL);
                    } else {
                        let r_pdf = bottom.pdf(-wos.wi, -wis.wi, mode, ReflTrans::ALL);
                        pdf_sum += power_heuristic(wis.pdf, r_pdf) * r_pdf;
                        let t_pdf = top.pdf(-rs.wi, wi, mode, ReflTrans::ALL);
                        pdf_sum += power_heuristic(rs.pdf, t_pdf) * t_pdf;
                    }
                }
            } else {
                // Transmit through the top, then through the bottom.
                let (uc, u) = (r(), Vec2::new(r(), r()));
                let Some(wos) = usable(top.sample_f(wo, uc, u, mode, ReflTrans::ALL)) else {
                    continue;
                };
                if wos.is_reflection() {
                    continue;
                }
                let (uc, u) = (r(), Vec2::new(r(), r()));
                let Some(wis) = usable(bottom.sample_f(wi, uc, u, mode.flip(), ReflTrans::ALL))
                else {
                    continue;
                };
                if wis.is_reflection() {
                    continue;
                }
                pdf_sum += if top.flags().is_specular() {
                    bottom.pdf(-wos.wi, wi, mode, ReflTrans::ALL)
                } else if bottom.flags().is_specular() {
                    top.pdf(wo, -wis.wi, mode, ReflTrans::ALL)
                } else {
                    (top.pdf(wo, -wis.wi, mode, ReflTrans::ALL)
                        + bottom.pdf(-wos.wi, wi, mode, ReflTrans::ALL))
                        / 2.0
                };
            }
        }
        lerp(0.9, INV_4PI, pdf_sum / n)
    }
}
