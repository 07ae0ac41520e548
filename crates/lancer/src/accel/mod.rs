//! Acceleration structures: the course's "keep the nearest valid hit over all objects", without
//! testing every object.

mod bvh;
mod indexed;
mod mesh;
pub mod packet;
mod simd;
mod tri4;

pub use bvh::{Bvh, MAX_LEAF};
pub use indexed::IndexedTris;
pub use mesh::MeshBvh;
pub use tri4::{Packet, Tri4};
