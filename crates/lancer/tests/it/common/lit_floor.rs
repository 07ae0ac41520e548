//! A diffuse floor under a point light, and its whole film rendered over a range of sample
//! indices: the scene of the tests that compare films across thread counts and splits of
//! their work (`light_paths`, `mlt`).

use super::units::render_units_on;
use lancer::Scene;
use lancer::film::Film;
use lancer::integrator::Integrator;
use lancer::light::PointDesc;
use lancer::material::{DiffuseMaterial, MaterialDesc};
use lancer::math::{PackedVec3, Rgb, Transform, Vec3};
use lancer::medium::{HomogeneousDesc, MediumDesc};
use lancer::render::{RenderSettings, work_units};
use lancer::scene::desc::{FilterDesc, Geometry, LightDesc, SceneDesc, ShapeDesc};
use lancer::shape::TriangleMesh;
use lancer::texture::SpectrumTex;
use std::sync::Arc;

/// A quad of corners `p` (counter-clockwise seen from its lit side), of material 0.
pub fn quad(p: [[f32; 3]; 4]) -> ShapeDesc {
    ShapeDesc::new(
        Geometry::TriangleMesh(Arc::new(TriangleMesh {
            positions: p
                .iter()
                .map(|&[x, y, z]| PackedVec3::new(x, y, z))
                .collect(),
            normals: vec![],
            uvs: vec![],
            indices: vec![0, 1, 2, 0, 2, 3],
            flip_normal: false,
        })),
        0,
    )
}

/// A 4 × 4 diffuse floor (y = 0) under a point light of intensity 3 at `light`, seen from
/// `eye` looking at `target`, `w × h` pixels, a Gaussian filter of radius 1.5.
pub fn lit_floor(
    integrator: Integrator,
    light: Vec3,
    eye: Vec3,
    target: Vec3,
    w: u32,
    h: u32,
) -> SceneDesc {
    let mut d = SceneDesc {
        filter: FilterDesc::Gaussian {
            radius: [1.5, 1.5],
            sigma: 0.5,
        },
        integrator,
        materials: vec![MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: SpectrumTex::Const(Rgb::new(0.7, 0.5, 0.3)),
        })],
        shapes: vec![quad([
            [-2.0, 0.0, 2.0],
            [2.0, 0.0, 2.0],
            [2.0, 0.0, -2.0],
            [-2.0, 0.0, -2.0],
        ])],
        lights: vec![LightDesc::Point(PointDesc {
            from: light,
            intensity: Rgb::splat(3.0),
        })],
        ..SceneDesc::default()
    };
    d.camera.camera_from_world = Transform::look_at(eye, target, Vec3::Y).unwrap();
    d.film.xresolution = w;
    d.film.yresolution = h;
    d
}

/// Renders sample indices (for mlt, chains) `samples` of the whole image of `d` on `threads`
/// threads, in 8-pixel tiles and 2-index passes, spectral or RGB.
pub fn render_film(
    d: &SceneDesc,
    samples: std::ops::Range<u32>,
    threads: usize,
    spectral: bool,
) -> Film {
    let scene = Scene::build(d).unwrap();
    let settings = RenderSettings {
        samples: samples.clone(),
        spectral,
        ..RenderSettings::from_desc(d)
    };
    let full = d.film.render_bounds();
    let mut film = Film::new(d.film.xresolution, d.film.yresolution, full);
    let units = work_units(&full, 8, samples, 2);
    render_units_on(threads, &scene, &settings, &d.integrator, &mut film, &units);
    film
}

/// `d` in a homogeneous fog that fills the scene, its coefficients different per channel (so
/// that the wavelengths' densities differ): the camera and every light are in it.
pub fn in_fog(mut d: SceneDesc) -> SceneDesc {
    d.media = vec![MediumDesc::Homogeneous(HomogeneousDesc {
        sigma_a: Rgb::new(0.1, 0.2, 0.3),
        sigma_s: Rgb::new(0.5, 0.4, 0.3),
        scale: 1.0,
        le: Rgb::ZERO,
        le_scale: 0.0,
        g: 0.2,
    })];
    d.camera_medium = Some(0);
    d.light_media = vec![Some(0); d.lights.len()];
    d
}
