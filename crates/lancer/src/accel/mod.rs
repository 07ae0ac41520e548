//! Acceleration structures: the course's "keep the nearest valid hit over all objects", without
//! testing every object.

mod bvh;
mod indexed;
mod mesh;
pub mod packet;
mod simd;
mod tri4;

pub use bvh::{Bvh, Leaf, MAX_LEAF};
pub use indexed::IndexedTris;
pub use mesh::MeshBvh;
pub use tri4::{Packet, Tri4};

/// Asks the memory system for the cache line holding `p`, to be read soon. Any address will
/// do: a prefetch never faults.
#[inline(always)]
pub(crate) fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        // SAFETY: a prefetch never faults, whatever the address.
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p as *const i8) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}
