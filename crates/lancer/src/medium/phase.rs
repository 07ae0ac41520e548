//! The Henyey–Greenstein phase function, with pbrt-v4's conventions: `wo` points back along
//! the incoming ray, `wi` towards where light comes from, and g > 0 scatters forward (wi near
//! −wo).

use crate::math::{Frame, Vec2, Vec3};
use std::f32::consts::PI;

/// p(cos θ) = (1 − g²) / (4π (1 + g² + 2g cos θ)^{3/2}), θ the angle between `wo` and `wi`
/// (so cos θ = −1 is straight on when `wo` points back along the ray).
#[inline]
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g + 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * PI * denom * denom.max(0.0).sqrt())
}

/// A sampled direction and its density (which is also the phase function's value: the
/// sampling is exact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseSample {
    /// The value p(wo, wi).
    pub p: f32,
    /// The sampled direction.
    pub wi: Vec3,
    /// Its density per solid angle.
    pub pdf: f32,
}

/// Henyey–Greenstein scattering with asymmetry `g` ∈ (−1, 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HgPhaseFunction {
    /// Mean cosine of the scattering angle (0 isotropic, > 0 forward).
    pub g: f32,
}

impl HgPhaseFunction {
    /// The phase function's value for the pair (`wo`, `wi`), both unit length.
    #[inline]
    pub fn p(&self, wo: Vec3, wi: Vec3) -> f32 {
        henyey_greenstein(wo.dot(wi), self.g)
    }

    /// Density of sampling `wi` from `wo`: equal to [`HgPhaseFunction::p`].
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.p(wo, wi)
    }

    /// Samples `wi` by inverting the distribution of cos θ:
    /// cos θ = −1/(2g) · (1 + g² − ((1 − g²)/(1 + g − 2g·u₀))²) (1 − 2u₀ when |g| < 10⁻³),
    /// φ = 2π·u₁, in a frame about `wo`.
    pub fn sample(&self, wo: Vec3, u: Vec2) -> Option<PhaseSample> {
        let g = self.g;
        let cos_theta = if g.abs() < 1e-3 {
            1.0 - 2.0 * u.x
        } else {
            let s = (1.0 - g * g) / (1.0 + g - 2.0 * g * u.x);
            -1.0 / (2.0 * g) * (1.0 + g * g - s * s)
        }
        .clamp(-1.0, 1.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let local = crate::sampling::spherical_direction_turn(sin_theta, cos_theta, u.y);
        let wi = Frame::from_z(wo).from_local(local);
        let pdf = henyey_greenstein(cos_theta, g);
        (pdf > 0.0 && pdf.is_finite()).then_some(PhaseSample { p: pdf, wi, pdf })
    }
}
