//! Metropolis light transport (`mlt`) through the film: the same film bits whatever the
//! thread count, a render split into ranges of chains merges into the whole render exactly,
//! and on a diffuse scene its image agrees with path tracing's.

use crate::common::lit_floor::{lit_floor, quad, render_film as render};
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
    let d = desc(mlt(chains, 4, 300), 20, 14);
    // The render's sample indices are its chains.
    assert_eq!(d.integrator.sample_indices(d.sampler.spp), chains);
    assert_eq!(RenderSettings::from_desc(&d).samples, 0..chains);
    for spectral in [false, true] {
        let whole = render(&d, 0..chains, 1, spectral);
        let splats = whole.splats.as_ref().expect("mlt splats");
        assert!(splats.sums.iter().any(|&s| s != 0));
        assert!(whole.image(1.0).iter().any(|p| p.x > 0.0));
        assert_eq!(
            render(&d, 0..chains, 3, spectral),
            whole,
            "spectral {spectral}"
        );
        let mut merged = Film::new(20, 14, d.film.render_bounds());
        for r in [0..2, 2..5, 5..chains] {
            merged.merge_film(&render(&d, r, 2, spectral));
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

#[test]
fn mlt_agrees_with_path_tracing_on_a_diffuse_scene() {
    let (w, h) = (32u32, 24u32);
    for spectral in [false, true] {
        let mut p = desc(
            Integrator::Path {
                max_depth: 3,
                regularize: false,
            },
            w,
            h,
        );
        p.sampler.spp = 256;
        let path = render(&p, 0..256, 2, spectral).image(1.0);
        let m = desc(mlt(64, 512, 20_000), w, h);
        let image = render(&m, 0..64, 2, spectral).image(1.0);
        // The whole image and its quadrants: a wrong normalisation b (say without the factor
        // maxdepth + 1 = 4), a wrong scale or a wrong share of the light-tracing strategies
        // moves them by far more than these bounds.
        let (w2, h2) = (w as usize / 2, h as usize / 2);
        let blocks = [
            (0..w as usize, 0..h as usize, 0.03),
            (0..w2, 0..h2, 0.08),
            (w2..w as usize, 0..h2, 0.08),
            (0..w2, h2..h as usize, 0.08),
            (w2..w as usize, h2..h as usize, 0.08),
        ];
        for (x, y, tol) in blocks {
            let a = block_mean(&image, w as usize, x.clone(), y.clone());
            let b = block_mean(&path, w as usize, x.clone(), y.clone());
            for c in 0..3 {
                assert!(
                    b[c] > 0.01 && (a[c] / b[c] - 1.0).abs() < tol,
                    "spectral {spectral}, block {x:?}×{y:?}: mlt {a:?}, path {b:?}"
                );
            }
        }
    }
}
