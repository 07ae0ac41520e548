//! bdpt and light tracing through the film: the same film bits whatever the thread count, and
//! a render split by samples merges into the whole render exactly (their light paths splat
//! anywhere in the image), with and without a medium around the floor.

use crate::common::lit_floor::{in_fog, lit_floor, render_film as render};
use lancer::film::Film;
use lancer::integrator::Integrator;
use lancer::math::Vec3;
use lancer::scene::desc::SceneDesc;

const W: u32 = 20;
const H: u32 = 14;
const SPP: u32 = 6;

/// A diffuse floor under a point light, seen from above at an angle.
fn desc(integrator: Integrator) -> SceneDesc {
    let mut d = lit_floor(
        integrator,
        Vec3::new(0.3, 1.0, 0.2),
        Vec3::new(0.0, 2.0, 3.0),
        Vec3::ZERO,
        W,
        H,
    );
    d.sampler.spp = SPP;
    d
}

#[test]
fn light_path_renders_are_exact_across_threads_and_sample_splits() {
    for integrator in [
        Integrator::Bdpt {
            max_depth: 4,
            regularize: false,
            visualize_strategies: false,
            visualize_weights: false,
        },
        Integrator::LightPath { max_depth: 4 },
    ] {
        for (spectral, fog) in [(false, false), (true, false), (false, true), (true, true)] {
            let d = if fog {
                in_fog(desc(integrator))
            } else {
                desc(integrator)
            };
            let whole = render(&d, 0..SPP, 1, spectral);
            let splats = whole.splats.as_ref().expect("light paths splat");
            assert!(splats.sums.iter().any(|&s| s != 0));
            assert!(whole.image(1.0).iter().any(|p| p.x > 0.0));
            assert_eq!(
                render(&d, 0..SPP, 2, spectral),
                whole,
                "{integrator:?}, fog {fog}"
            );
            let mut merged = Film::new(W, H, d.film.render_bounds());
            for r in [0..2, 2..5, 5..SPP] {
                merged.merge_film(&render(&d, r, 2, spectral));
            }
            assert_eq!(merged, whole, "{integrator:?}, fog {fog}: split by samples");
        }
    }
}
