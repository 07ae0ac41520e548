//! bdpt and light tracing through participating media: the room of [`super::tests`] filled
//! with a chromatic fog against `volpath`, the densities the walks store at medium vertices,
//! the MIS weights of paths with medium vertices, and `simplevolpath`.

use super::tests::{
    DensityChecks, assert_mis_weights_sum_to_one, bdpt, check_walk_densities, compare, render,
    room_desc, surface_vertex,
};
use super::vertex::{Kind, Vertex};
use crate::integrator::Integrator;
use crate::light::AreaLight;
use crate::material::{DiffuseMaterial, MaterialDesc};
use crate::math::{Rgb, SampledSpectrum, Vec3, normalize};
use crate::medium::{HgPhaseFunction, HomogeneousDesc, MediumDesc, MediumInterface};
use crate::scene::Scene;
use crate::scene::desc::{AreaLightDesc, SceneDesc};
use crate::texture::SpectrumTex;

/// A homogeneous fog whose coefficients differ by channel (so that the lanes' densities
/// differ), scattering forward a little; `scatter` multiplies σ_s.
fn fog(scatter: f32) -> MediumDesc {
    MediumDesc::Homogeneous(HomogeneousDesc {
        sigma_a: Rgb::new(0.05, 0.1, 0.15),
        sigma_s: Rgb::new(0.2, 0.35, 0.5) * scatter,
        scale: 1.0,
        le: Rgb::ZERO,
        le_scale: 0.0,
        g: 0.3,
    })
}

/// The interface of a shape in the fog on both sides.
const IN_FOG: MediumInterface = MediumInterface {
    inside: Some(0),
    outside: Some(0),
};

/// [`room_desc`] filled with `fog`: the camera, the light (the area light's quad, or the point
/// light) and every ray are in it.
fn foggy_room_desc(area: bool, integrator: Integrator, fog: MediumDesc) -> SceneDesc {
    let mut d = room_desc(area, integrator);
    d.media = vec![fog];
    d.camera_medium = Some(0);
    if area {
        d.shapes.last_mut().unwrap().medium_interface = Some(IN_FOG);
    } else {
        d.light_media = vec![Some(0)];
    }
    d
}

fn volpath(max_depth: u32) -> Integrator {
    Integrator::VolPath {
        max_depth,
        regularize: false,
    }
}

#[test]
fn bdpt_and_light_tracing_through_fog_agree_with_volpath() {
    // volpath itself is noisy in this fog (two of its 1024-sample images differ by up to 10 %
    // on a block, 1.6 % on the mean), hence bounds above that noise; what a missing factor
    // does is far beyond them (checked below).
    for area in [true, false] {
        let scene = Scene::build(&foggy_room_desc(area, bdpt(3), fog(1.0))).unwrap();
        let reference = render(&scene, volpath(3), 1024, 1, None);
        let b = render(&scene, bdpt(3), 128, 2, None);
        let (worst, ratio) = compare(&b, &reference);
        assert!(
            worst < 0.2 && (ratio - 1.0).abs() < 0.04,
            "bdpt, area {area}: worst block {worst}, mean ratio {ratio}"
        );
        // Light tracing is noisier still where fog scatters next to the lens.
        let lp = render(&scene, Integrator::LightPath { max_depth: 3 }, 256, 3, None);
        let (worst, ratio) = compare(&lp, &reference);
        assert!(
            worst < 0.5 && (ratio - 1.0).abs() < 0.04,
            "lightpath, area {area}: worst block {worst}, mean ratio {ratio}"
        );
        // The room without its fog (no transmittance at all) is 3 times as bright, and with
        // σ_s × 0.7 (one factor of σ_s 30 % off) 20 % brighter: far outside the bounds.
        let clear = Scene::build(&room_desc(area, volpath(3))).unwrap();
        let (_, ratio) = compare(&render(&clear, volpath(3), 32, 4, None), &reference);
        assert!(
            ratio > 2.0,
            "area {area}: the clear room's mean ratio is {ratio}"
        );
        let thinner = Scene::build(&foggy_room_desc(area, volpath(3), fog(0.7))).unwrap();
        let (_, ratio) = compare(&render(&thinner, volpath(3), 128, 5, None), &reference);
        assert!(
            ratio > 1.1,
            "area {area}: σ_s × 0.7 gives a mean ratio of {ratio}"
        );
    }
}

