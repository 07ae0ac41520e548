//! The OBJ and MTL readers on arbitrary text; a parsed OBJ is also turned into meshes, where
//! index checks matter.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(obj) = lancer_scene::obj::parse_obj(text, "fuzz.obj") {
        let _ = obj.meshes_by_material();
    }
    let _ = lancer_scene::obj::parse_mtl(text, "fuzz.mtl");
});
