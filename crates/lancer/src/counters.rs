//! Per-thread counters for statistics: every scene query calls [`count_ray`], bidirectional
//! integrators [`count_light_path`] and [`count_connection`], and a render reads [`counts`]
//! before and after its work (a leaf module, so that the scene and the integrators can count
//! without depending on the renderer).

use std::cell::Cell;

thread_local! {
    static RAYS: Cell<u64> = const { Cell::new(0) };
    static LIGHT_PATHS: Cell<u64> = const { Cell::new(0) };
    static CONNECTIONS: Cell<u64> = const { Cell::new(0) };
}

/// What this thread has counted so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    /// Rays traced (camera, bounce, shadow and connection rays alike).
    pub rays: u64,
    /// Light subpaths started (bdpt, lightpath, mlt).
    pub light_paths: u64,
    /// Connections tried between a light subpath's vertex and a camera subpath's, the lens or
    /// a sampled light point included (bdpt's strategies with s ≥ 1).
    pub connections: u64,
}

impl Counts {
    /// The counts of the work done since `before` (on the same thread).
    pub fn since(self, before: Counts) -> Counts {
        Counts {
            rays: self.rays - before.rays,
            light_paths: self.light_paths - before.light_paths,
            connections: self.connections - before.connections,
        }
    }
}

#[inline]
fn bump(c: &'static std::thread::LocalKey<Cell<u64>>) {
    c.with(|r| r.set(r.get() + 1));
}

/// Counts one traced ray on this thread.
#[inline]
pub fn count_ray() {
    bump(&RAYS);
}

/// Counts one light subpath started on this thread.
#[inline]
pub fn count_light_path() {
    bump(&LIGHT_PATHS);
}

/// Counts one connection tried on this thread.
#[inline]
pub fn count_connection() {
    bump(&CONNECTIONS);
}

/// This thread's ray count so far.
pub fn rays_traced() -> u64 {
    RAYS.with(|r| r.get())
}

/// Everything this thread has counted so far.
pub fn counts() -> Counts {
    Counts {
        rays: rays_traced(),
        light_paths: LIGHT_PATHS.with(|r| r.get()),
        connections: CONNECTIONS.with(|r| r.get()),
    }
}
