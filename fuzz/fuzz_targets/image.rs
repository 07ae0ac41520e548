//! Texture loading (PNG, JPEG, EXR) on arbitrary bytes; the first byte picks the decoder so
//! that one corpus feeds all three.
#![no_main]

use lancer_scene::image_read::{Encoding, decode_image};
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Some((&pick, bytes)) = data.split_first() else {
        return;
    };
    let name = match pick % 3 {
        0 => "fuzz.png",
        1 => "fuzz.jpg",
        _ => "fuzz.exr",
    };
    if let Ok(image) = decode_image(Path::new(name), bytes, Encoding::Srgb) {
        let _ = image.float_image(false);
    }
});
