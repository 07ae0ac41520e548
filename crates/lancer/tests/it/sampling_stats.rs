//! Chi-square tests of the sampling routines that are not BSDFs: the warps to directions, and
//! light sampling for every kind of area light and for the uniform sky. Sampled directions are
//! binned over the sphere and compared with the bin integrals of the routine's own density
//! (for lights, `pdf_li` where the direction meets the light, 0 where it misses).

use crate::common::chi2::*;

use lancer::Scene;
use lancer::image::Image;
use lancer::light::{Light, LightSampleContext};
use lancer::math::{PackedRgb, PackedVec3, Rgb, Transform, Vec2, Vec3, normalize};
use lancer::ray::Ray;
use lancer::sampling::{
    Pcg32, PiecewiseConstant2D, cosine_hemisphere_pdf, equal_area_square_to_sphere,
    henyey_greenstein, sample_cosine_hemisphere, sample_henyey_greenstein, sample_uniform_cone,
    sample_uniform_disk_polar, sample_uniform_hemisphere, sample_uniform_sphere,
    sample_uniform_triangle, uniform_cone_pdf, uniform_hemisphere_pdf, uniform_sphere_pdf,
};
use lancer::scene::desc::{AreaLightDesc, Geometry, LightDesc, SceneDesc, ShapeDesc};
use lancer::shape::{CylinderDesc, DiskDesc, SphereDesc, TriangleMesh};
use std::sync::Arc;

/// Chi-square tests in this file, for the Šidák correction.
const TESTS: usize = 19;

/// Bins `n` directions from `sample` (None: no sample) against the bin integrals of `pdf`
/// (`quadrature` Gauss panels per bin and axis), checks that the success rate equals ∫pdf, and
/// that the fit passes. `CHI2_DEBUG=1` prints the worst bins before each verdict.
fn chi2_fit(
    name: &str,
    n: usize,
    quadrature: usize,
    mut sample: impl FnMut(Vec2) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
) {
    let mut rng = Pcg32::new(0x5eed ^ name.len() as u64, 7);
    let mut obs = vec![0.0; N_BINS];
    let mut ok = 0usize;
    for _ in 0..n {
        let u = Vec2::new(rng.uniform(), rng.uniform());
        if let Some(w) = sample(u) {
            assert!(w.is_finite(), "{name}: non-finite direction");
            obs[bin_of(normalize(w))] += 1.0;
            ok += 1;
        }
    }
    let integral = integrate_bins(quadrature, &pdf);
    let total: f64 = integral.iter().sum();
    let rate = ok as f64 / n as f64;
    assert!(
        (rate - total).abs() < 0.01,
        "{name}: {rate} of samples succeed but ∫pdf = {total}"
    );
    let exp: Vec<f64> = integral.iter().map(|p| p * n as f64).collect();
    if std::env::var("CHI2_DEBUG").is_ok() {
        let mut worst: Vec<(f64, usize)> = (0..N_BINS)
            .map(|i| ((obs[i] - exp[i]).powi(2) / exp[i].max(1.0), i))
            .collect();
        worst.sort_by(|a, b| b.0.total_cmp(&a.0));
        for &(c, i) in worst.iter().take(6) {
            println!(
                "  bin {i} (cos {}, phi {}): obs {} exp {:.1} ({c:.1})",
                i / N_PHI,
                i % N_PHI,
                obs[i],
                exp[i]
            );
        }
    }
    let (chi2, dof) = pooled_chi2(&obs, &exp).unwrap_or_else(|e| panic!("{name}: {e}"));
    let p = chi2_survival(chi2, dof);
    println!("{name}: χ² = {chi2:.1}, {dof} dof, p = {p:.3}; ∫pdf = {total:.4}");
    assert!(
        p > sidak(TESTS),
        "{name}: χ² = {chi2:.1} with {dof} dof, p = {p:.2e}"
    );
}

