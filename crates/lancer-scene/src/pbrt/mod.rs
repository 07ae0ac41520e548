//! pbrt-v4 scene files (with pbrt-v3's quadrics and block directives, and lancer's extensions:
//! the infinite `plane` shape, the `whitted`, `normals` and `depth` integrators).
//!
//! [`lexer`] cuts the text into tokens, [`parser`] reads directives and follows `Include`s,
//! [`params`] types parameter lists, [`convert`] maps each directive's parameters onto lancer's
//! plain data, and [`builder`] keeps the graphics state that turns them into a `SceneDesc`.

pub mod builder;
pub mod convert;
pub mod lexer;
pub mod params;
pub mod parser;
pub mod sdf;
