//! The integration tests of this crate, one module per file, built as one test binary so
//! that CI links and compiles the shared helpers once rather than once per file.

mod common;

mod bdpt_strategies;
mod bench_scene;
mod caustics;
mod course_scenes;
mod denoise;
mod gbuffer;
mod gltf;
mod hostile;
mod img;
mod light_stats;
mod malformed;
mod meshes;
mod motion_workflow;
mod nan_stress;
mod orientation;
mod path_tracing;
mod pbrt_habits;
mod preview;
mod sdf_shapes;
mod spectral_film;
mod sppm;
mod vcm;
mod workflow;
