//! Participating media: sampled and procedural density grids and their majorants.

pub mod cloud;
pub mod coeff;
pub mod grid;
pub mod grids;
pub mod majorant;
pub mod nanovdb;
pub mod rgb_grid;
pub mod uniform_grid;
pub mod vdb;
