//! pbrt-v4's procedural `cloud` medium (`CloudMedium`): Perlin-noise density inside a box,
//! thinning with height, under a single majorant (density ≤ 1).
//!
//! Density at medium-space p (pbrt-v4's `CloudMedium::Density`): pp = frequency·p, perturbed by
//! two octaves of noise gradient when `wispiness` > 0 (pp += ω·∇N(λ·pp), ω = 0.05·wispiness
//! then halved, λ = 10 then ×1.99); d = Σ₀⁴ 0.5ⁱ⁺¹·N(1.99ⁱ·pp);
//! d = clamp((1 − p.y)·4.5·density·d, 0, 1) + 2·max(0, ½ − p.y), clamped to [0, 1].

use super::coeff::{Coefficient, PointProperties};
use super::majorant::{MajorantSegment, ray_in_medium};
use crate::math::noise::{dnoise, noise};
use crate::math::{Bounds3, Rgb, SampledSpectrum, Transform, Vec3};
use crate::ray::Ray;
use crate::spectrum::sampled::SampledWavelengths;

/// A `cloud` medium as the scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct CloudDesc {
    /// Medium space → render space (the CTM at `MakeNamedMedium`).
    pub medium_to_render: Transform,
    /// The box the cloud fills in medium space (`p0`, `p1`).
    pub bounds: Bounds3,
    /// σ_a (RGB, reduced as unbounded).
    pub sigma_a: Rgb,
    /// σ_s.
    pub sigma_s: Rgb,
    /// Henyey–Greenstein asymmetry `g`.
    pub g: f32,
    /// `density` (default 1).
    pub density: f32,
    /// `wispiness` (default 1).
    pub wispiness: f32,
    /// `frequency` (default 5).
    pub frequency: f32,
}

/// pbrt-v4's `CloudMedium`, ready to render.
#[derive(Clone, Debug)]
pub struct CloudMedium {
    render_to_medium: Transform,
    bounds: Bounds3,
    sigma_a: Coefficient,
    sigma_s: Coefficient,
    g: f32,
    density: f32,
    wispiness: f32,
    frequency: f32,
}

impl CloudMedium {
    /// Prepares the medium.
    pub fn new(desc: CloudDesc) -> CloudMedium {
        CloudMedium {
            render_to_medium: desc.medium_to_render.inverse(),
            bounds: desc.bounds,
            sigma_a: Coefficient::new(desc.sigma_a),
            sigma_s: Coefficient::new(desc.sigma_s),
            g: desc.g,
            density: desc.density,
            wispiness: desc.wispiness,
            frequency: desc.frequency,
        }
    }

    /// The Henyey–Greenstein asymmetry of its phase function.
    pub fn g(&self) -> f32 {
        self.g
    }

    /// The cloud's density in [0, 1] at medium-space `p`.
    pub fn density(&self, p: Vec3) -> f32 {
        let mut pp = p * self.frequency;
        if self.wispiness > 0.0 {
            let (mut omega, mut lambda) = (0.05 * self.wispiness, 10.0f32);
            for _ in 0..2 {
                pp += omega * dnoise(lambda * pp);
                omega *= 0.5;
                lambda *= 1.99;
            }
        }
        let mut d = 0.0;
        let (mut omega, mut lambda) = (0.5f32, 1.0f32);
        for _ in 0..5 {
            d += omega * noise(lambda * pp);
            omega *= 0.5;
            lambda *= 1.99;
        }
        let d = ((1.0 - p.y) * 4.5 * self.density * d).clamp(0.0, 1.0);
        let d = d + 2.0 * (0.5 - p.y).max(0.0);
        d.clamp(0.0, 1.0)
    }

    /// σ_a, σ_s (and no emission) at render-space point `p`.
    pub fn properties(&self, p: Vec3, lambda: Option<&SampledWavelengths>) -> PointProperties {
        let d = self.density(self.render_to_medium.point(p));
        PointProperties {
            sigma_a: self.sigma_a.at(lambda) * d,
            sigma_s: self.sigma_s.at(lambda) * d,
            le: SampledSpectrum::ZERO,
        }
    }

    /// The one majorant segment of render-space `ray` over [0, t_max]: the part inside the
    /// box, with σ_maj = σ_a + σ_s (the density never exceeds 1); `None` if it misses.
    pub fn majorant(
        &self,
        ray: &Ray,
        t_max: f32,
        lambda: Option<&SampledWavelengths>,
    ) -> Option<MajorantSegment> {
        let (_, _, t0, t1) = ray_in_medium(&self.render_to_medium, &self.bounds, ray, t_max)?;
        Some(MajorantSegment {
            t_min: t0,
            t_max: t1,
            sigma_maj: self.sigma_a.at(lambda) + self.sigma_s.at(lambda),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud(wispiness: f32) -> CloudMedium {
        CloudMedium::new(CloudDesc {
            medium_to_render: Transform::IDENTITY,
            bounds: Bounds3::new(Vec3::splat(-1.0), Vec3::ONE),
            sigma_a: Rgb::ONE,
            sigma_s: Rgb::ONE,
            g: 0.0,
            density: 10.0,
            wispiness,
            frequency: 5.0,
        })
    }

    #[test]
    fn density_is_a_clamped_noise_sum_that_fills_the_bottom() {
        let c = cloud(0.0);
        // Without wisps, by the formula: d = Σ 0.5ⁱ⁺¹·N(1.99ⁱ·5p).
        let p = Vec3::new(0.13, 0.7, -0.41);
        let pp = p * 5.0;
        let sum: f32 = (0..5)
            .map(|i| 0.5f32.powi(i + 1) * noise(1.99f32.powi(i) * pp))
            .sum();
        let want = ((1.0 - p.y) * 45.0 * sum).clamp(0.0, 1.0);
        assert!((c.density(p) - want).abs() < 1e-5);
        // Below y = 0 the height term 2·(½ − y) ≥ 1 saturates it.
        for x in 0..10 {
            assert_eq!(c.density(Vec3::new(x as f32 * 0.1, -0.2, 0.3)), 1.0);
        }
        let w = cloud(1.0);
        for i in 0..200 {
            let p = Vec3::new(i as f32 * 0.01 - 1.0, i as f32 * 0.007, 0.2);
            let d = w.density(p);
            assert!((0.0..=1.0).contains(&d));
        }
    }

    #[test]
    fn one_majorant_over_the_box() {
        let c = cloud(1.0);
        let ray = Ray::new(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
        let s = c.majorant(&ray, 100.0, None).unwrap();
        assert_eq!((s.t_min, s.sigma_maj), (2.0, SampledSpectrum::splat(2.0)));
        assert!((s.t_max - 4.0).abs() < 1e-5);
        assert!(c.majorant(&ray, 1.0, None).is_none());
        let p = c.properties(Vec3::new(0.0, -0.9, 0.0), None);
        assert_eq!(p.sigma_a + p.sigma_s, SampledSpectrum::splat(2.0));
    }
}
