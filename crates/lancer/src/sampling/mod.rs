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
