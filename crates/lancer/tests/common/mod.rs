//! Helpers shared by the library's integration tests. Each test crate uses a part of them.
#![allow(dead_code)]

pub mod chi2;
pub mod shapes;
