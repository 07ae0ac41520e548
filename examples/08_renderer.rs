//! Step 8 — the same scene, given to the renderer.
//!
//! Steps 1–7 wrote the loop by hand. lancer's renderer does the same work from a scene
//! description: the course's camera (`Camera::course`: eye at the origin, looking down −z, image
//! plane z = −1), the objects placed by transforms, point lights, diffuse materials, and the
//! `whitted` integrator (visible point, lights, shadows). Its image equals step 7's.

use lancer::film::{Film, PixelBounds};
use lancer::integrator::Integrator;
use lancer::light::PointDesc;
use lancer::material::DiffuseMaterial;
use lancer::material::MaterialDesc;
use lancer::math::{Rgb, Transform, Vec3};
use lancer::render::{RenderSettings, render};
use lancer::sampling::SamplerKind;
use lancer::scene::desc::{CameraDesc, FilterDesc, Geometry, LightDesc, SceneDesc, ShapeDesc};
use lancer::shape::{PlaneDesc, SphereDesc};
use lancer::texture::SpectrumTex;
use lancer_examples::{Canvas, save_or_exit};

#[path = "07_lights.rs"]
#[allow(dead_code)]
pub mod step7;
use step7::step6;

/// Step 7's scene as a description.
pub fn scene_desc(width: u32, height: u32) -> SceneDesc {
    let mut desc = SceneDesc {
        camera: CameraDesc {
            // pbrt's camera space looks down +z: mirroring z gives the course's view.
            camera_from_world: Transform::scale(Vec3::new(1.0, 1.0, -1.0)).unwrap(),
            ..CameraDesc::default()
        },
        integrator: Integrator::Whitted { max_depth: 1 },
        filter: FilterDesc::Box { radius: [0.5, 0.5] },
        ..SceneDesc::default()
    };
    desc.film.xresolution = width;
    desc.film.yresolution = height;
    let diffuse = |c: Rgb| {
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: SpectrumTex::Const(c),
        })
    };
    let place = |geometry, at: Vec3, material| ShapeDesc {
        medium_interface: None,
        geometry,
        object_to_world: Transform::translate(at),
        reverse_orientation: false,
        material,
        area_light: None,
        alpha: None,
    };
    let (_, albedos, _) = step6::scene();
    desc.materials = albedos.iter().map(|&a| diffuse(a)).collect();
    desc.shapes = vec![
        place(
            Geometry::Plane(PlaneDesc {
                p: Vec3::ZERO,
                n: Vec3::Y,
            }),
            Vec3::new(0.0, -1.0, 0.0),
            0,
        ),
        place(sphere(0.7), Vec3::new(-0.7, -0.3, -3.0), 1),
        place(sphere(0.5), Vec3::new(0.9, -0.5, -2.5), 2),
    ];
    desc.lights = step7::lights()
        .iter()
        .map(|l| {
            LightDesc::Point(PointDesc {
                from: l.at,
                intensity: l.intensity,
            })
        })
        .collect();
    desc
}

fn sphere(radius: f32) -> Geometry {
    Geometry::Sphere(SphereDesc {
        radius,
        z_min: -radius,
        z_max: radius,
        phi_max: 360.0,
    })
}

/// The image of this step, rendered by the library: one sample at each pixel's centre.
pub fn render_image(width: u32, height: u32) -> Canvas {
    let desc = scene_desc(width, height);
    let scene = lancer::Scene::build(&desc).expect("valid scene");
    let bounds = PixelBounds {
        x0: 0,
        x1: width as i32,
        y0: 0,
        y1: height as i32,
    };
    let settings = RenderSettings {
        samples: 0..1,
        spp: 1,
        seed: 0,
        // One stratum without jitter: the sample sits at the pixel's centre, as in step 7.
        sampler: SamplerKind::Stratified {
            xsamples: 1,
            ysamples: 1,
            jitter: false,
        },
        // In RGB, as the hand-written loop of step 7 (the library's default is spectral).
        spectral: false,
        ..RenderSettings::from_desc(&desc)
    };
    let mut film = Film::new(width, height, bounds);
    render(&scene, &settings, &mut film, &|_| {}, &Default::default());
    let image = film.image(1.0);
    // The film stores the top row first; the canvas counts rows from the bottom.
    Canvas::fill(width, height, |i, j| {
        image[((height - 1 - j) * width + i) as usize]
    })
}

#[allow(dead_code)]
fn main() {
    save_or_exit(&render_image(320, 240), "08-renderer.png");
}
