//! The film loop of `sppm` (pbrt-v4's stochastic progressive photon mapping): iterations of a
//! camera pass and a photon pass over the whole of `settings.bounds`, each pixel's estimate
//! progressing from one to the next ([`crate::integrator::sppm`] has the passes' transport).
//!
//! Unlike the other integrators' samples, iterations are not independent (each shrinks its
//! pixels' radii for the next), so a render is not a sum of units: this loop runs iterations
//! `0..settings.samples.end` in order and writes each pixel's estimate into the film (over
//! what it held). Determinism: iteration k's camera sample of a pixel is the sampler's sample
//! k of that pixel, its wavelengths and photons depend only on (seed, k, photon index), the
//! photons are traced in fixed blocks whose deposits are added in block order, and each
//! pixel's estimate depends on no other pixel: any thread count, and any split of the image
//! into pixel ranges, gives the same bits.

use super::{
    RenderJob, RenderSettings, RenderStats, SampleId, WorkUnit, camera_ray_at, rays_traced,
    scene_film_rgb,
};
use crate::film::{Film, PixelBounds, PixelSum, to_fixed};
use crate::integrator::sppm::grid::VisibleGrid;
use crate::integrator::sppm::{
    CameraPath, PhotonSampler, PixelState, SppmOptions, camera_path, photon_flux, trace_photon,
};
use crate::math::{Rgb, SampledSpectrum, Vec3};
use crate::sampling::halton::{DigitPermutations, radical_inverse};
use crate::sampling::{Sampler, hash_u64, u32_to_unit_f32};
use crate::spectrum::sampled::SampledWavelengths;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Photons per block: the photon pass's unit of parallel work; blocks' deposits are added in
/// block order.
const PHOTON_BLOCK: u64 = 4096;

/// The wavelengths' sample of iteration `k`, shared by every pixel and photon of it (pbrt-v4
/// draws the radical inverse of k in base 3): that radical inverse rotated by a value of the
/// seed (Cranley–Patterson), so that renders at other seeds see other wavelengths too.
pub fn wavelength_sample(seed: u64, k: u32) -> f32 {
    let rotation = u32_to_unit_f32(hash_u64(&[seed, 0x5350_504d]) as u32);
    let u = radical_inverse(1, k as u64) + rotation;
    if u >= 1.0 { u - 1.0 } else { u }
}

/// Photons per iteration: the scene's `photonsperiteration`, else one per pixel of the whole
/// render (`settings.splat_bounds`: a part of a split render traces the same photons).
pub fn photons_per_iteration(settings: &RenderSettings, options: &SppmOptions) -> u64 {
    options
        .photons_per_iteration
        .map_or(settings.splat_bounds.area(), u64::from)
        .max(1)
}

