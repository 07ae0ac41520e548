//! vcm through its film loop: a white furnace, agreement with the path tracer on bdpt's small
//! diffuse room (area and point light), the shrinking radius, and the same bits whatever the
//! thread count, the split by samples or by tiles.

use super::*;
use crate::film::Film;
use crate::integrator::Integrator;
use crate::integrator::bdpt::tests::{
    assert_furnace, compare, furnace_desc, plane_under_sky, room_desc,
};
use crate::integrator::test_scenes::{H, W, sphere};
use crate::material::{DielectricMaterial, MaterialDesc};
use crate::render::{RenderSettings, RenderStats};
use crate::scene::desc::SceneDesc;
use crate::spectrum::Ior;
use crate::texture::FloatTex;

/// vcm of `max_depth` bounces, default radius and α.
fn vcm(max_depth: u32) -> Integrator {
    Integrator::Vcm(VcmOptions {
        max_depth,
        radius: None,
        alpha: 0.75,
    })
}

/// Renders `settings` of `desc` on `threads` threads into a fresh film over `settings.bounds`.
fn render_on(desc: &SceneDesc, settings: &RenderSettings, threads: usize) -> (Film, RenderStats) {
    crate::render::testing::render_on(desc, settings, threads, 8)
}

/// `desc` at `spp` samples and `seed`, RGB mode.
fn rgb(desc: &SceneDesc, spp: u32, seed: u64) -> RenderSettings {
    let mut d = desc.clone();
    d.sampler.spp = spp;
    d.sampler.seed = seed;
    RenderSettings {
        spectral: false,
        ..RenderSettings::from_desc(&d)
    }
}

#[test]
fn radius_shrinks_by_alpha() {
    assert_eq!(radius_at(0.5, 0.75, 0), 0.5);
    // r_i = r_1 · i^((α − 1)/2): the 16th iteration at α = 0.75 has r_1 · 16^(−1/8) = r_1/√2.
    assert!((radius_at(0.5, 0.75, 15) - 0.5 / 2f32.sqrt()).abs() < 1e-6);
    // α = 1 keeps it.
    assert_eq!(radius_at(0.5, 1.0, 99), 0.5);
}

#[test]
fn white_furnace() {
    // Here the sky's light reaches the sphere by emission hits, light sampling, connections
    // to its light paths and merges; a radius the 432 light paths of a 24 × 18 image fill, so
    // that merges carry weight too.
    let desc = furnace_desc(Integrator::Vcm(VcmOptions {
        max_depth: 5,
        radius: Some(0.05),
        alpha: 0.75,
    }));
    let (film, stats) = render_on(&desc, &rgb(&desc, 64, 9), 2);
    assert_eq!(stats.light_paths, 64 * (W * H) as u64);
    assert!(stats.merges > 0);
    assert_furnace(&film.image(1.0));
}

#[test]
fn an_infinite_plane_is_lit_by_the_sky_beyond_the_scene_bounds() {
    // Past the scene's disk no light subpath arrives: light sampling and the sky's emission
    // hits must weigh all there (vcm's horizon was black as bdpt's was).
    let desc = plane_under_sky(vcm(3));
    let mut p = desc.clone();
    p.integrator = Integrator::Path {
        max_depth: 3,
        regularize: false,
    };
    let (want, _) = render_on(&p, &rgb(&p, 64, 1), 2);
    let (got, _) = render_on(&desc, &rgb(&desc, 64, 2), 2);
    let (worst, ratio) = compare(&got.image(1.0), &want.image(1.0));
    assert!(
        worst < 0.1 && (ratio - 1.0).abs() < 0.02,
        "worst block {worst}, mean ratio {ratio}"
    );
}

#[test]
fn agrees_with_path_tracing_on_a_diffuse_room() {
    for area in [true, false] {
        let reference = room_desc(area, vcm(5));
        let path = Integrator::Path {
            max_depth: 5,
            regularize: false,
        };
        let mut p = reference.clone();
        p.integrator = path;
        let (want, _) = render_on(&p, &rgb(&p, 1024, 1), 2);
        // The default radius, and one large enough for merges to matter.
        for radius in [None, Some(0.05)] {
            let mut d = reference.clone();
            d.integrator = Integrator::Vcm(VcmOptions {
                max_depth: 5,
                radius,
                alpha: 0.75,
            });
            let (got, stats) = render_on(&d, &rgb(&d, 256, 2), 2);
            let (worst, ratio) = compare(&got.image(1.0), &want.image(1.0));
            assert!(
                worst < 0.07 && (ratio - 1.0).abs() < 0.015,
                "area light {area}, radius {radius:?}: worst block {worst}, mean ratio {ratio}"
            );
            assert!(stats.photons > 0);
        }
    }
}

/// bdpt's room (area light) with a flint glass sphere on the floor: caustics that only
/// merges and light paths find.
fn room_with_glass() -> SceneDesc {
    let mut d = room_desc(true, vcm(6));
    d.materials
        .push(MaterialDesc::Dielectric(DielectricMaterial {
            eta: Ior::named_glass("glass-F11").unwrap(),
            uroughness: FloatTex::Const(0.0),
            vroughness: FloatTex::Const(0.0),
            remap_roughness: false,
        }));
    let glass = d.materials.len() as u32 - 1;
    d.shapes
        .push(sphere(Vec3::new(0.2, 0.35, 0.0), 0.35, glass));
    d.integrator = Integrator::Vcm(VcmOptions {
        max_depth: 6,
        radius: Some(0.03),
        alpha: 0.75,
    });
    d.sampler.spp = 6;
    d
}

#[test]
fn bits_do_not_depend_on_threads_sample_ranges_or_tiles() {
    let d = room_with_glass();
    let settings = RenderSettings::from_desc(&d);
    assert!(settings.spectral);
    let (one, s1) = render_on(&d, &settings, 1);
    let (three, s3) = render_on(&d, &settings, 3);
    assert_eq!(one, three);
    assert_eq!(s1, s3);
    assert!(s1.merges > 0 && one.pixels.iter().any(|p| p.value()[0] > 0.0));
    // Split by samples (0..2, 2..6), each part a film of its own, merged.
    let mut merged = Film::new(W, H, settings.bounds);
    for samples in [0..2, 2..6] {
        let part = RenderSettings {
            samples,
            ..settings.clone()
        };
        merged.merge_film(&render_on(&d, &part, 2).0);
    }
    assert_eq!(merged, one);
    // Split by tiles (left and right), each part splatting its own pixels' light paths.
    let mut merged = Film::new(W, H, settings.bounds);
    for (x0, x1) in [(0, 10), (10, W as i32)] {
        let mut part = settings.clone();
        part.bounds.x0 = x0;
        part.bounds.x1 = x1;
        merged.merge_film(&render_on(&d, &part, 2).0);
    }
    assert_eq!(merged, one);
}
