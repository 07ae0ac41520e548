//! Per-thread ray counters for statistics: [`count_ray`] is called by every scene query, and a
//! render reads [`rays_traced`] before and after its work (a leaf module, so that the scene can
//! count without depending on the renderer).

use std::cell::Cell;

thread_local! {
    static RAYS: Cell<u64> = const { Cell::new(0) };
}

/// Counts one traced ray on this thread (for statistics).
#[inline]
pub fn count_ray() {
    RAYS.with(|r| r.set(r.get() + 1));
}

/// This thread's ray count so far.
pub fn rays_traced() -> u64 {
    RAYS.with(|r| r.get())
}