#[test]
fn chi2_direction_warps() {
    let n = 200_000;
    chi2_fit(
        "cosine hemisphere",
        n,
        8,
        |u| Some(sample_cosine_hemisphere(u)),
        |w| {
            if w.z > 0.0 {
                cosine_hemisphere_pdf(w.z) as f64
            } else {
                0.0
            }
        },
    );
    chi2_fit(
        "uniform sphere",
        n,
        8,
        |u| Some(sample_uniform_sphere(u)),
        |_| uniform_sphere_pdf() as f64,
    );
    chi2_fit(
        "uniform hemisphere",
        n,
        8,
        |u| Some(sample_uniform_hemisphere(u)),
        |w| {
            if w.z > 0.0 {
                uniform_hemisphere_pdf() as f64
            } else {
                0.0
            }
        },
    );
    let cos_max = 0.3f32;
    chi2_fit(
        "uniform cone",
        n,
        // The density jumps at the cone's edge, inside a bin: finer quadrature.
        32,
        |u| Some(sample_uniform_cone(u, cos_max)),
        |w| {
            if w.z >= cos_max {
                uniform_cone_pdf(cos_max) as f64
            } else {
                0.0
            }
        },
    );
}

#[test]
fn chi2_more_direction_warps() {
    let n = 200_000;
    // pbrt-v4's equal-area square → sphere map takes uniform points to uniform directions.
    chi2_fit(
        "equal-area square to sphere",
        n,
        8,
        |u| Some(equal_area_square_to_sphere(u)),
        |_| uniform_sphere_pdf() as f64,
    );
    // A uniform disk point lifted onto the hemisphere (Malley) is cosine-distributed: this
    // checks the polar disk warp (the concentric one is checked through the cosine warp).
    chi2_fit(
        "polar disk, lifted",
        n,
        8,
        |u| {
            let d = sample_uniform_disk_polar(u);
            Some(Vec3::new(
                d.x,
                d.y,
                (1.0 - d.length_squared()).max(0.0).sqrt(),
            ))
        },
        |w| {
            if w.z > 0.0 {
                cosine_hemisphere_pdf(w.z) as f64
            } else {
                0.0
            }
        },
    );
    for g in [0.6f32, -0.3] {
        let wo = normalize(Vec3::new(0.3, -0.5, 0.8));
        chi2_fit(
            &format!("Henyey-Greenstein g = {g}"),
            n,
            8,
            |u| Some(sample_henyey_greenstein(wo, g, u).0),
            |w| henyey_greenstein(wo.dot(w), g) as f64,
        );
    }
}

#[test]
fn chi2_uniform_triangle() {
    // Points (b₁, b₂) of a uniform triangle sample fill the half square b₁ + b₂ < 1 evenly.
    // On an N × N grid the diagonal runs through cell corners, so each cell's expectation is
    // exact: whole below it, half on it, none above.
    const N: usize = 16;
    let n = 200_000;
    let mut rng = Pcg32::new(11, 3);
    let mut obs = vec![0.0; N * N];
    for _ in 0..n {
        let [_, b1, b2] = sample_uniform_triangle(Vec2::new(rng.uniform(), rng.uniform()));
        assert!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0 + 1e-6);
        let (i, j) = (
            ((b1 * N as f32) as usize).min(N - 1),
            ((b2 * N as f32) as usize).min(N - 1),
        );
        obs[i * N + j] += 1.0;
    }
    let cell = 2.0 / (N * N) as f64;
    let exp: Vec<f64> = (0..N * N)
        .map(|k| {
            let (i, j) = (k / N, k % N);
            n as f64
                * match (i + j).cmp(&(N - 1)) {
                    std::cmp::Ordering::Less => cell,
                    std::cmp::Ordering::Equal => cell / 2.0,
                    std::cmp::Ordering::Greater => 0.0,
                }
        })
        .collect();
    let (chi2, dof) = pooled_chi2(&obs, &exp).unwrap();
    let p = chi2_survival(chi2, dof);
    println!("uniform triangle: χ² = {chi2:.1}, {dof} dof, p = {p:.3}");
    assert!(p > sidak(TESTS), "uniform triangle: p = {p:.2e}");
}