#[test]
fn the_walks_store_the_densities_the_weights_recompute_in_fog() {
    // As the clear room's test: medium vertices convert the phase function's density by 1/d²
    // (no cosine), both ways.
    let mut checks = DensityChecks::default();
    let mut media_vertices = 0;
    for area in [true, false] {
        let scene = Scene::build(&foggy_room_desc(area, bdpt(5), fog(1.0))).unwrap();
        let what = format!("fog, area {area}");
        let (_, m) = check_walk_densities(
            &scene,
            &mut |w, got, want| checks.check(w, got, want),
            &what,
        );
        media_vertices += m;
    }
    assert!(
        media_vertices > 100,
        "only {media_vertices} medium vertices"
    );
    checks.assert_agree(1000);
}

/// A medium vertex at `p` reached from `from`.
fn medium_vertex(p: Vec3, from: Vec3) -> Vertex {
    let mut v = Vertex::endpoint(
        Kind::Medium,
        p,
        Vec3::ZERO,
        Vec3::ZERO,
        SampledSpectrum::ONE,
    );
    v.wo = normalize(from - p);
    v.phase = HgPhaseFunction { g: 0.4 };
    v.medium = Some(0);
    v
}

#[test]
fn mis_weights_of_paths_through_a_medium_sum_to_one() {
    for area in [true, false] {
        let scene = Scene::build(&foggy_room_desc(area, bdpt(6), fog(1.0))).unwrap();
        let c = Vec3::new(0.0, 1.0, 0.0);
        // Light → floor → fog → back wall → fog → fog → camera, every prefix of it.
        let floor = surface_vertex(&scene, c, Vec3::new(0.3, 0.0, 0.2));
        let wall = surface_vertex(&scene, c, Vec3::new(-0.5, 0.6, -1.0));
        let m1 = medium_vertex(Vec3::new(0.1, 0.7, 0.3), floor.p);
        let m2 = medium_vertex(Vec3::new(-0.3, 1.4, 0.1), wall.p);
        let m3 = medium_vertex(Vec3::new(0.2, 1.1, 1.5), m2.p);
        assert_mis_weights_sum_to_one(&scene, area, &[floor, m1, wall, m2, m3], "fog");
    }
}

#[test]
fn simplevolpath_agrees_with_volpath() {
    // Black walls (nothing scatters at a surface, which simplevolpath cannot do), the whole
    // ceiling emitting, fog everywhere: simplevolpath finds the ceiling by phase sampling
    // alone, volpath by light sampling too; the same image.
    let mut d = foggy_room_desc(true, volpath(4), fog(1.0));
    d.shapes.pop();
    d.materials = vec![MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: SpectrumTex::Const(Rgb::ZERO),
    })];
    for s in &mut d.shapes {
        s.material = 0;
    }
    d.shapes[2].area_light = Some(AreaLightDesc {
        l: Rgb::new(1.0, 0.8, 0.6),
        two_sided: false,
        spectrum: None,
        power: None,
        image: None,
    });
    d.shapes[2].medium_interface = Some(IN_FOG);
    let scene = Scene::build(&d).unwrap();
    assert!(matches!(
        scene.lights()[0].as_area(),
        Some(AreaLight { .. })
    ));
    let reference = render(&scene, volpath(4), 256, 1, None);
    // Finding the ceiling by chance is noisy: many samples, and a bound on blocks above the
    // noise (0.16 at 2048 samples).
    let simple = render(
        &scene,
        Integrator::SimpleVolPath { max_depth: 4 },
        1024,
        2,
        None,
    );
    let (worst, ratio) = compare(&simple, &reference);
    assert!(
        worst < 0.3 && (ratio - 1.0).abs() < 0.03,
        "simplevolpath: worst block {worst}, mean ratio {ratio}"
    );
    // Without its depth limit's scattering (maxdepth 0: only light reaching the camera
    // unscattered) the image is far darker: the bound sees scattering.
    let direct = render(
        &scene,
        Integrator::SimpleVolPath { max_depth: 0 },
        64,
        3,
        None,
    );
    let (_, ratio) = compare(&direct, &reference);
    assert!(ratio < 0.8, "maxdepth 0 gives a mean ratio of {ratio}");
}