/// Renders `settings.bounds` of `film` by sppm with `options`: iterations `0..samples.end`
/// (`samples.start` is ignored: an iteration needs those before it), written into the film's
/// pixels as their estimates (Σw·L = L, Σw = 1). `stop()` is asked between iterations: once
/// it says yes the film gets the estimate of the iterations done, the result is `cancelled`,
/// and `done` is left as it was (a resumed render starts again from the first iteration and
/// overwrites the film, so it ends with the same bits). Otherwise every unit is marked done.
/// `on_unit` is called after each iteration, with a unit of the whole bounds and that
/// iteration's index, and the estimate so far.
pub(super) fn render(job: RenderJob<'_>, options: SppmOptions) -> RenderStats {
    // Not unit by unit: iterations 0..settings.samples.end over all of settings.bounds,
    // every flag of `done` marked at the end.
    let RenderJob {
        scene,
        settings,
        film,
        units: _,
        done,
        on_unit,
        stop,
    } = job;
    let bounds = settings.bounds.intersect(&film.bounds);
    let mut stats = RenderStats::default();
    let iterations = settings.samples.end;
    let photons = photons_per_iteration(settings, &options);
    let seed = options.seed.unwrap_or(settings.seed);
    let perms = DigitPermutations::for_seed(seed);
    let w = bounds.width() as usize;
    let npix = bounds.area() as usize;
    let mut state = vec![PixelState::new(options.radius as f64); npix];
    let none = CameraPath {
        ld: SampledSpectrum::ZERO,
        vp: None,
    };
    let mut paths = vec![none; npix];
    let rays = AtomicU64::new(0);
    let nonfinite = AtomicU64::new(0);
    let mut finished = 0;
    for k in 0..iterations {
        if npix == 0 {
            break;
        }
        if stop() {
            stats.cancelled = true;
            break;
        }
        let lambda = settings
            .spectral
            .then(|| SampledWavelengths::sample_visible(wavelength_sample(seed, k)));
        // Camera pass: a visible point and Ld per pixel, rows in parallel.
        paths.par_chunks_mut(w).enumerate().for_each(|(row, out)| {
            let r0 = rays_traced();
            let mut sampler = Sampler::new(settings.sampler, settings.spp, settings.seed);
            let y = bounds.y0 + row as i32;
            for (i, o) in out.iter_mut().enumerate() {
                let x = bounds.x0 + i as i32;
                let (ray, ..) = camera_ray_at(scene, settings, &mut sampler, x, y, k);
                *o = match ray {
                    Some(r) => camera_path(
                        scene,
                        &r.ray,
                        r.weight,
                        &mut sampler,
                        lambda.as_ref(),
                        options.max_depth,
                    ),
                    None => none,
                };
            }
            rays.fetch_add(rays_traced() - r0, Ordering::Relaxed);
        });
        for (i, (s, p)) in state.iter_mut().zip(&paths).enumerate() {
            let rgb = scene_film_rgb(scene, lambda.as_ref(), p.ld);
            if rgb.is_finite() {
                for c in 0..3 {
                    s.ld[c] += rgb[c] as f64;
                }
            } else {
                stats.nonfinite += 1;
                let id = SampleId {
                    y: bounds.y0 + (i / w) as i32,
                    x: bounds.x0 + (i % w) as i32,
                    sample: k,
                };
                stats.first_nonfinite = Some(stats.first_nonfinite.map_or(id, |f| f.min(id)));
            }
        }
        // Photon pass: deposits into the visible points within their pixel's radius.
        let points: Vec<(Vec3, f32)> = paths
            .iter()
            .zip(&state)
            .map(|(p, s)| p.vp.map_or((Vec3::ZERO, 0.0), |v| (v.p, s.radius as f32)))
            .collect();
        let mut phi = vec![[0.0f64; 4]; npix];
        let mut m = vec![0u64; npix];
        if let Some(grid) = VisibleGrid::build(&points) {
            stats.photons += photons;
            let blocks = photons.div_ceil(PHOTON_BLOCK);
            // Blocks traced at once (their deposits wait in memory until added).
            let group = 2 * rayon::current_num_threads().max(1) as u64;
            let mut b0 = 0;
            while b0 < blocks {
                let b1 = (b0 + group).min(blocks);
                // Collected in block order (an indexed range), whatever thread traced each.
                let deposits: Vec<Vec<(u32, SampledSpectrum)>> = (b0 as usize..b1 as usize)
                    .into_par_iter()
                    .map(|b| {
                        let b = b as u64;
                        let r0 = rays_traced();
                        let mut out = Vec::new();
                        let mut u = PhotonSampler::new(perms.clone(), seed, 0);
                        for i in b * PHOTON_BLOCK..((b + 1) * PHOTON_BLOCK).min(photons) {
                            u.start(k as u64 * photons + i);
                            trace_photon(
                                scene,
                                lambda.as_ref(),
                                options.max_depth,
                                1,
                                &mut u,
                                &mut |h| {
                                    for &v in grid.candidates(h.p) {
                                        let (p, r) = points[v as usize];
                                        if (p - h.p).length_squared() > r * r {
                                            continue;
                                        }
                                        if let Some(vp) = &paths[v as usize].vp {
                                            out.push((v, photon_flux(vp, h)));
                                        }
                                    }
                                },
                            );
                        }
                        rays.fetch_add(rays_traced() - r0, Ordering::Relaxed);
                        out
                    })
                    .collect();
                for (v, f) in deposits.iter().flatten() {
                    let v = *v as usize;
                    m[v] += 1;
                    if f.is_finite() {
                        for c in 0..4 {
                            phi[v][c] += f[c] as f64;
                        }
                    } else {
                        nonfinite.fetch_add(1, Ordering::Relaxed);
                    }
                }
                b0 = b1;
            }
        }
        // Each pixel's progress: N, R and τ from this iteration's photons.
        for ((s, phi), m) in state.iter_mut().zip(&phi).zip(&m) {
            let l =
                SampledSpectrum::new(phi[0] as f32, phi[1] as f32, phi[2] as f32, phi[3] as f32);
            let rgb = scene_film_rgb(scene, lambda.as_ref(), l);
            s.update(*m, [rgb[0] as f64, rgb[1] as f64, rgb[2] as f64]);
        }
        finished = k + 1;
        let unit = WorkUnit {
            tile: bounds,
            samples: k..k + 1,
        };
        on_unit(&unit, &estimates(&state, finished, photons));
    }
    write_estimates(film, &bounds, &state, finished, photons);
    if !stats.cancelled {
        done.iter_mut().for_each(|d| *d = true);
    }
    stats.samples = npix as u64 * finished as u64;
    stats.rays = rays.into_inner();
    stats.nonfinite += nonfinite.into_inner();
    stats
}

