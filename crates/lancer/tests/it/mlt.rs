//! Metropolis light transport (`mlt`) through the film: the same film bits whatever the
//! thread count, a render split into ranges of chains merges into the whole render exactly,
//! and on a diffuse scene its image agrees with path tracing's.

use crate::common::lit_floor::{in_fog, lit_floor, quad, render_film as render};
use lancer::film::Film;
use lancer::integrator::Integrator;
use lancer::integrator::mlt::MltOptions;
use lancer::math::{Rgb, Vec3};
use lancer::render::RenderSettings;
use lancer::scene::desc::SceneDesc;

/// A diffuse floor and back wall under a point light, `w × h` pixels.
fn desc(integrator: Integrator, w: u32, h: u32) -> SceneDesc {
    let mut d = lit_floor(
        integrator,
        Vec3::new(0.6, 1.0, 0.2),
        Vec3::new(0.0, 1.5, 3.0),
        Vec3::new(0.0, 0.6, 0.0),
        w,
        h,
    );
    d.shapes.push(quad([
        [-2.0, 0.0, -1.0],
        [2.0, 0.0, -1.0],
        [2.0, 3.0, -1.0],
        [-2.0, 3.0, -1.0],
    ]));
    d
}

fn mlt(chains: u32, mutations_per_pixel: u32, bootstrap_samples: u32) -> Integrator {
    Integrator::Mlt(MltOptions {
        max_depth: 3,
        bootstrap_samples,
        chains,
        mutations_per_pixel,
        large_step_probability: 0.3,
        sigma: 0.01,
        regularize: false,
    })
}

#[test]
fn mlt_renders_are_exact_across_threads_and_chain_splits() {
    let chains = 7;
    let clear = desc(mlt(chains, 4, 300), 20, 14);
    // The render's sample indices are its chains.
    assert_eq!(clear.integrator.sample_indices(clear.sampler.spp), chains);
    assert_eq!(RenderSettings::from_desc(&clear).samples, 0..chains);
    let foggy = in_fog(clear.clone());
    for (spectral, d) in [
        (false, &clear),
        (true, &clear),
        (false, &foggy),
        (true, &foggy),
    ] {
        let whole = render(d, 0..chains, 1, spectral);
        let splats = whole.splats.as_ref().expect("mlt splats");
        assert!(splats.sums.iter().any(|&s| s != 0));
        assert!(whole.image(1.0).iter().any(|p| p.x > 0.0));
        assert_eq!(
            render(d, 0..chains, 3, spectral),
            whole,
            "spectral {spectral}"
        );
        let mut merged = Film::new(20, 14, d.film.render_bounds());
        for r in [0..2, 2..5, 5..chains] {
            merged.merge_film(&render(d, r, 2, spectral));
        }
        assert_eq!(merged, whole, "spectral {spectral}: split by chains");
    }
}

/// Mean colour of the pixels of `image` (`w` wide) in columns `x0..x1`, rows `y0..y1`.
fn block_mean(
    image: &[Rgb],
    w: usize,
    x: std::ops::Range<usize>,
    y: std::ops::Range<usize>,
) -> Rgb {
    let mut s = Rgb::ZERO;
    let mut n = 0.0;
    for j in y {
        for i in x.clone() {
            s += image[j * w + i];
            n += 1.0;
        }
    }
    s / n
}

/// Renders `scene(mlt)` by mlt (64 chains, `n` mutations per pixel) and `scene(reference)` by
/// the camera-path integrator `reference` at `n / 2` spp, in both modes, and asserts that the
/// whole image and its quadrants agree within `whole` and `quadrant`: a wrong normalisation b
/// (say without the factor maxdepth + 1 = 4), a wrong scale or a wrong share of the
/// light-tracing strategies moves them by far more.
fn agrees(
    scene: fn(Integrator) -> SceneDesc,
    reference: Integrator,
    n: u32,
    whole: f32,
    quadrant: f32,
) {
    let (w, h) = (32u32, 24u32);
    for spectral in [false, true] {
        let mut p = scene(reference);
        p.sampler.spp = n / 2;
        let reference = render(&p, 0..n / 2, 2, spectral).image(1.0);
        let image = render(&scene(mlt(64, n, 20_000)), 0..64, 2, spectral).image(1.0);
        let (w2, h2) = (w as usize / 2, h as usize / 2);
        let blocks = [
            (0..w as usize, 0..h as usize, whole),
            (0..w2, 0..h2, quadrant),
            (w2..w as usize, 0..h2, quadrant),
            (0..w2, h2..h as usize, quadrant),
            (w2..w as usize, h2..h as usize, quadrant),
        ];
        for (x, y, tol) in blocks {
            let a = block_mean(&image, w as usize, x.clone(), y.clone());
            let b = block_mean(&reference, w as usize, x.clone(), y.clone());
            for c in 0..3 {
                assert!(
                    b[c] > 0.01 && (a[c] / b[c] - 1.0).abs() < tol,
                    "spectral {spectral}, block {x:?}×{y:?}: mlt {a:?}, reference {b:?}"
                );
            }
        }
    }
}

#[test]
fn mlt_agrees_with_path_tracing_on_a_diffuse_scene() {
    agrees(
        |i| desc(i, 32, 24),
        Integrator::Path {
            max_depth: 3,
            regularize: false,
        },
        512,
        0.03,
        0.08,
    );
}

#[test]
fn mlt_through_fog_agrees_with_volpath() {
    // The same scene in a chromatic fog: mlt's paths scatter in the medium as bdpt's do. Both
    // images are noisier here (over four seeds, a channel's mean moves by up to 4 % in each),
    // hence wider bounds, which still tell this image from the scene without its fog (23 %
    // brighter: 0.068, 0.046, 0.026 against 0.054, 0.035, 0.021).
    agrees(
        |i| in_fog(desc(i, 32, 24)),
        Integrator::VolPath {
            max_depth: 3,
            regularize: false,
        },
        2048,
        0.08,
        0.15,
    );
}
