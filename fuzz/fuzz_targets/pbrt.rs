//! The pbrt-v4 lexer, parser and scene builder on arbitrary text, then the scene build (BVH,
//! lights) when the description is small enough to build quickly.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // Relative names point into a folder that does not exist: a fuzzed Include or plymesh
    // must fail cleanly, never read the machine's files.
    let Ok(loaded) =
        lancer_scene::load_pbrt_str(text, "fuzz.pbrt", Path::new("/nonexistent-lancer-fuzz"))
    else {
        return;
    };
    let _ = lancer::Scene::build(&loaded.desc);
});
