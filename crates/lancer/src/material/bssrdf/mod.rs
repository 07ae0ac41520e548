//! Subsurface scattering as pbrt-v4 renders its `subsurface` material: a tabulated radial
//! profile S_r (photon beam diffusion, [`BssrdfTable`]) scaled to the medium's σt, exit points
//! found by probe rays through the object, and the diffuse-like exit lobe
//! [`NormalizedFresnelBxdf`].
//!
//! S(po, ωo, pi, ωi) ≈ (1 − F(ωo)) · S_p(|po − pi|) · S_ω(ωi): the entry's Fresnel term is the
//! dielectric surface's transmission, S_p = σt² · profile(ρ, σt r) / (2π σt r), and S_ω is
//! the exit lobe.

mod spline;
mod table;

pub use table::BssrdfTable;
use table::fresnel_moment1;

use super::fresnel::fresnel_dielectric;
use super::scatter::{BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode, same_hemisphere};
use crate::math::{Frame, INV_PI, SampledSpectrum, Vec2, Vec3};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use spline::{catmull_rom_weights, invert_catmull_rom, sample_catmull_rom_2d};
use std::f32::consts::PI;

/// σa and σs of the medium whose effective albedo is `rho_eff` and mean free path `mfp`, per
/// lane: ρ = ρ_eff⁻¹(rho_eff) (inverting the table's spline), σs = ρ/mfp, σa = (1 − ρ)/mfp.
pub fn subsurface_from_diffuse(
    t: &BssrdfTable,
    rho_eff: SampledSpectrum,
    mfp: SampledSpectrum,
) -> (SampledSpectrum, SampledSpectrum) {
    let mut sa = [0.0; 4];
    let mut ss = [0.0; 4];
    for c in 0..4 {
        let rho = invert_catmull_rom(&t.rho_samples, &t.rho_eff, rho_eff[c]);
        ss[c] = rho / mfp[c];
        sa[c] = (1.0 - rho) / mfp[c];
    }
    (
        SampledSpectrum::from_array(sa),
        SampledSpectrum::from_array(ss),
    )
}

/// pbrt-v4's `TabulatedBSSRDF` at an entry point.
#[derive(Clone, Copy, Debug)]
pub struct TabulatedBssrdf<'a> {
    /// Entry point.
    pub po: Vec3,
    /// Shading normal there.
    pub ns: Vec3,
    /// Index of refraction of the medium.
    pub eta: f32,
    /// σt = σa + σs per lane.
    pub sigma_t: SampledSpectrum,
    /// Albedo ρ = σs/σt per lane.
    pub rho: SampledSpectrum,
    /// The profile table.
    pub table: &'a BssrdfTable,
}

/// A probe segment through the object, along which exit points are looked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeSegment {
    /// Start.
    pub p0: Vec3,
    /// End.
    pub p1: Vec3,
}

impl<'a> TabulatedBssrdf<'a> {
    /// The BSSRDF at `po` (shading normal `ns`) of a medium with coefficients σa, σs.
    pub fn new(
        po: Vec3,
        ns: Vec3,
        eta: f32,
        sigma_a: SampledSpectrum,
        sigma_s: SampledSpectrum,
        table: &'a BssrdfTable,
    ) -> Self {
        let sigma_t = sigma_a + sigma_s;
        let rho = SampledSpectrum::select(
            sigma_t.cmpne(SampledSpectrum::ZERO),
            sigma_s / sigma_t,
            SampledSpectrum::ZERO,
        );
        TabulatedBssrdf {
            po,
            ns,
            eta,
            sigma_t,
            rho,
            table,
        }
    }

    /// The interpolated profile of lane `i` at distance r, with the table's 2πr_optical
    /// divided out, and the interpolated ρ_eff; `None` off the table.
    fn profile(&self, i: usize, r: f32) -> Option<(f32, f32)> {
        let t = self.table;
        let r_optical = r * self.sigma_t[i];
        let (ro, rw) = catmull_rom_weights(&t.rho_samples, self.rho[i])?;
        let (qo, qw) = catmull_rom_weights(&t.radius_samples, r_optical)?;
        let (mut sr, mut rho_eff) = (0.0, 0.0);
        for (j, &wj) in rw.iter().enumerate() {
            if wj == 0.0 {
                continue;
            }
            let rj = (ro + j as isize) as usize;
            rho_eff += t.rho_eff[rj] * wj;
            for (k, &wk) in qw.iter().enumerate() {
                if wk != 0.0 {
                    sr += wj * wk * t.eval_profile(rj, (qo + k as isize) as usize);
                }
            }
        }
        if r_optical != 0.0 {
            sr /= 2.0 * PI * r_optical;
        }
        Some((sr, rho_eff))
    }

