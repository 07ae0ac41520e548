//! pbrt-v4's `measured` material: tabulated BRDFs in RGL's `.bsdf` format (Dupuy & Jakob
//! 2018, "An adaptive parameterization for efficient material acquisition and rendering"),
//! read from the format's description ([`tensor`]) and evaluated as pbrt-v4's `MeasuredBxDF`.
//!
//! The tables, over the unit square with θ ↦ u = √(2θ/π) and φ ↦ v = φ/2π + ½:
//! - `ndf` D(ωm) and `sigma` σ(ωo) = ∫ D(ωm) ⟨ωo·ωm⟩₊ dωm (the projected microfacet area),
//!   plain bilinear tables;
//! - `vndf`, per incident (φᵢ, θᵢ) node: the visible normals D(ωm)⟨ωo·ωm⟩₊/σ(ωo), as a density
//!   over the unit square (the Jacobian 2π²u sin θm included), sampled as [`Linear2D`]; for an
//!   isotropic file (at most 2 φᵢ nodes) its v is φm − φo;
//! - `luminance`, per (φᵢ, θᵢ): a density over the VNDF warp's *sample* square, which is
//!   sampled first (the product of the two warps follows f·cos);
//! - `spectra`, per (φᵢ, θᵢ, λ): the reflectance part S over the sample square, at the
//!   `wavelengths`; an `rgb` table (per (φᵢ, θᵢ, channel)) may replace or accompany it.
//!
//! With u = R⁻¹(ωm) the VNDF warp's inverse at the half vector ωm of (ωo, ωi):
//!   f(ωo, ωi) = max(0, S(u, λ)) · D(ωm) / (4 σ(ωo) cos θi),
//! and a sample's density over ωi is p_lum(u) · p_vndf(ωm) / (4 (ωo·ωm) · 2π² u_θ sin θm).
//! (For a microfacet model with Fresnel F and Smith masking G₁, σ = cos θo / G₁(ωo), so
//! S = F · G₁(ωi) gives f = F G₁(ωo) G₁(ωi) D / (4 cos θo cos θi).)

pub mod file;
pub mod tensor;

use super::scatter::{BsdfSample, BxdfFlags, ReflTrans, Scatter, TransportMode, same_hemisphere};
use crate::math::{PI, SampledSpectrum, Vec2, Vec3, normalize, rgb_lanes, spherical_direction};
use crate::sampling::Linear2D;
use crate::spectrum::cie;
use crate::spectrum::sampled::{ColourKind, RgbSpectrum, SampledWavelengths};
pub use file::{MAX_ENTRIES, MeasuredFile, Table};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// A measured BRDF's tables, ready to evaluate and sample (see the module documentation).
#[derive(Clone, PartialEq)]
pub struct MeasuredData {
    /// Where it was read from (for messages).
    pub name: String,
    /// Its file's [`MeasuredFile::content_key`].
    pub content_key: (u64, usize),
    /// At most two φᵢ nodes: the tables depend on φm − φo only.
    pub isotropic: bool,
    /// The wavelengths of `spectra`, nm (empty for an RGB-only file).
    pub wavelengths: Vec<f32>,
    ndf: Linear2D,
    sigma: Linear2D,
    vndf: Linear2D,
    luminance: Linear2D,
    /// Parameters (φᵢ, θᵢ, λ).
    spectra: Option<Linear2D>,
    /// Parameters (φᵢ, θᵢ, channel 0, 1, 2): the file's `rgb`, or `spectra` reduced to linear
    /// sRGB under D65.
    rgb: Linear2D,
}

impl std::fmt::Debug for MeasuredData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "MeasuredData {{ name: {:?}, content_key: ({:#018x}, {}) }}",
            self.name, self.content_key.0, self.content_key.1
        )
    }
}

/// θ ∈ [0, π/2] ↦ u = √(2θ/π).
#[inline]
pub fn theta_to_u(theta: f32) -> f32 {
    (theta * (2.0 / PI)).sqrt()
}

/// φ ∈ [−π, π] ↦ v = φ/2π + ½.
#[inline]
pub fn phi_to_u(phi: f32) -> f32 {
    phi * (0.5 / PI) + 0.5
}

/// u ↦ θ = u²π/2.
#[inline]
pub fn u_to_theta(u: f32) -> f32 {
    u * u * (PI / 2.0)
}

/// v ↦ φ = (2v − 1)π.
#[inline]
pub fn u_to_phi(v: f32) -> f32 {
    (2.0 * v - 1.0) * PI
}

