//! How next-event estimation chooses a light (pbrt-v4's `"string lightsampler"`): uniformly,
//! in proportion to power, or by the light BVH's estimate of each light's contribution at the
//! point being lit (pbrt-v4's default).

use super::bounds::LightExtent;
use super::bvh::BvhLightSampler;
use super::distribution::LightDistribution;
use super::sample::LightSampleContext;

/// Which light sampler (the integrator's `lightsampler`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSamplerKind {
    /// Every light equally likely.
    Uniform,
    /// In proportion to emitted power, whatever the point.
    Power,
    /// pbrt-v4's `BVHLightSampler`: by importance at the point (the default).
    #[default]
    Bvh,
}

impl LightSamplerKind {
    /// The kind named `name` in pbrt-v4 (`uniform`, `power`, `bvh`).
    pub fn from_pbrt(name: &str) -> Option<LightSamplerKind> {
        Some(match name {
            "uniform" => LightSamplerKind::Uniform,
            "power" => LightSamplerKind::Power,
            "bvh" => LightSamplerKind::Bvh,
            _ => return None,
        })
    }
}

/// A light sampler built for a scene's lights.
#[derive(Clone, Debug)]
pub enum LightSampler {
    /// A fixed distribution over the lights (uniform or by power).
    Fixed(LightDistribution),
    /// The light BVH.
    Bvh(Box<BvhLightSampler>),
}

impl Default for LightSampler {
    fn default() -> Self {
        LightSampler::Fixed(LightDistribution::default())
    }
}

impl LightSampler {
    /// The sampler of `kind` over lights of extents `lights` ([`super::Light::extent`]);
    /// `power` is the distribution by power the scene already holds (so that `power` chooses
    /// exactly as it always did).
    pub fn new(
        kind: LightSamplerKind,
        lights: &[LightExtent],
        power: &LightDistribution,
    ) -> LightSampler {
        match kind {
            LightSamplerKind::Uniform => {
                LightSampler::Fixed(LightDistribution::new(&vec![1.0; lights.len()]))
            }
            LightSamplerKind::Power => LightSampler::Fixed(power.clone()),
            LightSamplerKind::Bvh => LightSampler::Bvh(Box::new(BvhLightSampler::new(lights))),
        }
    }

    /// Bytes of the tables.
    pub fn memory_bytes(&self) -> usize {
        match self {
            LightSampler::Fixed(d) => d.memory_bytes(),
            LightSampler::Bvh(b) => b.memory_bytes(),
        }
    }

    /// A light for the point `ctx`, chosen with the uniform number `u`, and its probability.
    #[inline]
    pub fn sample(&self, ctx: &LightSampleContext, u: f32) -> Option<(usize, f32)> {
        match self {
            LightSampler::Fixed(d) => d.sample(u),
            LightSampler::Bvh(b) => b.sample(ctx, u),
        }
    }

    /// The probability that [`LightSampler::sample`] chooses light `i` at `ctx`.
    #[inline]
    pub fn pmf(&self, ctx: &LightSampleContext, i: usize) -> f32 {
        match self {
            LightSampler::Fixed(d) => d.pmf(i),
            LightSampler::Bvh(b) => b.pmf(ctx, i),
        }
    }
}
