//! Acceleration structures: the course's "keep the nearest valid hit over all objects", without
//! testing every object.

mod bvh;
mod mesh;

pub use bvh::Bvh;
pub use mesh::MeshBvh;
