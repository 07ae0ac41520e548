//! The integration tests of this crate, one module per file, built as one test binary so
//! that CI links and compiles the shared helpers once rather than once per file.

mod common;

mod alpha;
mod area_image;
mod coincident_media;
mod coverage_table;
mod curves_bilinear;
mod displaced;
mod envmap;
mod gltf;
mod imagemap;
mod mesh_scene;
mod motion;
mod objmesh;
mod pbrt_parity;
mod pbrt_semantics;
mod plymesh;
mod sdf_scene;
mod spectra;
mod vox;
