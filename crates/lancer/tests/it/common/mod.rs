//! Helpers shared by the library's integration tests. Each test crate uses a part of them.
//!
//! `scratch.rs` beside them (scratch folders that go away) is, for now, only included by the
//! unit tests; declare it here when an integration test writes files.
#![allow(dead_code)]

pub mod bsdf_file;
pub mod chi2;
pub mod lit_floor;
pub mod shapes;
pub mod units;