fn emitter(geometry: Geometry, to_world: Transform) -> ShapeDesc {
    ShapeDesc {
        medium_interface: None,
        geometry,
        object_to_world: to_world,
        reverse_orientation: false,
        material: 0,
        area_light: Some(AreaLightDesc {
            l: Rgb::ONE,
            two_sided: false,
            spectrum: None,
            power: None,
            image: None,
        }),
        alpha: None,
    }
}

/// Chi-square test of light 0 of a scene seen from the origin (surface normal +z).
fn chi2_light(name: &str, desc: SceneDesc) {
    let scene = Scene::build(&desc).unwrap();
    let ctx = LightSampleContext {
        p: Vec3::ZERO,
        n: Vec3::Z,
        ns: Vec3::Z,
    };
    let light = &scene.lights()[0];
    // Lights at infinity: each sample's density must be pdf_li's for its direction (but for
    // rounding at texel borders).
    let mismatched = std::cell::Cell::new(0usize);
    // Lights' densities jump at their silhouettes, which cross bins: fine quadrature.
    chi2_fit(
        name,
        200_000,
        32,
        |u| {
            let s = light.sample_li(&ctx, u, scene.shapes(), scene.meshes())?;
            if desc.shapes.is_empty() {
                let p = light.pdf_li(&ctx, s.wi, None);
                if (p - s.pdf).abs() > 1e-3 * s.pdf {
                    mismatched.set(mismatched.get() + 1);
                }
            }
            Some(s.wi)
        },
        |w| {
            let hit = if desc.shapes.is_empty() {
                None
            } else {
                // An area light has a density only where the direction meets it, and only on
                // the side it emits from.
                let Light::Area(lancer::light::AreaLight { prim, .. }) = light else {
                    unreachable!("scenes with shapes test their area light")
                };
                match scene.intersect(&Ray::new(Vec3::ZERO, w)) {
                    Some(h) if h.prim == *prim && h.si.n.dot(w) < 0.0 => Some((h.si.p, h.si.n)),
                    _ => return 0.0,
                }
            };
            light.pdf_li(&ctx, w, hit) as f64
        },
    );
    assert!(
        mismatched.get() * 1000 < 200_000,
        "{name}: {} sample densities differ from pdf_li",
        mismatched.get()
    );
}

fn scene_with(shapes: Vec<ShapeDesc>) -> SceneDesc {
    SceneDesc {
        shapes,
        ..SceneDesc::default()
    }
}

#[test]
fn chi2_area_lights() {
    let quad = TriangleMesh {
        positions: vec![
            PackedVec3::new(-1.0, -0.5, 1.0),
            PackedVec3::new(1.5, -0.5, 1.2),
            PackedVec3::new(1.0, 1.0, 0.8),
            PackedVec3::new(-1.2, 1.0, 0.6),
        ],
        normals: vec![],
        uvs: vec![],
        // Wound so that the geometric normal faces down, towards the origin.
        indices: vec![0, 2, 1, 0, 3, 2],
        flip_normal: false,
    };
    chi2_light(
        "triangle-mesh light",
        scene_with(vec![emitter(
            Geometry::TriangleMesh(Arc::new(quad)),
            Transform::IDENTITY,
        )]),
    );
    let sphere = |z_min: f32, z_max: f32, phi: f32| {
        Geometry::Sphere(SphereDesc {
            radius: 0.7,
            z_min,
            z_max,
            phi_max: phi,
        })
    };
    chi2_light(
        "whole sphere light (cone)",
        scene_with(vec![emitter(
            sphere(-0.7, 0.7, 360.0),
            Transform::translate(Vec3::new(0.4, 0.2, 1.5)),
        )]),
    );
    // Area sampling of a curved light has a density d²/(|cos θ|·A) that diverges at the
    // silhouette, which quadrature cannot integrate: test it from inside, lit by the inner
    // side (ReverseOrientation), where cos θ stays away from 0.
    let mut inside = emitter(
        sphere(-0.7, 0.5, 270.0),
        Transform::translate(Vec3::new(0.1, -0.2, 0.15)),
    );
    inside.reverse_orientation = true;
    chi2_light("partial sphere light (area)", scene_with(vec![inside]));
    chi2_light(
        "disk light",
        scene_with(vec![emitter(
            Geometry::Disk(DiskDesc {
                height: 0.0,
                radius: 1.0,
                inner_radius: 0.3,
                phi_max: 300.0,
            }),
            // Above the origin, tilted, its normal turned down towards it.
            Transform::translate(Vec3::new(0.5, 0.3, 1.2))
                * Transform::rotate(160.0, Vec3::new(1.0, 0.3, 0.0)).unwrap(),
        )]),
    );
    // The cylinder too, from inside.
    let mut tube = emitter(
        Geometry::Cylinder(CylinderDesc {
            radius: 0.5,
            z_min: -0.8,
            z_max: 0.8,
            phi_max: 300.0,
        }),
        Transform::translate(Vec3::new(0.1, 0.15, 0.2)) * Transform::rotate(40.0, Vec3::X).unwrap(),
    );
    tube.reverse_orientation = true;
    chi2_light("cylinder light", scene_with(vec![tube]));
}

