//! Random numbers, samplers and warps from the unit square to the shapes light travels through.

mod hash;
pub(crate) mod piecewise;
mod sampler;
mod warp;

pub use hash::{hash_u64, mix_bits, permutation_element, u32_to_unit_f32};
pub use piecewise::{PiecewiseConstant1D, PiecewiseConstant2D};
pub use sampler::{Sampler, SamplerKind};
pub use warp::*;
