//! pbrt-v4 scene files (with pbrt-v3's quadrics and block directives, and lancer's extensions:
//! the infinite `plane` shape, the `whitted`, `normals` and `depth` integrators).
//!
//! [`lexer`] cuts the text into tokens, [`parser`] reads directives and follows `Include`s
//! (relative names found through [`search_path`]), [`params`] types parameter lists, and
//! [`builder`] keeps the graphics state that turns the directives into a `SceneDesc`. Each
//! directive's parameters become lancer's plain data in the file of its kind, as pbrt-v4 puts
//! `X::Create` beside each type: [`shapes`] (with [`sdf`]), [`materials`], [`textures`],
//! [`lights`], [`media`], [`cameras`] and [`options`] (film, sampler, filter, integrator), all
//! reading through [`convert`]'s shared [`convert::Reader`]. [`singular`] places shapes under a
//! transformation with no inverse, as pbrt-v4 does.

pub mod area_image;
pub mod builder;
pub mod cameras;
pub mod convert;
pub mod lexer;
pub mod light_spectra;
pub mod lights;
pub mod materials;
pub mod media;
pub mod media_grids;
pub mod options;
pub mod params;
pub mod parser;
pub mod sdf;
pub mod search_path;
pub mod shapes;
pub mod singular;
pub mod textures;
