//! Numerical hygiene: a scene of degenerate geometry and extreme parameters (zero-area and
//! sub-precision area lights, a point light on a surface, zero-length shading normals,
//! degenerate uv, slivers, roughness 0 and 1, index-matched glass, a zero-thickness coat)
//! gives a finite radiance for every camera sample, with every integrator.
//!
//! The renderer replaces a non-finite sample by black before it reaches the film, so looking
//! at the image would prove nothing: this test calls the integrators itself, sample by sample.

use crate::common::*;
use lancer::Scene;
use lancer::film::tile::FilmKind;
use lancer::filter::Filter;
use lancer::integrator::Integrator;
use lancer::math::Vec2;
use lancer::render::RenderSettings;
use lancer::sampling::Sampler;

#[test]
fn degenerate_scene_gives_only_finite_samples() {
    let path = data("stress/degenerate.pbrt");
    let loaded = lancer_scene::load(&path).expect("the stress scene loads");
    let desc = loaded.desc;
    let scene = Scene::build(&desc).expect("the stress scene builds");
    let filter = Filter::new(desc.filter);
    let integrators = [
        desc.integrator,
        Integrator::Path {
            max_depth: 8,
            regularize: true,
        },
        Integrator::Whitted { max_depth: 5 },
        Integrator::AmbientOcclusion {
            cos_sample: true,
            max_distance: 1.0,
        },
        Integrator::Normals,
        Integrator::Depth,
    ];
    let (w, h) = (desc.film.xresolution as i32, desc.film.yresolution as i32);
    let spp = desc.sampler.spp;
    let mut bad = Vec::new();
    let mut samples = 0u64;
    for integrator in &integrators {
        let mut sampler = Sampler::new(desc.sampler.kind, spp, desc.sampler.seed);
        for y in 0..h {
            for x in 0..w {
                for s in 0..spp {
                    sampler.start_pixel_sample(x, y, s as u64);
                    let (offset, _) = filter.sample(sampler.get_pixel_2d());
                    let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                    let p_lens = sampler.get_2d();
                    let ray = scene
                        .camera()
                        .generate_ray(p_film, p_lens)
                        .expect("a ray")
                        .ray;
                    let l = integrator.li(&scene, &ray, &mut sampler, None);
                    samples += 1;
                    if !l.is_finite() && bad.len() < 10 {
                        bad.push(format!("{integrator:?} pixel ({x}, {y}) sample {s}: {l:?}"));
                    }
                }
            }
        }
    }
    assert!(samples >= 6 * 48 * 32 * 16, "only {samples} samples taken");
    assert!(bad.is_empty(), "non-finite radiance:\n{}", bad.join("\n"));
}

/// A scene whose right-hand sphere emits NaN radiance (possible only through the library: the
/// scene reader refuses NaN), rendered with `threads` workers and `tile`-pixel tiles.
fn render_with_nan_sphere(
    threads: usize,
    tile: u32,
) -> (
    lancer::render::RenderStats,
    Vec<lancer::math::Rgb>,
    Scene,
    RenderSettings,
) {
    let text = "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n\
        Film \"rgb\" \"integer xresolution\" [40] \"integer yresolution\" [24]\n\
        Sampler \"independent\" \"integer pixelsamples\" [4]\nIntegrator \"path\"\nWorldBegin\n\
        LightSource \"infinite\" \"rgb L\" [1 1 1]\n\
        AttributeBegin\n Material \"diffuse\" \"rgb reflectance\" [0.5 0.5 0.5]\n\
         Translate 1 0 0\n Shape \"sphere\" \"float radius\" [0.6]\nAttributeEnd\n\
        AttributeBegin\n AreaLightSource \"diffuse\" \"rgb L\" [0.123 0.123 0.123]\n\
         Translate -1 0 0\n Shape \"sphere\" \"float radius\" [0.6]\nAttributeEnd\n";
    let mut desc = lancer_scene::load_pbrt_str(text, "nan.pbrt", std::path::Path::new("."))
        .expect("the scene loads")
        .desc;
    let mut poisoned = 0;
    for sd in &mut desc.shapes {
        if let Some(light) = &mut sd.area_light {
            light.l = lancer::math::Rgb::splat(f32::NAN);
            poisoned += 1;
        }
    }
    assert_eq!(poisoned, 1, "one emitter to poison");
    let scene = Scene::build(&desc).unwrap();
    let bounds = lancer::film::PixelBounds {
        x0: 0,
        x1: 40,
        y0: 0,
        y1: 24,
    };
    let settings = RenderSettings {
        bounds,
        seed: 3,
        tile_size: tile,
        max_component_value: f32::INFINITY,
        // In RGB mode the NaN colour reaches the radiance as it is; spectral mode's uplift
        // would turn it into black (a spectrum of scale 0) before it could poison anything.
        spectral: false,
        ..RenderSettings::from_desc(&desc)
    };
    let mut film = lancer::film::Film::new(40, 24, bounds);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let stats = pool.install(|| {
        lancer::render::render(&scene, &settings, &mut film, &|_| {}, &Default::default())
    });
    (stats, film.image(1.0), scene, settings)
}

#[test]
fn nonfinite_samples_are_counted_dropped_and_replayed() {
    let (a, image, scene, settings) = render_with_nan_sphere(1, 16);
    let (b, _, _, _) = render_with_nan_sphere(2, 7);
    // The sphere covers many pixels: many samples, every one dropped from the image.
    assert!(a.nonfinite > 50, "{} non-finite samples", a.nonfinite);
    assert!(image.iter().all(|c| c.is_finite()));
    // The count and the first one do not depend on threads or tiles.
    assert_eq!(
        (a.nonfinite, a.first_nonfinite),
        (b.nonfinite, b.first_nonfinite)
    );
    let first = a.first_nonfinite.expect("a first non-finite sample");
    // Replaying it gives the same non-finite radiance, along a path that reaches the
    // poisoned sphere (seen or hit) or samples it as a light (the radiance gathered so far
    // turns non-finite at that vertex).
    let (l, path) = lancer::render::trace_sample(&scene, &settings, FilmKind::Rgb, first);
    assert!(!l.is_finite(), "replayed radiance {l:?}");
    let on_poisoned = |p: lancer::math::Vec3| {
        ((p - lancer::math::Vec3::new(-1.0, 0.0, 0.0)).length() - 0.6).abs() < 1e-3
    };
    assert!(
        path.iter().any(|v| on_poisoned(v.p) || !v.l.is_finite()),
        "no vertex of {path:?} shows the poisoned sphere"
    );
    // Every sample before it in (row, column, sample) order is finite.
    for y in 0..=first.y {
        for x in 0..40 {
            for s in 0..settings.spp {
                let id = lancer::render::SampleId { y, x, sample: s };
                if id >= first {
                    continue;
                }
                let (l, _) = lancer::render::trace_sample(&scene, &settings, FilmKind::Rgb, id);
                assert!(l.is_finite(), "{id:?} gave {l:?} before the first");
            }
        }
    }
}
