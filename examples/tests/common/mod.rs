//! Helpers for the course test.

pub use lancer_testing::ScratchDir;
