//! The Trowbridge–Reitz (GGX) microfacet distribution, anisotropic, in the local shading frame
//! (z = macro-normal), with visible-normal sampling (Heitz 2018) as pbrt-v4 uses it.

use crate::math::{PI, Vec2, Vec3, cross, lerp, normalize, safe_sqrt};
use crate::sampling::sample_uniform_disk_polar;

/// An anisotropic Trowbridge–Reitz distribution of microfacet normals with widths `alpha_x`
/// along the tangent and `alpha_y` along the bitangent.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrowbridgeReitz {
    alpha_x: f32,
    alpha_y: f32,
}

impl TrowbridgeReitz {
    /// A distribution with the given widths (negative ones taken as zero). As in pbrt-v4, a
    /// rough distribution keeps both widths at least 10⁻⁴: one zero width beside a non-zero
    /// one would make the anisotropic term cos²φ/αx² of [`Self::d`] infinite.
    #[inline]
    pub fn new(alpha_x: f32, alpha_y: f32) -> TrowbridgeReitz {
        let mut d = TrowbridgeReitz {
            alpha_x: alpha_x.max(0.0),
            alpha_y: alpha_y.max(0.0),
        };
        if !d.effectively_smooth() {
            d.alpha_x = d.alpha_x.max(1e-4);
            d.alpha_y = d.alpha_y.max(1e-4);
        }
        d
    }

    /// Width along x.
    #[inline]
    pub fn alpha_x(&self) -> f32 {
        self.alpha_x
    }

    /// Width along y.
    #[inline]
    pub fn alpha_y(&self) -> f32 {
        self.alpha_y
    }

    /// pbrt-v4's map from a user's "roughness" to α: α = √roughness (negative roughness is
    /// treated as zero).
    #[inline]
    pub fn roughness_to_alpha(roughness: f32) -> f32 {
        roughness.max(0.0).sqrt()
    }

    /// The distribution a material's `uroughness`/`vroughness` describe: remapped by
    /// [`Self::roughness_to_alpha`] when `remap` is set (pbrt's `remaproughness`), used as α
    /// directly otherwise.
    #[inline]
    pub fn from_roughness(u: f32, v: f32, remap: bool) -> TrowbridgeReitz {
        if remap {
            TrowbridgeReitz::new(Self::roughness_to_alpha(u), Self::roughness_to_alpha(v))
        } else {
            TrowbridgeReitz::new(u, v)
        }
    }

    /// True when the surface is so smooth that it is treated as a perfect specular interface:
    /// max(αx, αy) < 10⁻³ (pbrt-v4's threshold).
    #[inline]
    pub fn effectively_smooth(&self) -> bool {
        self.alpha_x.max(self.alpha_y) < 1e-3
    }

    /// pbrt-v4's path regularisation: widths below 0.3 become clamp(2α, 0.1, 0.3), trading a
    /// little bias for much less noise on near-specular paths.
    pub fn regularize(&mut self) {
        if self.alpha_x < 0.3 {
            self.alpha_x = (2.0 * self.alpha_x).clamp(0.1, 0.3);
        }
        if self.alpha_y < 0.3 {
            self.alpha_y = (2.0 * self.alpha_y).clamp(0.1, 0.3);
        }
    }

    /// Density of microfacet normals per unit projected area:
    /// D(ωm) = 1 / (π αx αy cos⁴θm (1 + tan²θm (cos²φm/αx² + sin²φm/αy²))²),
    /// normalised so that ∫ D(ωm) cos θm dωm = 1.
    #[inline]
    ///
    /// With tan²θ cos²φ = x²/z² and tan²θ sin²φ = y²/z² (ωm = (x, y, z), a unit vector), the
    /// angles need no square root: e = tan²θ (cos²φ/αx² + sin²φ/αy²) = ((x/αx)² + (y/αy)²)/z²
    /// and cos⁴θ = z⁴. With k = αx αy, z⁴(1 + e)² = (k²z² + (αy x)² + (αx y)²)²/k⁴, so
    /// D = k³ / (π (k²z² + (αy x)² + (αx y)²)²): one division.
    pub fn d(&self, wm: Vec3) -> f32 {
        let z2 = wm.z * wm.z;
        if z2 * z2 < 1e-16 {
            return 0.0;
        }
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let k = ax * ay;
        let s = k * k * z2 + (ay * wm.x).powi(2) + (ax * wm.y).powi(2);
        k * k * k / (PI * s * s)
    }

