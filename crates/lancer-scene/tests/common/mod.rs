//! Helpers shared by the scene readers' integration tests.

pub mod scratch;

pub use scratch::ScratchDir;
