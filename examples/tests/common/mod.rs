//! Helpers for the course test.

pub mod scratch;

pub use scratch::ScratchDir;