    /// Smith's auxiliary function: the microfacet area hidden from `w` per unit visible area,
    /// Λ(ω) = (√(1 + α²(φ) tan²θ) − 1) / 2 with α²(φ) = (αx cos φ)² + (αy sin φ)²
    /// (zero at grazing angles, where tan θ is infinite, as pbrt does). For ω = (x, y, z) a
    /// unit vector, α²(φ) tan²θ = ((αx x)² + (αy y)²)/z²: one division, no angle.
    #[inline]
    pub fn lambda(&self, w: Vec3) -> f32 {
        let a2_tan2 = ((self.alpha_x * w.x).powi(2) + (self.alpha_y * w.y).powi(2)) / (w.z * w.z);
        if !a2_tan2.is_finite() {
            return 0.0;
        }
        ((1.0 + a2_tan2).sqrt() - 1.0) / 2.0
    }

    /// Smith's masking function: the fraction of microfacets visible from `w`,
    /// G₁(ω) = 1 / (1 + Λ(ω)).
    #[inline]
    pub fn g1(&self, w: Vec3) -> f32 {
        1.0 / (1.0 + self.lambda(w))
    }

    /// Height-correlated masking-shadowing: the fraction of microfacets visible from both
    /// directions, G(ωo, ωi) = 1 / (1 + Λ(ωo) + Λ(ωi)).
    #[inline]
    pub fn g(&self, wo: Vec3, wi: Vec3) -> f32 {
        Self::g_from_lambdas(self.lambda(wo), self.lambda(wi))
    }

    /// [`Self::g`] from Λ(ωo) and Λ(ωi) already computed: 1 / (1 + Λ(ωo) + Λ(ωi)).
    #[inline]
    pub fn g_from_lambdas(lambda_o: f32, lambda_i: f32) -> f32 {
        1.0 / (1.0 + lambda_o + lambda_i)
    }

    /// Distribution of normals visible from `w`:
    /// D_ω(ωm) = G₁(ω) / |cos θ| · D(ωm) · |ω·ωm|, a density over the hemisphere of ωm.
    #[inline]
    pub fn d_visible(&self, w: Vec3, wm: Vec3) -> f32 {
        Self::d_visible_from(w, wm, self.d(wm), self.lambda(w))
    }

    /// [`Self::d_visible`] from D(ωm) and Λ(ω) already computed, for the samplers that
    /// need D and Λ(ωo) for the BxDF's value too:
    /// D_ω(ωm) = 1/(1 + Λ(ω)) / |cos θ| · D(ωm) · |ω·ωm|.
    #[inline]
    pub fn d_visible_from(w: Vec3, wm: Vec3, d_wm: f32, lambda_w: f32) -> f32 {
        d_wm * w.dot(wm).abs() / ((1.0 + lambda_w) * w.z.abs())
    }

    /// Density (solid angle of ωm) with which [`Self::sample_wm`] returns `wm`: D_ω(ωm).
    #[inline]
    pub fn pdf(&self, w: Vec3, wm: Vec3) -> f32 {
        self.d_visible(w, wm)
    }