/// The linear-sRGB weights of each of `lambda`'s nodes: the reduction (under D65, as
/// reflectances are reduced) of the hat function that is 1 at node k and falls linearly to
/// 0 at its neighbours (the first and last extended flat beyond the range, as the spectral
/// lookup clamps λ). A spectrum with node values s_k reduces to Σ s_k W_k.
fn rgb_weights(lambda: &[f32]) -> Vec<[f64; 3]> {
    let n = lambda.len();
    let hat = |k: usize, l: f64| -> f64 {
        let x = |i: usize| lambda[i] as f64;
        if n == 1 {
            return 1.0;
        }
        if l <= x(0) {
            return (k == 0) as u8 as f64;
        }
        if l >= x(n - 1) {
            return (k == n - 1) as u8 as f64;
        }
        if k > 0 && l >= x(k - 1) && l <= x(k) {
            (l - x(k - 1)) / (x(k) - x(k - 1))
        } else if k + 1 < n && l >= x(k) && l <= x(k + 1) {
            (x(k + 1) - l) / (x(k + 1) - x(k))
        } else {
            0.0
        }
    };
    let d65_y: f64 = cie::INTEGRATION_RANGE
        .map(|l| cie::d65(l as f64) * cie::cmf(l as f64)[1])
        .sum();
    (0..n)
        .map(|k| {
            let mut xyz = [0.0f64; 3];
            for l in cie::INTEGRATION_RANGE {
                let (l, w) = (l as f64, hat(k, l as f64));
                if w != 0.0 {
                    let c = cie::cmf(l);
                    for (a, ci) in xyz.iter_mut().zip(c) {
                        *a += w * cie::d65(l) * ci / d65_y;
                    }
                }
            }
            cie::xyz_to_srgb(xyz)
        })
        .collect()
}

impl MeasuredData {
    /// The sampling tables of `file` (its `rgb` table, when the file gives only spectra, the
    /// spectra reduced to linear sRGB under D65, as reflectances are reduced).
    pub fn new(file: &MeasuredFile) -> MeasuredData {
        let params = || vec![file.phi_i.clone(), file.theta_i.clone()];
        let table = |t: &Table, p: Vec<Vec<f32>>, sampled| {
            let s = &t.shape;
            Linear2D::new(&t.values, s[s.len() - 1], s[s.len() - 2], p, sampled)
        };
        let n = file.luminance.shape[3];
        let rgb = match (&file.rgb, &file.spectra) {
            (Some(rgb), _) => rgb.values.clone(),
            (
                None,
                Some(Table {
                    values: sp,
                    shape: s,
                }),
            ) => {
                // Each node's spectrum reduced to linear sRGB: Σ_k s_k W_k.
                let w = rgb_weights(&file.wavelengths);
                let (nl, nn) = (s[2], n * n);
                let mut out = Vec::with_capacity(sp.len() / nl * 3);
                for slice in sp.chunks_exact(nl * nn) {
                    for c in [0, 1, 2] {
                        for i in 0..nn {
                            let v: f64 = (0..nl).map(|k| slice[k * nn + i] as f64 * w[k][c]).sum();
                            out.push(v.max(0.0) as f32);
                        }
                    }
                }
                out
            }
            // Neither (the reader refuses such a file): black.
            (None, None) => vec![0.0; file.phi_i.len() * file.theta_i.len() * 3 * n * n],
        };
        let mut rgb_params = params();
        rgb_params.push(vec![0.0, 1.0, 2.0]);
        let rgb = Table {
            values: rgb,
            shape: vec![file.phi_i.len(), file.theta_i.len(), 3, n, n],
        };
        MeasuredData {
            name: file.name.clone(),
            content_key: file.content_key,
            isotropic: file.isotropic,
            ndf: table(&file.ndf, vec![], false),
            sigma: table(&file.sigma, vec![], false),
            vndf: table(&file.vndf, params(), true),
            luminance: table(&file.luminance, params(), true),
            spectra: file.spectra.as_ref().map(|s| {
                let mut p = params();
                p.push(file.wavelengths.clone());
                table(s, p, false)
            }),
            rgb: table(&rgb, rgb_params, false),
            wavelengths: file.wavelengths.clone(),
        }
    }

    /// The BRDF in the bytes of a `.bsdf` file, read ([`MeasuredFile::from_bytes`]) and built;
    /// `name` names it in messages. Errors say what is wrong with the file.
    pub fn from_bytes(bytes: &[u8], name: &str) -> Result<MeasuredData, String> {
        MeasuredFile::from_bytes(bytes, name).map(|f| MeasuredData::new(&f))
    }

