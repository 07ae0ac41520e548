//! The signed-distance expression language on arbitrary text: parsing, then (for valid
//! expressions) bounds, the Lipschitz bound and evaluation at a few points.
#![no_main]

use lancer::shape::SdfFunction;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(f) = SdfFunction::parse(text) else {
        return;
    };
    let b = f.bounds();
    let _ = f.lipschitz(&b);
    for p in [[0.0, 0.0, 0.0], [0.3, -1.2, 2.5], [1e3, 1e-3, -7.0]] {
        let p = glam::DVec3::from_array(p);
        let _ = f.eval(p);
        let _ = f.gradient(p, 1e-4);
    }
});
