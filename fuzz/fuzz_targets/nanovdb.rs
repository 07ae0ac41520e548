//! The NanoVDB reader (segments, ZIP, the trees of formats 19 and 32) on arbitrary bytes: every grid the
//! file lists is read, and a few lookups made in what comes back.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(grids) = lancer_scene::nanovdb::list_grids(data) else {
        return;
    };
    for g in grids.iter().take(4) {
        if let Ok(Some(grid)) = lancer_scene::nanovdb::read_float_grid(data, &g.name) {
            let [lo, hi] = grid.index_bounds();
            let _ = grid.value(lo[0], lo[1], lo[2]);
            let _ = grid.sample_index(glam::Vec3A::new(hi[0] as f32, 0.5, -3.25));
            let _ = grid.max_in(lo, [lo[0] + 2, lo[1] + 2, lo[2] + 2]);
        }
    }
});
