//! The PLY reader (ASCII, binary little and big endian) on arbitrary bytes.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = lancer_scene::ply::parse_ply(data, "fuzz.ply");
});
