//! bdpt's strategy images ([`crate::render::strategies`], `visualizestrategies` and
//! `visualizeweights`) on the diffuse room: rendering them leaves the image's bits alone, the
//! weighted ones add up to the image, each unweighted one converges to the light of its depth
//! as the path tracer computes it, and none depends on the thread count.

use super::tests::{bdpt, compare, path, render, room, room_desc};
use crate::film::Film;
use crate::integrator::Integrator;
use crate::math::Rgb;
use crate::render::strategies::{ObservedBdpt, Strategy, StrategyImages, strategies};
use crate::render::{RenderJob, RenderSettings, render_units_with, work_units};
use crate::scene::Scene;
use crate::scene::desc::{FilterDesc, SceneDesc};

/// The film of `desc` rendered over samples `0..spp` on `threads` threads, by bdpt as
/// `desc.integrator` sets it, and, when `weighted` is given, with its strategy images
/// (weighted or not) observed on the way.
fn render_film(
    desc: &SceneDesc,
    spp: u32,
    threads: usize,
    spectral: bool,
    weighted: Option<bool>,
) -> (Film, Vec<(Strategy, Vec<Rgb>)>) {
    let Integrator::Bdpt {
        max_depth,
        regularize,
        ..
    } = desc.integrator
    else {
        panic!("a bdpt scene");
    };
    let scene = Scene::build(desc).unwrap();
    let settings = RenderSettings {
        samples: 0..spp,
        spp,
        spectral,
        ..RenderSettings::from_desc(desc)
    };
    let bounds = desc.film.render_bounds();
    let mut film = Film::new(desc.film.xresolution, desc.film.yresolution, bounds);
    let units = work_units(&bounds, 8, 0..spp, 3);
    let mut done = vec![false; units.len()];
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let images = weighted.map(|w| StrategyImages::new(max_depth, w, settings.splat_bounds));
    pool.install(|| match &images {
        Some(images) => {
            let observed = ObservedBdpt {
                options: super::BdptOptions {
                    max_depth,
                    regularize,
                },
                images,
                filter: &settings.filter,
            };
            let f = &mut film;
            render_units_with(
                RenderJob::new(&scene, &settings, f, &units, &mut done),
                &observed,
            )
        }
        None => render_units_with(
            RenderJob::new(&scene, &settings, &mut film, &units, &mut done),
            &settings.integrator,
        ),
    });
    let images = images.map_or_else(Vec::new, |i| i.images(&film, 1.0));
    (film, images)
}

#[test]
fn strategy_names_and_order_are_pbrt_v4s() {
    let names: Vec<String> = strategies(2).iter().map(Strategy::file_name).collect();
    assert_eq!(
        names,
        [
            "bdpt_d00_s00_t02.exr",
            "bdpt_d01_s00_t03.exr",
            "bdpt_d01_s01_t02.exr",
            "bdpt_d01_s02_t01.exr",
            "bdpt_d02_s00_t04.exr",
            "bdpt_d02_s01_t03.exr",
            "bdpt_d02_s02_t02.exr",
            "bdpt_d02_s03_t01.exr",
        ]
    );
    // pbrt-v4 allocates (1 + d)(6 + d)/2 buffers, t = 0 and (1, 1) left empty: d + 2
    // strategies per depth d ≥ 1 and one at depth 0.
    assert_eq!(strategies(5).len(), 1 + (3..=7).sum::<usize>());
}

#[test]
fn weighted_strategy_images_add_up_to_the_image_and_leave_it_alone() {
    // A Gaussian filter of radius 1.5: camera samples of varying weight, splats spread over
    // 3 × 3 pixels, as the image's.
    let mut desc = room_desc(true, bdpt(3));
    desc.filter = FilterDesc::Gaussian {
        radius: [1.5, 1.5],
        sigma: 0.5,
    };
    for spectral in [false, true] {
        let (plain, _) = render_film(&desc, 6, 2, spectral, None);
        let (film, images) = render_film(&desc, 6, 2, spectral, Some(true));
        assert_eq!(
            film, plain,
            "spectral {spectral}: observing changed the image"
        );
        let (film1, images1) = render_film(&desc, 6, 1, spectral, Some(true));
        assert_eq!(film1, film);
        assert_eq!(
            images1, images,
            "spectral {spectral}: threads changed the images"
        );
        assert_eq!(images.len(), strategies(3).len());
        let image = film.image(1.0);
        let mut sum = vec![Rgb::ZERO; image.len()];
        for (_, img) in &images {
            for (a, b) in sum.iter_mut().zip(img) {
                *a += *b;
            }
        }
        let mean = image.iter().map(|c| c.x + c.y + c.z).sum::<f32>() / (3 * image.len()) as f32;
        assert!(mean > 0.01, "a lit room: {mean}");
        for (i, (a, b)) in sum.iter().zip(&image).enumerate() {
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() <= 1e-4 * b[c].abs() + 1e-6,
                    "spectral {spectral}, pixel {i}: strategies sum to {a}, image {b}"
                );
            }
        }
        // Light tracing (t = 1) and every camera-side strategy of depth 1 brought something.
        for st in [(0, 3), (1, 2), (2, 1)] {
            let (_, img) = images.iter().find(|(s, _)| (s.s, s.t) == st).unwrap();
            assert!(img.iter().any(|c| c.y > 0.0), "strategy {st:?} is empty");
        }
    }
}

#[test]
fn each_unweighted_strategy_image_converges_to_the_light_of_its_depth() {
    // Acceptance 4 of the light-transport issue: each strategy alone gives the image of its
    // depth, the path tracer's at maxdepth d less its image at maxdepth d − 1 (the camera
    // does not see the light: nothing at depth 0).
    let desc = room_desc(true, bdpt(2));
    let (_, images) = render_film(&desc, 512, 2, false, Some(false));
    let scene = room(true, path(2));
    let depth1 = render(&scene, path(1), 512, 4, None);
    let upto2 = render(&scene, path(2), 512, 5, None);
    let depth2: Vec<Rgb> = upto2.iter().zip(&depth1).map(|(a, b)| *a - *b).collect();
    for (st, img) in &images {
        let reference = match st.depth() {
            0 => {
                assert!(img.iter().all(|c| *c == Rgb::ZERO), "{st:?} sees the light");
                continue;
            }
            1 => &depth1,
            _ => &depth2,
        };
        let (worst, ratio) = compare(img, reference);
        // The strategies that hit the small light by chance (s = 0) are noisier.
        let (bound, mean_bound) = if st.s == 0 {
            (0.35, 0.05)
        } else {
            (0.15, 0.03)
        };
        assert!(
            worst < bound && (ratio - 1.0).abs() < mean_bound,
            "strategy {st:?}: worst block {worst}, mean ratio {ratio}"
        );
    }
}