    /// [`MeasuredData::new`], kept for the life of the process and shared: a file's tables
    /// are built once per content (as pbrt-v4 keeps one BRDF per file name), however many
    /// materials and scene builds name it, and BxDFs refer to them by a plain reference.
    pub fn shared(file: &MeasuredFile) -> &'static MeasuredData {
        type Cache = Mutex<HashMap<(u64, usize), &'static MeasuredData>>;
        static CACHE: OnceLock<Cache> = OnceLock::new();
        let cache = CACHE.get_or_init(Default::default);
        let mut c = cache.lock().unwrap_or_else(|e| e.into_inner());
        c.entry(file.content_key)
            .or_insert_with(|| Box::leak(Box::new(MeasuredData::new(file))))
    }

    /// Bytes of the tables.
    pub fn memory_bytes(&self) -> usize {
        [
            &self.ndf,
            &self.sigma,
            &self.vndf,
            &self.luminance,
            &self.rgb,
        ]
        .iter()
        .map(|t| t.memory_bytes())
        .sum::<usize>()
            + self.spectra.as_ref().map_or(0, Linear2D::memory_bytes)
    }
}

/// pbrt-v4's `MeasuredBxDF`: a [`MeasuredData`] seen at the path's wavelengths (`lambda`,
/// spectral mode) or in RGB (`None`).
#[derive(Clone, Copy, Debug)]
pub struct MeasuredBxdf {
    /// The tables.
    pub data: &'static MeasuredData,
    /// The path's four wavelengths (nm), or `None` in RGB mode.
    pub lambda: Option<[f32; 4]>,
}

impl PartialEq for MeasuredBxdf {
    fn eq(&self, o: &Self) -> bool {
        std::ptr::eq(self.data, o.data) && self.lambda == o.lambda
    }
}

/// The spherical angles (θ, φ) of a direction, φ = atan2(y, x).
#[inline]
fn angles(w: Vec3) -> (f32, f32) {
    (w.z.clamp(-1.0, 1.0).acos(), w.y.atan2(w.x))
}

impl MeasuredBxdf {
    /// The BxDF of `data` at `lambda`'s wavelengths (spectral mode) or in RGB (`None`).
    pub fn new(data: &'static MeasuredData, lambda: Option<&SampledWavelengths>) -> Self {
        MeasuredBxdf {
            data,
            lambda: lambda.map(|l| l.lambda.to_array()),
        }
    }

    /// The unit-square coordinates of half vector `wm` seen from `wo` at azimuth `phi_o`
    /// (v relative to φo for an isotropic file, wrapped into [0, 1)).
    #[inline]
    fn wm_to_u(&self, wm: Vec3, phi_o: f32) -> [f32; 2] {
        let (theta_m, phi_m) = angles(wm);
        let v = phi_to_u(if self.data.isotropic {
            phi_m - phi_o
        } else {
            phi_m
        });
        [theta_to_u(theta_m), v - v.floor()]
    }

    /// S at sample-square point `u` for incident (φo, θo), max(0, ·) per lane.
    #[inline]
    fn reflectance(&self, u: [f32; 2], phi_o: f32, theta_o: f32) -> SampledSpectrum {
        let d = self.data;
        let s = match (self.lambda, &d.spectra) {
            (Some(l), Some(sp)) => {
                SampledSpectrum::from_array(l.map(|l| sp.eval(u, &[phi_o, theta_o, l])))
            }
            (lambda, _) => {
                let c = [0.0, 1.0, 2.0].map(|c| d.rgb.eval(u, &[phi_o, theta_o, c]));
                let rgb = crate::math::Rgb::new(c[0], c[1], c[2]).max(crate::math::Rgb::ZERO);
                match lambda {
                    None => rgb_lanes(rgb),
                    Some(l) => {
                        let sp = RgbSpectrum::new(rgb, ColourKind::Unbounded);
                        let mut wl = SampledWavelengths::sample_visible(0.5);
                        wl.lambda = glam::Vec4::from_array(l);
                        wl.sample(&sp)
                    }
                }
            }
        };
        s.max(SampledSpectrum::ZERO)
    }

