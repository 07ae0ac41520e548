//! # lancer — a physically based ray tracer
//!
//! The course "lancer de rayons", for real. To make an image, cast one ray per pixel from a
//! [`camera`], describe it as p(t) = o + t·d ([`ray`]), intersect it with every object
//! ([`shape`], through the [`accel`] structure), keep the nearest valid hit, then find how that
//! point is lit ([`light`], [`material`], [`integrator`]). Samples accumulate in a [`film`]
//! and are written as PNG or EXR ([`image_io`]).
//!
//! Scenes arrive as a plain-data [`scene::desc::SceneDesc`] (from the `lancer-scene` crate's
//! readers or from code) and are built into an immutable [`Scene`].

pub mod accel;
pub mod camera;
pub mod counters;
pub mod film;
pub mod filter;
pub mod gbuffer;
pub mod image;
pub mod image_io;
pub mod integrator;
pub mod light;
pub mod material;
pub mod math;
pub mod medium;
pub mod ray;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod shape;
pub mod spectrum;
pub mod texture;

pub use scene::Scene;
pub use scene::desc::SceneDesc;