/// The film sums of every pixel's estimate after `iterations` iterations (value L, weight 1),
/// row-major.
fn estimates(state: &[PixelState], iterations: u32, photons: u64) -> Vec<PixelSum> {
    state
        .iter()
        .map(|s| pixel_sum(s.estimate(iterations, photons), iterations))
        .collect()
}

/// A pixel holding value `l` after `samples` samples: Σw·L = L, Σw = 1 (nothing before the
/// first).
fn pixel_sum(l: Rgb, samples: u32) -> PixelSum {
    if samples == 0 {
        return PixelSum::default();
    }
    PixelSum {
        rgb: [to_fixed(l[0]), to_fixed(l[1]), to_fixed(l[2])],
        weight: to_fixed(1.0),
        samples,
    }
}

/// Writes the estimates of `bounds`' pixels into `film`, over what it held.
fn write_estimates(
    film: &mut Film,
    bounds: &PixelBounds,
    state: &[PixelState],
    iterations: u32,
    photons: u64,
) {
    let w = bounds.width().max(1) as usize;
    for (i, s) in state.iter().enumerate() {
        let (x, y) = (bounds.x0 + (i % w) as i32, bounds.y0 + (i / w) as i32);
        if let Some(p) = film.pixel_mut(x, y) {
            *p = pixel_sum(s.estimate(iterations, photons), iterations);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::Integrator;
    use crate::integrator::test_scenes::{self, H, W, diffuse, quad};
    use crate::light::PointDesc;
    use crate::material::{DielectricMaterial, MaterialDesc};
    use crate::math::Transform;
    use crate::render::{render_units, work_units};
    use crate::scene::Scene;
    use crate::scene::desc::{Geometry, LightDesc, SceneDesc, ShapeDesc};
    use crate::shape::SphereDesc;
    use crate::spectrum::Ior;
    use crate::texture::FloatTex;

    /// An sppm integrator of `max_depth` bounces, `photons` photons per iteration, initial
    /// radius `radius`.
    fn sppm(max_depth: u32, photons: u32, radius: f32) -> Integrator {
        Integrator::Sppm(SppmOptions {
            max_depth,
            photons_per_iteration: Some(photons),
            radius,
            seed: None,
        })
    }

    /// [`test_scenes::view`] at 30°, rendered at `spp`.
    fn view(eye: Vec3, target: Vec3, up: Vec3, integrator: Integrator, spp: u32) -> SceneDesc {
        let mut d = test_scenes::view(eye, target, up, 30.0, integrator);
        d.sampler.spp = spp;
        d
    }

    /// A corner of a room (floor, back wall, red left wall) under a point light, and a glass
    /// sphere on the floor that focuses a caustic: light that only photons bring.
    fn room(integrator: Integrator, spp: u32) -> SceneDesc {
        let mut d = view(
            Vec3::new(0.3, 1.2, 3.5),
            Vec3::new(0.0, 0.5, 0.0),
            Vec3::Y,
            integrator,
            spp,
        );
        d.materials = vec![
            diffuse(Rgb::splat(0.7)),
            diffuse(Rgb::new(0.7, 0.15, 0.1)),
            // Flint glass: it disperses, so spectral paths through it keep their hero
            // wavelength.
            MaterialDesc::Dielectric(DielectricMaterial {
                eta: Ior::named_glass("glass-F11").unwrap(),
                uroughness: FloatTex::Const(0.0),
                vroughness: FloatTex::Const(0.0),
                remap_roughness: false,
            }),
        ];
        d.shapes = vec![
            quad(
                [
                    [-1.0, 0.0, 1.5],
                    [1.5, 0.0, 1.5],
                    [1.5, 0.0, -1.0],
                    [-1.0, 0.0, -1.0],
                ],
                0,
            ),
            quad(
                [
                    [-1.0, 0.0, -1.0],
                    [1.5, 0.0, -1.0],
                    [1.5, 2.0, -1.0],
                    [-1.0, 2.0, -1.0],
                ],
                0,
            ),
            quad(
                [
                    [-1.0, 0.0, 1.5],
                    [-1.0, 0.0, -1.0],
                    [-1.0, 2.0, -1.0],
                    [-1.0, 2.0, 1.5],
                ],
                1,
            ),
        ];
        d.lights = vec![LightDesc::Point(PointDesc {
            from: Vec3::new(0.4, 1.8, 0.3),
            intensity: Rgb::splat(3.0),
        })];
        d
    }

    /// Renders `settings.bounds` of `desc` on `threads` threads into a fresh film.
    fn render_on(
        desc: &SceneDesc,
        settings: &RenderSettings,
        threads: usize,
    ) -> (Film, RenderStats) {
        crate::render::testing::render_on(desc, settings, threads, 16)
    }

    fn rgb_settings(desc: &SceneDesc) -> RenderSettings {
        RenderSettings {
            spectral: false,
            ..RenderSettings::from_desc(desc)
        }
    }

    /// Only direct light reaches a lone floor (no photon has a second surface to land on):
    /// sppm's image is its camera pass's Ld, the analytic ρ/π·I·cos θ/d² of a floor under a
    /// point light, at the pixels that see the floor straight below the camera.
    #[test]
    fn direct_light_of_a_floor_is_analytic() {
        let mut d = view(
            Vec3::new(0.0, 3.0, 0.0),
            Vec3::ZERO,
            Vec3::Z,
            sppm(5, 1000, 0.1),
            8,
        );
        d.materials = vec![diffuse(Rgb::splat(0.5))];
        d.shapes = vec![quad(
            [
                [-9.0, 0.0, 9.0],
                [9.0, 0.0, 9.0],
                [9.0, 0.0, -9.0],
                [-9.0, 0.0, -9.0],
            ],
            0,
        )];
        d.lights = vec![LightDesc::Point(PointDesc {
            from: Vec3::new(0.0, 1.0, 0.0),
            intensity: Rgb::splat(3.0),
        })];
        let (film, stats) = render_on(&d, &rgb_settings(&d), 2);
        assert_eq!(stats.samples, (W * H * 8) as u64);
        assert_eq!(stats.photons, 8 * 1000);
        let img = film.image(1.0);
        // The four centre pixels see the floor within 0.13 of the point below the light (E within 2.5 % of its value there).
        let expected = 0.5 / std::f32::consts::PI * 3.0;
        for (x, y) in [(11, 8), (12, 8), (11, 9), (12, 9)] {
            let v = img[(y * W + x) as usize];
            assert!(
                (v[0] - expected).abs() < 0.03 * expected,
                "pixel ({x}, {y}): {v:?}, analytic {expected}"
            );
        }
    }

    /// Block means of a W × H image (4 × 3 blocks of 6 × 6 pixels).
    fn blocks(img: &[Rgb]) -> Vec<Rgb> {
        let mut out = vec![Rgb::ZERO; 12];
        for y in 0..H {
            for x in 0..W {
                out[((y / 6) * 4 + x / 6) as usize] += img[(y * W + x) as usize] / 36.0;
            }
        }
        out
    }

    /// sppm agrees with the path tracer on the diffuse room without the sphere (indirect
    /// light from photons, direct from the camera pass), block by block.
    #[test]
    fn agrees_with_path_tracing_on_a_diffuse_room() {
        let d = room(sppm(5, 20_000, 0.1), 64);
        let (film, _) = render_on(&d, &rgb_settings(&d), 2);
        let path = room(
            Integrator::Path {
                max_depth: 5,
                regularize: false,
            },
            512,
        );
        let (reference, _) = render_on(&path, &rgb_settings(&path), 2);
        let (a, b) = (blocks(&film.image(1.0)), blocks(&reference.image(1.0)));
        for (i, (a, b)) in a.iter().zip(&b).enumerate() {
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() <= 0.06 * b[c] + 2e-3,
                    "block {i} channel {c}: sppm {a:?}, path {b:?}"
                );
            }
        }
    }

    /// The same bits whatever the thread count (spectral mode, with the glass sphere's
    /// caustic), whether the image is rendered whole or in two halves (every part traces the
    /// same photons), and after an interruption whose render is started again.
    #[test]
    fn bits_do_not_depend_on_threads_tiles_or_interruptions() {
        let mut d = room(sppm(6, 3000, 0.15), 6);
        let sphere = SphereDesc {
            radius: 0.35,
            z_min: -0.35,
            z_max: 0.35,
            phi_max: 360.0,
        };
        d.shapes.push(ShapeDesc {
            object_to_world: Transform::translate(Vec3::new(0.2, 0.35, 0.0)),
            ..ShapeDesc::new(Geometry::Sphere(sphere), 2)
        });
        let settings = RenderSettings::from_desc(&d);
        assert!(settings.spectral);
        let (one, s1) = render_on(&d, &settings, 1);
        let (three, s3) = render_on(&d, &settings, 3);
        assert_eq!(one.pixels, three.pixels);
        assert_eq!((s1.samples, s1.photons), (s3.samples, s3.photons));
        assert!(one.pixels.iter().any(|p| p.value()[0] > 0.0));
        // Two halves, each over its own pixels, with the whole render's pixel count.
        let whole = settings.bounds;
        let mut left = settings.clone();
        left.bounds.x1 = whole.x0 + 10;
        let mut right = settings.clone();
        right.bounds.x0 = whole.x0 + 10;
        let (l, _) = render_on(&d, &left, 2);
        let (r, _) = render_on(&d, &right, 2);
        for y in whole.y0..whole.y1 {
            for x in whole.x0..whole.x1 {
                let part = if x < left.bounds.x1 { &l } else { &r };
                let i = whole.index(x, y).unwrap();
                let j = part.bounds.index(x, y).unwrap();
                assert_eq!(one.pixels[i], part.pixels[j], "pixel ({x}, {y})");
            }
        }
        // Stopped after two iterations: the estimate so far, nothing marked done; the render
        // started again over that film ends with the uninterrupted bits.
        let scene = Scene::build(&d).unwrap();
        let mut film = Film::new(W, H, whole);
        let units = work_units(&whole, 16, settings.samples.clone(), 4);
        let mut done = vec![false; units.len()];
        let calls = std::sync::atomic::AtomicU32::new(0);
        let stop = || calls.fetch_add(1, Ordering::Relaxed) >= 2;
        let stats = render_units(RenderJob {
            stop: &stop,
            ..RenderJob::new(&scene, &settings, &mut film, &units, &mut done)
        });
        assert!(stats.cancelled && !done.iter().any(|&d| d));
        assert_eq!(film.pixels[0].samples, 2);
        assert_ne!(film.pixels, one.pixels);
        render_units(RenderJob::new(
            &scene, &settings, &mut film, &units, &mut done,
        ));
        assert_eq!(film.pixels, one.pixels);
    }

    #[test]
    fn wavelength_samples_are_stratified_and_move_with_the_seed() {
        // The first 9 radical inverses in base 3 are the ninths: rotated, still 1/9 apart.
        let mut a: Vec<f32> = (0..9).map(|k| wavelength_sample(0, k)).collect();
        a.sort_by(f32::total_cmp);
        for i in 0..9 {
            let gap = if i < 8 {
                a[i + 1] - a[i]
            } else {
                a[0] + 1.0 - a[8]
            };
            assert!((gap - 1.0 / 9.0).abs() < 1e-5, "{a:?}");
        }
        assert!(a.iter().all(|u| (0.0..1.0).contains(u)));
        assert_ne!(wavelength_sample(0, 3), wavelength_sample(1, 3));
    }
}
