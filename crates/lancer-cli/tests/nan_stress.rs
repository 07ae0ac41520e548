//! Numerical hygiene: a scene of degenerate geometry and extreme parameters (zero-area and
//! sub-precision area lights, a point light on a surface, zero-length shading normals,
//! degenerate uv, slivers, roughness 0 and 1, index-matched glass, a zero-thickness coat)
//! gives a finite radiance for every camera sample, with every integrator.
//!
//! The renderer replaces a non-finite sample by black before it reaches the film, so looking
//! at the image would prove nothing: this test calls the integrators itself, sample by sample.

mod common;
use common::*;
use lancer::Scene;
use lancer::filter::Filter;
use lancer::integrator::Integrator;
use lancer::math::Vec2;
use lancer::sampling::Sampler;
use lancer::scene::desc::IntegratorDesc;

#[test]
fn degenerate_scene_gives_only_finite_samples() {
    let path = data("stress/degenerate.pbrt");
    let loaded = lancer_scene::load(&path).expect("the stress scene loads");
    let desc = loaded.desc;
    let scene = Scene::build(&desc).expect("the stress scene builds");
    let filter = Filter::new(desc.filter);
    let integrators = [
        desc.integrator,
        IntegratorDesc::Path {
            max_depth: 8,
            regularize: true,
        },
        IntegratorDesc::Whitted { max_depth: 5 },
        IntegratorDesc::AmbientOcclusion {
            cos_sample: true,
            max_distance: 1.0,
        },
        IntegratorDesc::Normals,
        IntegratorDesc::Depth,
    ];
    let (w, h) = (desc.film.xresolution as i32, desc.film.yresolution as i32);
    let spp = desc.sampler.spp;
    let mut bad = Vec::new();
    let mut samples = 0u64;
    for integrator_desc in &integrators {
        let integrator = Integrator::from_desc(integrator_desc);
        let mut sampler = Sampler::new(desc.sampler.kind, spp, desc.sampler.seed);
        for y in 0..h {
            for x in 0..w {
                for s in 0..spp {
                    sampler.start_pixel_sample(x, y, s as u64);
                    let (offset, _) = filter.sample(sampler.get_pixel_2d());
                    let p_film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                    let p_lens = sampler.get_2d();
                    let ray = scene.camera.generate_ray(p_film, p_lens);
                    let l = integrator.li(&scene, &ray, &mut sampler);
                    samples += 1;
                    if !l.is_finite() && bad.len() < 10 {
                        bad.push(format!(
                            "{integrator_desc:?} pixel ({x}, {y}) sample {s}: {l:?}"
                        ));
                    }
                }
            }
        }
    }
    assert!(samples >= 6 * 48 * 32 * 16, "only {samples} samples taken");
    assert!(bad.is_empty(), "non-finite radiance:\n{}", bad.join("\n"));
}