    /// S_r(r) = σt² · profile(ρ, σt r)/(2π σt r), per lane, clamped at 0.
    pub fn sr(&self, r: f32) -> SampledSpectrum {
        let mut out = [0.0; 4];
        for (i, o) in out.iter_mut().enumerate() {
            if let Some((sr, _)) = self.profile(i, r) {
                *o = (sr * self.sigma_t[i] * self.sigma_t[i]).max(0.0);
            }
        }
        SampledSpectrum::from_array(out)
    }

    /// Density (per unit area of the disk) of [`TabulatedBssrdf::sample_sr`] with lane i's
    /// profile choosing radius r: S_r,i(r)/ρ_eff,i.
    pub fn pdf_sr(&self, r: f32) -> SampledSpectrum {
        let mut out = [0.0; 4];
        for (i, o) in out.iter_mut().enumerate() {
            if let Some((sr, rho_eff)) = self.profile(i, r) {
                *o = (sr * self.sigma_t[i] * self.sigma_t[i] / rho_eff).max(0.0);
            }
        }
        SampledSpectrum::from_array(out)
    }

    /// A radius from lane `lane`'s profile (in proportion to 2πr S_r(r)).
    pub fn sample_sr(&self, u: f32, lane: usize) -> Option<f32> {
        let st = self.sigma_t[lane];
        if st <= 0.0 {
            return None;
        }
        let t = self.table;
        Some(
            sample_catmull_rom_2d(
                &t.rho_samples,
                &t.radius_samples,
                &t.profile,
                &t.profile_cdf,
                self.rho[lane],
                u,
            ) / st,
        )
    }

    /// A probe segment: an axis chosen with `u1` (the normal with probability ½, each tangent
    /// with ¼), a radius r from lane `lane`'s profile and an angle from `u2`, and the chord of
    /// the sphere of radius r_max (the profile's 99.9 % radius) at distance r from `po`
    /// along that axis.
    pub fn sample_sp(&self, u1: f32, u2: Vec2, lane: usize) -> Option<ProbeSegment> {
        let f = Frame::from_z(self.ns);
        let (a, b, axis) = if u1 < 0.25 {
            (f.y, f.z, f.x)
        } else if u1 < 0.5 {
            (f.z, f.x, f.y)
        } else {
            (f.x, f.y, f.z)
        };
        let r = self.sample_sr(u2.x, lane)?;
        let phi = 2.0 * PI * u2.y;
        let r_max = self.sample_sr(0.999, lane)?;
        if r >= r_max {
            return None;
        }
        let l = 2.0 * (r_max * r_max - r * r).sqrt();
        let p0 = self.po + r * (a * phi.cos() + b * phi.sin()) - l * axis / 2.0;
        Some(ProbeSegment {
            p0,
            p1: p0 + l * axis,
        })
    }

    /// Density (per unit area) of finding exit point `pi` (normal `ni`) with lane i's radius
    /// sampling, per lane: Σ over the three axes of P(axis) · pdf_r(r projected) · |n·axis|.
    pub fn pdf_sp(&self, pi: Vec3, ni: Vec3) -> SampledSpectrum {
        let f = Frame::from_z(self.ns);
        let d = f.to_local(pi - self.po);
        let n = f.to_local(ni);
        let r_proj = [
            (d.y * d.y + d.z * d.z).sqrt(),
            (d.z * d.z + d.x * d.x).sqrt(),
            (d.x * d.x + d.y * d.y).sqrt(),
        ];
        let axis_prob = [0.25, 0.25, 0.5];
        let mut pdf = SampledSpectrum::ZERO;
        for axis in 0..3 {
            pdf += self.pdf_sr(r_proj[axis]) * (n[axis].abs() * axis_prob[axis]);
        }
        pdf
    }

    /// S_p at exit point `pi`.
    pub fn sp(&self, pi: Vec3) -> SampledSpectrum {
        self.sr(self.po.distance(pi))
    }
}

/// The exit lobe of a BSSRDF (pbrt-v4's `NormalizedFresnelBxDF`): the Fresnel transmission
/// into the exit direction, normalised to integrate to one against cos θ:
/// f = (1 − F(cos θi, η)) / (c π), c = 1 − 2 M₁(1/η), times η² for radiance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalizedFresnelBxdf {
    /// Index of refraction of the medium.
    pub eta: f32,
}

impl Scatter for NormalizedFresnelBxdf {
    fn flags(&self) -> BxdfFlags {
        BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE
    }

