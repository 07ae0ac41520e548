//! Participating media: sampled and procedural density grids and their majorants.

pub mod coeff;
pub mod grid;
pub mod majorant;
pub mod rgb_grid;
pub mod uniform_grid;
pub mod cloud;
