//! The measured-BRDF reader (RGL `.bsdf` tensor files) on arbitrary bytes: the tables are
//! built, then evaluated and sampled at a few directions.
#![no_main]

use lancer::material::{BxDF, MeasuredBxdf, MeasuredData, TransportMode};
use lancer::math::{Vec2, Vec3};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(d) = MeasuredData::from_bytes(data, "fuzz.bsdf") else {
        return;
    };
    // Leaked as a scene's BRDFs are (each kept for the process's life).
    let d: &'static MeasuredData = Box::leak(Box::new(d));
    let b = BxDF::Measured(MeasuredBxdf::new(d, None));
    let wo = Vec3::new(0.3, -0.2, 0.93);
    let wi = Vec3::new(-0.5, 0.1, 0.86);
    let _ = b.f(wo, wi, TransportMode::Radiance);
    let _ = b.pdf(wo, wi, TransportMode::Radiance);
    let _ = b.sample_f(wo, 0.5, Vec2::new(0.25, 0.75), TransportMode::Radiance);
});
