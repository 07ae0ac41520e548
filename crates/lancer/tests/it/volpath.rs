//! The volumetric path tracer against closed forms: a white furnace (a sphere of
//! non-absorbing medium behind an index-matched boundary, under a uniform environment of
//! radiance 1, looks exactly like the environment), and an absorbing sphere seen through its
//! centre (exp(−σ_a·2r)), in RGB mode (with coloured coefficients, which tests the spectral
//! MIS over the lanes) and in spectral mode.

use lancer::Scene;
use lancer::integrator::Integrator;
use lancer::material::InterfaceMaterial;
use lancer::material::MaterialDesc;
use lancer::math::{Rgb, SampledSpectrum, Vec3, normalize, rgb_lanes};
use lancer::medium::{HomogeneousDesc, MediumDesc, MediumInterface};
use lancer::ray::Ray;
use lancer::sampling::{Sampler, SamplerKind};
use lancer::scene::desc::{Geometry, LightDesc, SceneDesc, ShapeDesc};
use lancer::shape::SphereDesc;
use lancer::spectrum::sampled::SampledWavelengths;

/// A unit sphere of `medium` (index-matched: `interface` material) under a uniform white sky.
fn furnace(medium: MediumDesc) -> Scene {
    let desc = SceneDesc {
        materials: vec![MaterialDesc::Interface(InterfaceMaterial)],
        shapes: vec![ShapeDesc {
            medium_interface: Some(MediumInterface {
                inside: Some(0),
                outside: None,
            }),
            ..ShapeDesc::new(
                Geometry::Sphere(SphereDesc {
                    radius: 1.0,
                    z_min: -1.0,
                    z_max: 1.0,
                    phi_max: 360.0,
                }),
                0,
            )
        }],
        lights: vec![LightDesc::UniformInfinite(
            lancer::light::UniformInfiniteDesc { l: Rgb::ONE },
        )],
        media: vec![medium],
        ..SceneDesc::default()
    };
    Scene::build(&desc).unwrap()
}

fn homogeneous(sigma_a: Rgb, sigma_s: Rgb, g: f32) -> MediumDesc {
    MediumDesc::Homogeneous(HomogeneousDesc {
        sigma_a,
        sigma_s,
        scale: 1.0,
        le: Rgb::ZERO,
        le_scale: 1.0,
        g,
    })
}

/// The mean over `n` samples of the radiance along rays from (0, 0, −4) through points near
/// the sphere's centre, divided lane by lane by the environment's radiance (1 in RGB mode,
/// the white illuminant's spectrum in spectral mode).
fn mean_ratio(scene: &Scene, spectral: bool, n: u32) -> SampledSpectrum {
    let integrator = Integrator::VolPath {
        max_depth: 10_000,
        regularize: false,
    };
    let mut sampler = Sampler::new(SamplerKind::Independent, n, 7);
    let mut sum = SampledSpectrum::ZERO;
    for i in 0..n {
        sampler.start_pixel_sample(3, 5, i as u64);
        let u = sampler.get_2d();
        let target = Vec3::new(u.x - 0.5, u.y - 0.5, 0.0) * 0.5;
        let o = Vec3::new(0.0, 0.0, -4.0);
        let ray = Ray::new(o, normalize(target - o));
        let lambda = spectral.then(|| SampledWavelengths::sample_visible(sampler.get_1d()));
        let l = integrator.li(scene, &ray, &mut sampler, lambda.as_ref());
        let white = lambda.map_or(rgb_lanes(Rgb::ONE), |w| w.illuminant(Rgb::ONE));
        sum += l / white;
    }
    sum / n as f32
}

#[test]
fn white_furnace_in_a_non_absorbing_medium() {
    for (sigma_s, g) in [(Rgb::splat(1.5), 0.0), (Rgb::new(0.5, 1.0, 3.0), 0.6)] {
        let scene = furnace(homogeneous(Rgb::ZERO, sigma_s, g));
        for spectral in [false, true] {
            let m = mean_ratio(&scene, spectral, 20_000);
            // In RGB mode each lane is a colour channel and unbiased by itself. In spectral
            // mode lane 0 is always the hero, so a lane alone is not (a wavelength is
            // unbiased over the four positions it can take): the lanes' average is.
            let lanes = if spectral {
                vec![m.element_sum() / 4.0]
            } else {
                m.to_array().to_vec()
            };
            for v in lanes {
                assert!(
                    (v - 1.0).abs() < 0.03,
                    "σ_s {sigma_s}, g {g}, spectral {spectral}: {m}"
                );
            }
        }
    }
}

#[test]
fn purely_absorbing_sphere_transmits_exp_minus_sigma_a_chord() {
    let sigma_a = Rgb::new(0.2, 0.7, 1.5);
    let scene = furnace(homogeneous(sigma_a, Rgb::ZERO, 0.0));
    // Rays aimed within 0.25 of the centre: chords between 2·√(1 − 0.125) and 2.
    let m = mean_ratio(&scene, false, 4_000);
    for (lane, s) in [sigma_a.x, sigma_a.y, sigma_a.z].into_iter().enumerate() {
        let (lo, hi) = ((-s * 2.0).exp(), (-s * 2.0 * 0.875f32.sqrt()).exp());
        assert!(
            m[lane] > lo * 0.97 && m[lane] < hi * 1.03,
            "lane {lane}: {} not in [{lo}, {hi}]",
            m[lane]
        );
    }
}
