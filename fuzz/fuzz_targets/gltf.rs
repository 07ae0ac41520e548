//! The glTF 2.0 reader (`.gltf` JSON and `.glb` binary) on arbitrary bytes, through the same
//! entry point as `lancer render model.glb`: the bytes are written to a file in a private
//! temporary folder (external buffers and images resolve there, and are missing).
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

fn input_path() -> &'static PathBuf {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("lancer-fuzz-gltf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("a temporary folder");
        dir.join("input.glb")
    })
}

fuzz_target!(|data: &[u8]| {
    let path = input_path();
    if std::fs::write(path, data).is_err() {
        return;
    }
    if let Ok(loaded) = lancer_scene::gltf::load_gltf_scene(path) {
        let _ = lancer::Scene::build(&loaded.desc);
    }
});
