//! Participating media: sampled and procedural density grids and their majorants.

pub mod grid;
pub mod majorant;