    /// Samples a microfacet normal from the distribution of normals visible from `w`
    /// (Heitz 2018, "Sampling the GGX distribution of visible normals"): stretch `w` into the
    /// configuration where α = 1 (a hemisphere), sample the projected area of that hemisphere
    /// seen from it (a disk whose half beyond the horizon is squashed to height
    /// (1 + cos θ)/2), lift the point onto the hemisphere and unstretch the normal.
    /// Always returns a normal with positive z.
    #[inline]
    pub fn sample_wm(&self, w: Vec3, u: Vec2) -> Vec3 {
        // Stretched direction s, on the +z side, and its unit vector wh.
        let mut s = Vec3::new(self.alpha_x * w.x, self.alpha_y * w.y, w.z);
        if s.z < 0.0 {
            s = -s;
        }
        let wh = normalize(s);
        // Basis around wh: t1 = normalize(z × wh) = (−s_y, s_x, 0)/√(s_x² + s_y²), from s
        // rather than wh, so that its square root and division run beside wh's.
        let t1 = if wh.z < 0.99999 {
            Vec3::new(-s.y, s.x, 0.0) / (s.x * s.x + s.y * s.y).sqrt()
        } else {
            Vec3::X
        };
        let t2 = cross(wh, t1);
        // Uniform disk point, its far half warped onto the visible part of the projection.
        let mut p = sample_uniform_disk_polar(u);
        let h = (1.0 - p.x * p.x).max(0.0).sqrt();
        p.y = lerp((1.0 + wh.z) / 2.0, h, p.y);
        // Back onto the hemisphere, then to the ellipsoid configuration: normals transform by
        // the inverse transpose of the stretch, i.e. multiply x and y by α.
        let pz = safe_sqrt(1.0 - p.length_squared());
        let nh = p.x * t1 + p.y * t2 + pz * wh;
        normalize(Vec3::new(
            self.alpha_x * nh.x,
            self.alpha_y * nh.y,
            nh.z.max(1e-6),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    /// ∫ f over the hemisphere z > 0 by the midpoint rule in (cos θ, φ), which has no
    /// Jacobian: dω = d(cos θ) dφ.
    fn integrate_hemisphere(n: usize, f: impl Fn(Vec3) -> f64) -> f64 {
        let mut s = 0.0;
        for i in 0..n {
            let c = (i as f64 + 0.5) / n as f64;
            let st = (1.0 - c * c).max(0.0).sqrt();
            for j in 0..2 * n {
                let phi = (j as f64 + 0.5) / (2 * n) as f64 * 2.0 * std::f64::consts::PI;
                let w = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, c as f32);
                s += f(w);
            }
        }
        s * (1.0 / n as f64) * (2.0 * std::f64::consts::PI / (2 * n) as f64)
    }

    #[test]
    fn projected_normal_density_integrates_to_one() {
        // ∫ D(ωm) cos θm dωm = 1: the microsurface projects onto exactly the macro-surface.
        for (ax, ay) in [(0.3, 0.3), (0.6, 0.15), (1.0, 1.0)] {
            let d = TrowbridgeReitz::new(ax, ay);
            let s = integrate_hemisphere(800, |w| d.d(w) as f64 * w.z as f64);
            assert!((s - 1.0).abs() < 5e-3, "α = ({ax}, {ay}): ∫D cos = {s}");
        }
    }

    /// D in its one-division form against pbrt-v4's angle form in f64,
    /// 1/(π αx αy cos⁴θ (1 + tan²θ (cos²φ/αx² + sin²φ/αy²))²), down to the narrowest widths
    /// (where the form's k³ and its squared denominator are smallest).
    #[test]
    fn d_matches_the_angle_form() {
        for (ax, ay) in [
            (1e-4f32, 1e-4f32),
            (1e-3, 1e-3),
            (1e-4, 0.8),
            (0.1, 0.1),
            (0.6, 0.15),
            (1.0, 1.0),
        ] {
            let d = TrowbridgeReitz::new(ax, ay);
            for i in 0..=200 {
                for j in 0..24 {
                    // cos θ from 1 to 0.01, with a cluster near the normal where narrow lobes live
                    let c = if i < 100 {
                        1.0 - (i as f64 / 100.0).powi(4) * 1e-3
                    } else {
                        1.0 - (i - 100) as f64 / 101.0
                    };
                    let phi = j as f64 * 0.27;
                    let st = (1.0 - c * c).sqrt();
                    let wm = Vec3::new((st * phi.cos()) as f32, (st * phi.sin()) as f32, c as f32);
                    let (x, y, z) = (wm.x as f64, wm.y as f64, wm.z as f64);
                    let (cos2, tan2) = (z * z, (x * x + y * y) / (z * z));
                    let (cp2, sp2) = if x * x + y * y > 0.0 {
                        (x * x / (x * x + y * y), y * y / (x * x + y * y))
                    } else {
                        (1.0, 0.0)
                    };
                    let (ax, ay) = (ax as f64, ay as f64);
                    let e = tan2 * (cp2 / (ax * ax) + sp2 / (ay * ay));
                    let want = 1.0
                        / (std::f64::consts::PI * ax * ay * cos2 * cos2 * (1.0 + e) * (1.0 + e));
                    let got = d.d(wm) as f64;
                    assert!(
                        (got - want).abs() <= 1e-5 * want,
                        "α ({ax}, {ay}) wm {wm:?}: {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn visible_normals_are_a_density_and_project_onto_the_view() {
        // ∫ D_ω(ωm) dωm = 1 and, equivalently, ∫ G₁(ω) max(0, ω·ωm) D(ωm) dωm = cos θ: the
        // visible projected microsurface area equals the macro-surface's (Heitz 2014, eq. 2).
        let d = TrowbridgeReitz::new(0.5, 0.25);
        for w in [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.6, 0.0, 0.8),
            normalize(Vec3::new(-0.3, 0.9, 0.3163)),
        ] {
            let s = integrate_hemisphere(800, |m| {
                if w.dot(m) > 0.0 {
                    d.d_visible(w, m) as f64
                } else {
                    0.0
                }
            });
            assert!((s - 1.0).abs() < 5e-3, "w = {w}: ∫D_ω = {s}");
        }
    }

    #[test]
    fn lambda_matches_the_isotropic_closed_form() {
        // For an isotropic distribution Λ = (−1 + √(1 + α² tan²θ))/2; at θ = 60°, α = 0.5:
        // tan²θ = 3, Λ = (√1.75 − 1)/2.
        let d = TrowbridgeReitz::new(0.5, 0.5);
        let w = Vec3::new(3f32.sqrt() / 2.0, 0.0, 0.5);
        assert!((d.lambda(w) - (1.75f32.sqrt() - 1.0) / 2.0).abs() < 1e-5);
        assert_eq!(d.lambda(Vec3::Z), 0.0);
        // Grazing: Λ is defined as 0 (tan θ infinite), so nothing divides by zero.
        assert_eq!(d.lambda(Vec3::X), 0.0);
        assert!(d.g(Vec3::X, Vec3::Z).is_finite());
    }

    #[test]
    fn sampled_visible_normals_follow_their_density() {
        // The mean of any function over sampled normals equals its integral against D_ω:
        // checked for the normal's z and x² components, whose integrals are computed by
        // quadrature. 2·10⁵ samples give standard errors near 10⁻³.
        let d = TrowbridgeReitz::new(0.4, 0.2);
        let w = normalize(Vec3::new(0.5, 0.3, 0.812));
        let mut rng = Pcg32::new(3, 0);
        let n = 200_000;
        let (mut sz, mut sx2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let m = d.sample_wm(w, Vec2::new(rng.uniform(), rng.uniform()));
            assert!(m.z > 0.0 && (m.length() - 1.0).abs() < 1e-4);
            assert!(
                w.dot(m) > -1e-4,
                "a sampled normal faces away from the viewer"
            );
            sz += m.z as f64;
            sx2 += (m.x * m.x) as f64;
        }
        let vis = |m: Vec3| {
            if w.dot(m) > 0.0 {
                d.d_visible(w, m) as f64
            } else {
                0.0
            }
        };
        let ez = integrate_hemisphere(1000, |m| vis(m) * m.z as f64);
        let ex2 = integrate_hemisphere(1000, |m| vis(m) * (m.x * m.x) as f64);
        assert!(
            (sz / n as f64 - ez).abs() < 5e-3,
            "E[z]: {} vs {ez}",
            sz / n as f64
        );
        assert!(
            (sx2 / n as f64 - ex2).abs() < 5e-3,
            "E[x²]: {} vs {ex2}",
            sx2 / n as f64
        );
    }

    #[test]
    fn roughness_maps_and_regularises_as_pbrt_does() {
        assert_eq!(TrowbridgeReitz::roughness_to_alpha(0.25), 0.5);
        assert_eq!(
            TrowbridgeReitz::from_roughness(0.25, 0.04, true).alpha_y(),
            0.2
        );
        assert_eq!(
            TrowbridgeReitz::from_roughness(0.25, 0.04, false).alpha_x(),
            0.25
        );
        // A zero width beside a rough one is raised to 10⁻⁴.
        assert_eq!(TrowbridgeReitz::new(0.0, 0.5).alpha_x(), 1e-4);
        assert_eq!(TrowbridgeReitz::new(0.0, 5e-4).alpha_x(), 0.0);
        assert!(TrowbridgeReitz::new(0.0, 9e-4).effectively_smooth());
        assert!(!TrowbridgeReitz::new(0.0, 1e-3).effectively_smooth());
        let mut d = TrowbridgeReitz::new(0.02, 0.5);
        d.regularize();
        assert_eq!((d.alpha_x, d.alpha_y), (0.1, 0.5));
        let mut d = TrowbridgeReitz::new(0.12, 0.2);
        d.regularize();
        assert_eq!((d.alpha_x, d.alpha_y), (0.24, 0.3));
    }
}