#[test]
fn chi2_uniform_sky() {
    chi2_light(
        "uniform sky",
        SceneDesc {
            lights: vec![LightDesc::UniformInfinite(
                lancer::light::UniformInfiniteDesc { l: Rgb::ONE },
            )],
            ..SceneDesc::default()
        },
    );
}

/// A `w × h` environment with a gradient, a bright spot and a black corner.
fn sky_image(w: u32, h: u32) -> Arc<Image> {
    let texels = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 / w as f32, (i / w) as f32 / h as f32);
            let mut c = Rgb::new(0.2 + x, 0.5 + 0.3 * y, 0.1 + x * y);
            if (x - 0.3).abs() < 0.1 && (y - 0.6).abs() < 0.1 {
                c *= 20.0;
            }
            if x > 0.85 && y > 0.8 {
                c = Rgb::ZERO;
            }
            PackedRgb::from(c)
        })
        .collect();
    Arc::new(Image::new(w, h, texels).unwrap())
}

#[test]
fn chi2_environment_lights() {
    // Square images are equal-area octahedral maps, 2:1 ones lat-long; both turned.
    for (name, w, h) in [("octahedral sky", 32, 32), ("lat-long sky", 48, 24)] {
        chi2_light(
            name,
            SceneDesc {
                lights: vec![LightDesc::ImageInfinite(lancer::light::ImageInfiniteDesc {
                    light_to_world: Transform::rotate(35.0, Vec3::new(1.0, 2.0, 0.5)).unwrap(),
                    l: Rgb::ONE,
                    image: sky_image(w, h),
                })],
                ..SceneDesc::default()
            },
        );
    }
}

#[test]
fn chi2_piecewise_constant_2d() {
    // A 6 × 4 table with a zero cell, a bright cell and a zero row: sampled cells against
    // expected counts n·f/Σf (exact: the density is constant on each cell).
    let (nu, nv) = (6usize, 4usize);
    let mut f: Vec<f32> = (0..nu * nv).map(|i| 1.0 + (i % 5) as f32).collect();
    f[3] = 0.0;
    f[8] = 40.0;
    for u in 0..nu {
        f[2 * nu + u] = 0.0;
    }
    let d = PiecewiseConstant2D::new(&f, nu, nv).unwrap();
    let total: f64 = f.iter().map(|&v| v as f64).sum();
    let n = 200_000;
    let mut rng = Pcg32::new(5, 9);
    let mut obs = vec![0.0; nu * nv];
    for _ in 0..n {
        let (p, pdf) = d.sample(Vec2::new(rng.uniform(), rng.uniform()));
        let cell = (p.y * nv as f32) as usize * nu + (p.x * nu as f32) as usize;
        assert!((pdf - d.pdf(p)).abs() <= 1e-5 * pdf);
        obs[cell] += 1.0;
    }
    let exp: Vec<f64> = f.iter().map(|&v| n as f64 * v as f64 / total).collect();
    let (chi2, dof) = pooled_chi2(&obs, &exp).unwrap();
    let p = chi2_survival(chi2, dof);
    println!("piecewise constant 2D: χ² = {chi2:.1}, {dof} dof, p = {p:.3}");
    assert!(p > sidak(TESTS), "piecewise constant 2D: p = {p:.2e}");
}