    fn f(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) {
            return SampledSpectrum::ZERO;
        }
        let c = 1.0 - 2.0 * fresnel_moment1(1.0 / self.eta);
        let mut f = (1.0 - fresnel_dielectric(wi.z, self.eta)) / (c * PI);
        if mode == TransportMode::Radiance {
            f *= self.eta * self.eta;
        }
        SampledSpectrum::splat(f)
    }

    fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        u: Vec2,
        mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        if !mask.reflection() {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = cosine_hemisphere_pdf(wi.z.abs());
        (pdf > 0.0).then(|| {
            BsdfSample::new(
                self.f(wo, wi, mode),
                wi,
                pdf,
                BxdfFlags::REFLECTION | BxdfFlags::DIFFUSE,
            )
        })
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, mask: ReflTrans) -> f32 {
        if !mask.reflection() || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        wi.z.abs() * INV_PI
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profile_pdf_integrates_to_one_and_sp_to_the_effective_albedo() {
        let t = BssrdfTable::shared(0.0, 1.33);
        let sa = SampledSpectrum::new(0.05, 0.2, 1.0, 0.01);
        let ss = SampledSpectrum::new(1.0, 1.0, 2.0, 3.0);
        let b = TabulatedBssrdf::new(Vec3::ZERO, Vec3::Z, 1.33, sa, ss, &t);
        // ∫ pdf_sr(r) 2πr dr = 1 and ∫ S_r(r) 2πr dr = ρ_eff, by the midpoint rule in log r.
        let (mut p, mut s) = (SampledSpectrum::ZERO, SampledSpectrum::ZERO);
        let n = 40_000;
        let (lo, hi) = (1e-6f32.ln(), 200.0f32.ln());
        for k in 0..n {
            let x = lo + (hi - lo) * (k as f32 + 0.5) / n as f32;
            let r = x.exp();
            let w = 2.0 * PI * r * r * (hi - lo) / n as f32; // dr = r dx
            p += b.pdf_sr(r) * w;
            s += b.sr(r) * w;
        }
        assert!((p - SampledSpectrum::ONE).abs().max_element() < 0.02, "{p}");
        for i in 0..4 {
            let (_, rho_eff) = b.profile(i, 0.0).unwrap();
            assert!(
                (s[i] - rho_eff).abs() < 0.02 * rho_eff.max(0.05),
                "{s} {rho_eff}"
            );
        }
        // Sampled radii follow pdf_sr: the median of lane 1's radii has half the mass.
        let mut radii: Vec<f32> = (0..2001)
            .filter_map(|k| b.sample_sr((k as f32 + 0.5) / 2001.0, 1))
            .collect();
        radii.sort_by(f32::total_cmp);
        let median = radii[radii.len() / 2];
        let mut mass = 0.0;
        for k in 0..n {
            let x = lo + (median.ln() - lo) * (k as f32 + 0.5) / n as f32;
            let r = x.exp();
            mass += b.pdf_sr(r)[1] * 2.0 * PI * r * r * (median.ln() - lo) / n as f32;
        }
        assert!((mass - 0.5).abs() < 0.02, "{mass}");
    }

    #[test]
    fn inverting_the_effective_albedo_recovers_the_medium() {
        let t = BssrdfTable::shared(0.0, 1.33);
        let (sa, ss) = subsurface_from_diffuse(
            &t,
            SampledSpectrum::new(0.8, 0.6, 0.3, 0.0),
            SampledSpectrum::splat(0.5),
        );
        // σt = 1/mfp, and the albedo's effective albedo is the colour asked for.
        for i in 0..4 {
            assert!((sa[i] + ss[i] - 2.0).abs() < 1e-5);
        }
        let b = TabulatedBssrdf::new(Vec3::ZERO, Vec3::Z, 1.33, sa, ss, &t);
        for (i, want) in [0.8f32, 0.6, 0.3, 0.0].into_iter().enumerate() {
            let (_, rho_eff) = b.profile(i, 0.0).unwrap();
            assert!((rho_eff - want).abs() < 2e-3, "lane {i}: {rho_eff}");
        }
    }

    #[test]
    fn exit_lobe_integrates_to_eta_squared_for_radiance() {
        // ∫ f cos θ dω = η² (1 − 2M₁(1/η)... normalised): the cosine-weighted integral of
        // 1 − F over the hemisphere is π(1 − 2 M₁(1/η)), so radiance mode gives η².
        let b = NormalizedFresnelBxdf { eta: 1.33 };
        let n = 200_000;
        let mut sum = 0.0f64;
        for k in 0..n {
            let mu = (k as f32 + 0.5) / n as f32;
            let wi = Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
            sum += (b.f(Vec3::Z, wi, TransportMode::Radiance).x * mu) as f64;
        }
        let integral = sum / n as f64 * 2.0 * std::f64::consts::PI;
        assert!((integral - 1.33f64 * 1.33).abs() < 0.02, "{integral}");
    }
}
