//! A writer of RGL `.bsdf` tensor files from analytic BRDFs, for testing lancer's reader and
//! `MeasuredBxdf` without the database's files (not reachable here).
//!
//! The file is isotropic (one φᵢ node). Its adaptive parameterisation is that of a GGX
//! (Trowbridge–Reitz) microfacet distribution of roughness `alpha`: `ndf` D, `sigma`
//! σ(ωo) = (cos θo + √(cos²θo + α² sin²θo))/2, and per θᵢ node the visible-normal density
//! D(ωm)⟨ωo·ωm⟩₊/σ(ωo) times the unit square's Jacobian 2π²u sin θm. The reflectance part over
//! the VNDF's sample square is S = f · 4σ(ωo) cos θi / D(ωm) at the ωi each sample point warps
//! to (so for the GGX BRDF F G₁(ωo) G₁(ωi) D/(4 cos θo cos θi) itself, S = F G₁(ωi)); the
//! luminance table is S averaged over the wavelengths.

use lancer::material::measured::tensor::{Field, Tensor};
use lancer::material::measured::{u_to_phi, u_to_theta};
use lancer::math::{PI, Vec3, spherical_direction};
use lancer::sampling::Linear2D;

/// GGX D(ωm) for roughness α: 1 / (π α² cos⁴θ (1 + tan²θ/α²)²).
pub fn ggx_d(alpha: f32, wm: Vec3) -> f32 {
    let c2 = wm.z * wm.z;
    if c2 <= 0.0 {
        return 0.0;
    }
    let t2 = (1.0 - c2).max(0.0) / c2;
    let e = 1.0 + t2 / (alpha * alpha);
    1.0 / (PI * alpha * alpha * c2 * c2 * e * e)
}

/// Smith's G₁ for GGX: 1 / (1 + Λ), Λ = (√(1 + α² tan²θ) − 1)/2.
pub fn ggx_g1(alpha: f32, w: Vec3) -> f32 {
    if w.z <= 0.0 {
        return 0.0;
    }
    let t2 = (1.0 - w.z * w.z).max(0.0) / (w.z * w.z);
    2.0 / (1.0 + (1.0 + alpha * alpha * t2).sqrt())
}

/// σ(ωo) = cos θo / G₁(ωo) = (cos θo + √(cos²θo + α² sin²θo))/2.
pub fn ggx_sigma(alpha: f32, cos_o: f32) -> f32 {
    let s2 = (1.0 - cos_o * cos_o).max(0.0);
    0.5 * (cos_o + (cos_o * cos_o + alpha * alpha * s2).sqrt())
}

/// The bytes of a `.bsdf` file tabulating `f(wo, wi, λ)` (wo at φ = 0) with GGX(`alpha`)'s
/// parameterisation: n × n nodes per table, incident angles `theta_i` (radians), spectra at
/// `wavelengths` (nm).
pub fn bsdf_file(
    alpha: f32,
    f: impl Fn(Vec3, Vec3, f32) -> f32,
    n: usize,
    theta_i: &[f32],
    wavelengths: &[f32],
) -> Vec<u8> {
    let node = |i: usize| i as f32 / (n - 1) as f32;
    let dir = |u: f32, v: f32| {
        let (t, p) = (u_to_theta(u), u_to_phi(v));
        spherical_direction(t.sin(), t.cos(), p)
    };
    let mut ndf = Vec::new();
    let mut sigma = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let w = dir(node(i), node(j));
            ndf.push(ggx_d(alpha, w));
            sigma.push(ggx_sigma(alpha, w.z.max(0.0)));
        }
    }
    let (nt, nl) = (theta_i.len(), wavelengths.len());
    let mut vndf = Vec::new();
    let mut lum = Vec::new();
    let mut spectra = Vec::new();
    for &t in theta_i {
        let wo = spherical_direction(t.sin(), t.cos(), 0.0);
        let sig = ggx_sigma(alpha, wo.z);
        let mut slice = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let wm = dir(node(i), node(j));
                let jac = 2.0 * PI * PI * node(i) * u_to_theta(node(i)).sin();
                slice.push(ggx_d(alpha, wm) * wo.dot(wm).max(0.0) / sig * jac);
            }
        }
        let warp = Linear2D::new(&slice, n, n, vec![], true);
        vndf.extend(&slice);
        let mut s = vec![0.0f32; nl * n * n];
        let mut l = vec![0.0f32; n * n];
        for j in 0..n {
            for i in 0..n {
                let (u_wm, _) = warp.sample([node(i), node(j)], &[]);
                let wm = dir(u_wm[0], u_wm[1]);
                let wi = 2.0 * wo.dot(wm) * wm - wo;
                if wi.z <= 0.0 {
                    continue;
                }
                let k = 4.0 * sig * wi.z / ggx_d(alpha, wm);
                for (c, &lambda) in wavelengths.iter().enumerate() {
                    let v = f(wo, wi, lambda) * k;
                    s[c * n * n + j * n + i] = v;
                    l[j * n + i] += v / nl as f32;
                }
            }
        }
        lum.extend(l);
        spectra.extend(s);
    }
    let fields = [
        ("description", Field::u8(&[9], b"generated")),
        ("jacobian", Field::u8(&[1], &[1])),
        ("theta_i", Field::f32(&[nt], theta_i)),
        ("phi_i", Field::f32(&[1], &[0.0])),
        ("ndf", Field::f32(&[n, n], &ndf)),
        ("sigma", Field::f32(&[n, n], &sigma)),
        ("vndf", Field::f32(&[1, nt, n, n], &vndf)),
        ("luminance", Field::f32(&[1, nt, n, n], &lum)),
        ("wavelengths", Field::f32(&[nl], wavelengths)),
        ("spectra", Field::f32(&[1, nt, nl, n, n], &spectra)),
    ];
    let refs: Vec<(&str, &Field)> = fields.iter().map(|(n, f)| (*n, f)).collect();
    Tensor::write(&refs)
}
