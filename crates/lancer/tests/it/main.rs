//! The integration tests of this crate, one module per file, built as one test binary so
//! that CI links and compiles the shared helpers once rather than once per file.

mod common;

mod area_lights;
mod bilinear;
mod bsdf_stats;
mod bvh_props;
mod curves;
mod hair_stats;
mod light_paths;
mod measured;
mod mlt;
mod quadrics;
mod sampling_stats;
mod sdf;
mod shape_props;
mod splats;
mod volpath;
mod voxels;
mod whitted_analytic;
