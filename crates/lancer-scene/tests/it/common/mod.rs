//! Helpers shared by the scene readers' integration tests.

pub use lancer_testing::ScratchDir;
