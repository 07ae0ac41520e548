//! The MagicaVoxel `.vox` reader on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = lancer_scene::vox::parse_vox(data, "fuzz.vox");
});