    /// D(ωm) / (4 σ(ωo) cos θi), the factor beside S in f.
    #[inline]
    fn geometry(&self, u_wm: [f32; 2], theta_o: f32, phi_o: f32, cos_i: f32) -> f32 {
        let u_wo = [theta_to_u(theta_o), phi_to_u(phi_o)];
        let sigma = self.data.sigma.eval(u_wo, &[]);
        let g = self.data.ndf.eval(u_wm, &[]) / (4.0 * sigma * cos_i);
        if g.is_finite() { g } else { 0.0 }
    }
}

/// The Jacobian of ωm's unit-square coordinates: dω = 2π² u_θ sin θm du dv (floored as
/// pbrt-v4 floors it, 10⁻⁶).
#[inline]
fn square_jacobian(u_theta: f32, sin_theta_m: f32) -> f32 {
    (2.0 * PI * PI * u_theta * sin_theta_m).max(1e-6)
}

impl Scatter for MeasuredBxdf {
    fn flags(&self) -> BxdfFlags {
        BxdfFlags::REFLECTION | BxdfFlags::GLOSSY
    }

    fn f(&self, wo: Vec3, wi: Vec3, _mode: TransportMode) -> SampledSpectrum {
        if !same_hemisphere(wo, wi) {
            return SampledSpectrum::ZERO;
        }
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return SampledSpectrum::ZERO;
        }
        let wm = normalize(wm);
        let (theta_o, phi_o) = angles(wo);
        let u_wm = self.wm_to_u(wm, phi_o);
        let (ui, _) = self.data.vndf.invert(u_wm, &[phi_o, theta_o]);
        let f = self.reflectance(ui, phi_o, theta_o) * self.geometry(u_wm, theta_o, phi_o, wi.z);
        if f.is_finite() {
            f
        } else {
            SampledSpectrum::ZERO
        }
    }

    fn sample_f(
        &self,
        wo: Vec3,
        _uc: f32,
        u: Vec2,
        _mode: TransportMode,
        mask: ReflTrans,
    ) -> Option<BsdfSample> {
        if !mask.reflection() {
            return None;
        }
        let flip = wo.z <= 0.0;
        let wo = if flip { -wo } else { wo };
        let (theta_o, phi_o) = angles(wo);
        let params = [phi_o, theta_o];
        // Luminance first, then the visible normals.
        let (u, lum_pdf) = self.data.luminance.sample([u.x, u.y], &params);
        let (u_wm, vndf_pdf) = self.data.vndf.sample(u, &params);
        let (theta_m, mut phi_m) = (u_to_theta(u_wm[0]), u_to_phi(u_wm[1]));
        if self.data.isotropic {
            phi_m += phi_o;
        }
        let (sin_m, cos_m) = theta_m.sin_cos();
        let wm = spherical_direction(sin_m, cos_m, phi_m);
        let wi = 2.0 * wo.dot(wm) * wm - wo;
        if wi.z <= 0.0 {
            return None;
        }
        let f = self.reflectance(u, phi_o, theta_o) * self.geometry(u_wm, theta_o, phi_o, wi.z);
        let pdf = lum_pdf * vndf_pdf / (4.0 * wo.dot(wm) * square_jacobian(u_wm[0], sin_m));
        if !(pdf > 0.0 && pdf.is_finite() && f.is_finite()) {
            return None;
        }
        let wi = if flip { -wi } else { wi };
        Some(BsdfSample::new(f, wi, pdf, self.flags()))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3, _mode: TransportMode, mask: ReflTrans) -> f32 {
        if !mask.reflection() || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let wm = wo + wi;
        if wm.length_squared() == 0.0 {
            return 0.0;
        }
        let wm = normalize(wm);
        let (theta_o, phi_o) = angles(wo);
        let params = [phi_o, theta_o];
        let u_wm = self.wm_to_u(wm, phi_o);
        let (ui, vndf_pdf) = self.data.vndf.invert(u_wm, &params);
        let lum_pdf = self.data.luminance.eval(ui, &params);
        let sin_m = (wm.x * wm.x + wm.y * wm.y).sqrt();
        let pdf = vndf_pdf * lum_pdf / (4.0 * wo.dot(wm) * square_jacobian(u_wm[0], sin_m));
        if pdf.is_finite() { pdf.max(0.0) } else { 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::tensor::{Field, Tensor};
    use super::*;
    use crate::math::Vec2;

    /// A small consistent file: 3 × 3 tables, two θᵢ nodes, spectra at two wavelengths.
    fn small() -> Vec<u8> {
        let t = |v: f32| Field::f32(&[1, 2, 3, 3], &[v; 18]);
        let ramp: Vec<f32> = (0..36).map(|i| 0.1 + 0.02 * i as f32).collect();
        let fields = [
            ("theta_i", Field::f32(&[2], &[0.0, 1.5])),
            ("phi_i", Field::f32(&[1], &[0.0])),
            ("ndf", Field::f32(&[3, 3], &[0.3; 9])),
            ("sigma", Field::f32(&[3, 3], &[0.9; 9])),
            ("vndf", t(1.0)),
            ("luminance", t(2.0)),
            ("wavelengths", Field::f32(&[2], &[400.0, 700.0])),
            ("spectra", Field::f32(&[1, 2, 2, 3, 3], &ramp)),
        ];
        let refs: Vec<(&str, &Field)> = fields.iter().map(|(n, f)| (*n, f)).collect();
        Tensor::write(&refs)
    }

    #[test]
    fn a_grey_spectrum_reduces_to_grey_and_a_ramp_to_its_colour() {
        let lambda: Vec<f32> = (0..=10).map(|i| 360.0 + 47.0 * i as f32).collect();
        let w = rgb_weights(&lambda);
        for c in 0..3 {
            let grey: f64 = w.iter().map(|w| w[c]).sum();
            assert!((grey - 1.0).abs() < 2e-3, "{c}: {grey}");
        }
        // More at long wavelengths: redder than blue.
        let red: Vec<f64> = (0..3)
            .map(|c| w.iter().enumerate().map(|(k, w)| k as f64 * w[c]).sum())
            .collect();
        assert!(red[0] > red[2], "{red:?}");
    }

    #[test]
    fn shape_errors_name_the_field() {
        let ok = MeasuredData::from_bytes(&small(), "s").unwrap();
        assert!(ok.spectra.is_some() && ok.memory_bytes() > 0);
        let bad = Tensor::write(&[
            ("theta_i", &Field::f32(&[2], &[0.5, 0.1])),
            ("phi_i", &Field::f32(&[1], &[0.0])),
        ]);
        assert_eq!(
            MeasuredData::from_bytes(&bad, "s").unwrap_err(),
            "field \"theta_i\" does not increase: [0.5, 0.1]"
        );
        let t = Tensor::parse(&small()).unwrap();
        let mut fields: Vec<(&str, &Field)> =
            t.fields.iter().map(|(n, f)| (n.as_str(), f)).collect();
        let wrong = Field::f32(&[1, 3, 3, 3], &[1.0; 27]);
        for f in fields.iter_mut().filter(|f| f.0 == "vndf") {
            f.1 = &wrong;
        }
        assert_eq!(
            MeasuredData::from_bytes(&Tensor::write(&fields), "s").unwrap_err(),
            "field \"vndf\" has shape [1, 3, 3, 3]; [1, 2, n ≥ 2, n ≥ 2] is needed"
        );
        let nan = Field::f32(&[3, 3], &[0.3, 0.3, f32::NAN, 0.3, 0.3, 0.3, 0.3, 0.3, 0.3]);
        for f in fields.iter_mut().filter(|f| f.0 == "ndf") {
            f.1 = &nan;
        }
        assert!(
            MeasuredData::from_bytes(&Tensor::write(&fields), "s")
                .unwrap_err()
                .starts_with("field \"")
        );
    }

    /// Every byte of a valid file changed, and every truncation: never a panic, and what
    /// loads evaluates to finite values.
    #[test]
    fn damaged_files_never_panic() {
        let good = small();
        let probe = |bytes: &[u8]| {
            if let Ok(d) = MeasuredData::from_bytes(bytes, "x") {
                let d: &'static MeasuredData = Box::leak(Box::new(d));
                let b = MeasuredBxdf::new(d, None);
                let (wo, wi) = (
                    normalize(Vec3::new(0.3, 0.1, 0.9)),
                    normalize(Vec3::new(-0.2, 0.4, 0.8)),
                );
                let m = TransportMode::Radiance;
                assert!(b.f(wo, wi, m).is_finite());
                assert!(b.pdf(wo, wi, m, ReflTrans::ALL).is_finite());
                if let Some(s) = b.sample_f(wo, 0.5, Vec2::new(0.3, 0.6), m, ReflTrans::ALL) {
                    assert!(s.f.is_finite() && s.pdf.is_finite());
                }
            }
        };
        for len in 0..good.len() {
            probe(&good[..len]);
        }
        for i in 0..good.len() {
            for v in [0x00, 0x01, 0x7f, 0x80, 0xff] {
                let mut b = good.clone();
                b[i] = v;
                probe(&b);
            }
        }
    }
}
