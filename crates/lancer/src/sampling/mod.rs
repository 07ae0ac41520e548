//! Random numbers, samplers and warps from the unit square to the shapes light travels through.

pub mod halton;
mod hash;
mod linear2d;
pub(crate) mod piecewise;
mod pmj02;
mod randomization;
mod rng;
mod sampler;
pub mod sobol;
mod sobol_block;
mod warp;

pub use hash::{hash_u64, mix_bits, permutation_element, u32_to_unit_f32};
pub use linear2d::Linear2D;
pub use piecewise::{PiecewiseConstant1D, PiecewiseConstant2D};
pub use randomization::Randomization;
pub use rng::Pcg32;
pub use sampler::{Sampler, SamplerKind};
pub use warp::*;

/// The largest float below 1 (pbrt's `OneMinusEpsilon`): where a sample in [0, 1) must stay.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Where an estimator takes its random numbers, one dimension after the other: a pixel
/// sample's [`Sampler`], or the primary-sample vector of a Markov chain (`mlt`), which
/// bidirectional path tracing's subpaths and connections draw from alike.
pub trait SampleSource {
    /// The next dimension, in [0, 1).
    fn get_1d(&mut self) -> f32;
    /// The next two dimensions.
    fn get_2d(&mut self) -> crate::math::Vec2;
}

impl SampleSource for Sampler {
    #[inline(always)]
    fn get_1d(&mut self) -> f32 {
        Sampler::get_1d(self)
    }

    #[inline(always)]
    fn get_2d(&mut self) -> crate::math::Vec2 {
        Sampler::get_2d(self)
    }
}

/// Power heuristic (β = 2) weight of a sample taken with density `f` against another strategy
/// of density `g`: w = f² / (f² + g²) (Veach 1997). An infinite `f` (a delta strategy) gets
/// all the weight.
#[inline]
pub fn power_heuristic(f: f32, g: f32) -> f32 {
    let (f2, g2) = (f * f, g * g);
    if f2.is_infinite() {
        return 1.0;
    }
    if f2 + g2 == 0.0 { 0.0 } else { f2 / (f2 + g2) }
}
