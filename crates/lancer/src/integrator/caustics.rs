//! Path tracing with caustics by light tracing (lancer's `Integrator "path" "bool caustics"
//! [true]`): the path tracer's estimate of every path except the caustics the camera sees
//! directly, which light tracing renders instead.
//!
//! A caustic seen directly is a path E D S⁺ L: the camera sees a surface D that scatters by a
//! non-specular lobe, the light reaches it through one or more specular (delta) bounces S. A
//! path from the camera finds it only by BSDF sampling at D through the specular chain into
//! the light: never for a delta light (a `distant` sun, a point light behind glass), rarely
//! for a small one (the sun of a `sunsky`). A path from the light finds it with the density
//! of the light's own emission, and joins D to the lens deterministically. So the two
//! estimators split the paths between them, for the light that is a caustic source
//! ([`crate::light::Light::caustic_source`]: every delta light's, the sun's disk of a sky):
//!
//! - the camera path ([`super::path::li_without_caustics`]) is the path tracer's, leaving out
//!   a caustic source's light met at the end of E D S⁺;
//! - with probability `causticpaths` per camera sample, one light path (a light chosen by
//!   power, a ray leaving it, as `lightpath`; kept only if it leaves a caustic source) follows
//!   specular bounces only: at each surface it meets after at least one specular bounce, the
//!   surface's non-specular lobes are joined to the lens (splatted, β·f·|cos θ|·We/p_c as
//!   `lightpath`, divided by `causticpaths`), and the path goes on only while the surface's
//!   sampled lobe is specular. A path whose first surface is non-specular ends there: direct
//!   light is the camera path's.
//!
//! Every path belongs to exactly one of the two, so their sum is the path tracer's image with
//! its caustics rendered by the estimator that finds them. Light from infinity (distant
//! lights, the sun) is aimed at the surfaces that may scatter specularly
//! ([`crate::scene::Scene::caustic_casters`]): its rays start on the disk of their bounding
//! sphere rather than of the whole scene, since a ray that meets no such surface first carries
//! nothing. At most `max_depth` bounces in both; surfaces only, as `path` (media are
//! ignored); no regularisation (it would change which bounces are specular on one side only).

use super::lightpath::to_camera;
use super::{Splat, bsdf_at, keep_hero_only, path};
use crate::light::LightType;
use crate::material::TransportMode;
use crate::math::{Frame, PI, SampledSpectrum, Vec3};
use crate::ray::Ray;
use crate::sampling::Sampler;
use crate::sampling::sample_uniform_disk_concentric;
use crate::scene::Casters;
use crate::scene::Scene;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// Light paths per camera sample by default (`causticpaths`).
pub const DEFAULT_PATHS: f32 = 0.125;

/// Radiance along a camera ray without the caustics it sees directly, and, with probability
/// `paths`, one light path's caustics splatted (weighted by 1/`paths`): see the module.
pub fn li(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    paths: f32,
    splat: Splat<'_>,
) -> SampledSpectrum {
    let l = path::li_without_caustics(scene, ray, sampler, lambda, max_depth);
    if sampler.get_1d() < paths {
        let scale = 1.0 / paths;
        caustic_light_path(scene, sampler, lambda, max_depth, &mut |p, l| {
            splat(p, l * scale)
        });
    }
    l
}

/// One light path of the caustics estimator: from a light chosen by power, through specular
/// bounces only, each surface met after the first of them joined to the lens.
fn caustic_light_path(
    scene: &Scene,
    sampler: &mut Sampler,
    lambda: Option<&SampledWavelengths>,
    max_depth: u32,
    splat: Splat<'_>,
) {
    let casters = scene.caustic_casters();
    let (ul, u1, u2) = (sampler.get_1d(), sampler.get_2d(), sampler.get_2d());
    if casters == Casters::None {
        return;
    }
    let Some((light, p_l)) = scene.light_distribution().sample(ul) else {
        return;
    };
    let emitter = &scene.lights()[light];
    let Some(mut les) = emitter.sample_le(u1, u2, scene.shapes(), scene.meshes()) else {
        return;
    };
    // Only the caustic sources' light is light tracing's.
    if p_l == 0.0 || les.pdf_pos == 0.0 || les.pdf_dir == 0.0 || !emitter.caustic_source(les.w) {
        return;
    }
    // Light from infinity (its rays start uniformly on a disk across the scene, Le the same
    // for every start) is aimed at the surfaces that may start a caustic: a point uniform on
    // the disk of their bounding sphere (c, ρ) across the ray, outside the scene (a distance
    // D = R + |c − C| + ρ back from c, (C, R) the scene's sphere), density 1/(π ρ²).
    // A ray that misses that sphere meets no specular surface first, so it carried nothing.
    if let Casters::Within(c, rho) = casters
        && matches!(
            emitter.light_type(),
            LightType::DeltaDirection | LightType::Infinite
        )
    {
        let (centre, radius) = scene.bounds().bounding_sphere();
        let d = radius + (c - centre).length() + rho;
        let disk = sample_uniform_disk_concentric(u2) * rho;
        les.p = c + Frame::from_z(les.w).from_local(Vec3::new(disk.x, disk.y, 0.0)) - les.w * d;
        les.p_error = Vec3::ZERO;
        les.pdf_pos = 1.0 / (PI * rho * rho);
    }
    crate::counters::count_light_path();
    let mut wavelengths = lambda.copied();
    let le = scene.light_radiance(light, wavelengths.as_ref(), les.l, les.factor, -les.w);
    // β = Le·|cos θ₀| / (p_l·p_pos·p_dir).
    let mut beta = le * (les.abs_cos() / (p_l * les.pdf_pos * les.pdf_dir));
    let mut ray = les.ray();
    // Bounces so far, all specular.
    let mut bounces = 0u32;
    while bounces < max_depth
        && beta != SampledSpectrum::ZERO
        && beta.is_finite()
        && let Some(hit) = scene.intersect(&ray)
    {
        let si = &hit.si;
        let Some((bsdf, disperses)) = bsdf_at(scene, &hit, wavelengths.as_ref()) else {
            // An interface between media: the ray goes on.
            ray = si.spawn_ray(ray.d);
            continue;
        };
        if keep_hero_only(&mut wavelengths, disperses) {
            beta *= HERO_ONLY;
        }
        // The surface the camera sees, lit through at least one specular bounce: its
        // non-specular lobes (f has no delta part) joined to the lens.
        if bounces > 0 && bsdf.flags().is_non_specular() {
            to_camera(scene, si, &bsdf, beta, sampler.get_2d(), splat);
        }
        let uc = sampler.get_1d();
        let Some(bs) = bsdf.sample_f(si.wo, uc, sampler.get_2d(), TransportMode::Importance) else {
            break;
        };
        // A non-specular bounce leaves the caustics: what follows is the camera path's.
        if !bs.is_specular() {
            break;
        }
        beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
        ray = si.spawn_ray(bs.wi);
        bounces += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::Film;
    use crate::integrator::Integrator;
    use crate::integrator::bdpt::tests::{bdpt, blocks, compare, path, room_desc};
    use crate::integrator::test_scenes::{diffuse, quad, sphere, view};
    use crate::light::{LightDesc, SunskyDesc, SunskyParams};
    use crate::material::{DielectricMaterial, MaterialDesc};
    use crate::math::Rgb;
    use crate::math::Transform;
    use crate::render::{RenderSettings, RenderStats};
    use crate::scene::desc::SceneDesc;
    use crate::spectrum::Ior;
    use crate::texture::FloatTex;

    fn caustics(paths: f32) -> Integrator {
        Integrator::PathCaustics {
            max_depth: 5,
            paths,
        }
    }

    /// `desc` with `integrator` at `spp` samples and `seed`, RGB mode, on `threads` threads.
    fn render(
        desc: &SceneDesc,
        integrator: Integrator,
        spp: u32,
        seed: u64,
        threads: usize,
    ) -> (Film, RenderStats) {
        let mut d = desc.clone();
        d.integrator = integrator;
        d.sampler.spp = spp;
        d.sampler.seed = seed;
        let settings = RenderSettings {
            spectral: false,
            ..RenderSettings::from_desc(&d)
        };
        crate::render::testing::render_on(&d, &settings, threads, 8)
    }

    /// Smooth glass of index 1.5.
    fn smooth_glass() -> MaterialDesc {
        MaterialDesc::Dielectric(DielectricMaterial {
            eta: Ior::Constant(1.5),
            uroughness: FloatTex::Const(0.0),
            vroughness: FloatTex::Const(0.0),
            remap_roughness: false,
        })
    }

    /// bdpt's room lit by a point light, with a smooth glass sphere in the air: a caustic
    /// that no camera path can find.
    fn room_with_glass() -> SceneDesc {
        let mut d = room_desc(false, path(5));
        d.materials.push(smooth_glass());
        let glass = d.materials.len() as u32 - 1;
        d.shapes
            .push(sphere(Vec3::new(-0.4, 0.7, 0.3), 0.35, glass));
        d
    }

    #[test]
    fn agrees_with_bdpt_where_path_tracing_misses_the_caustic() {
        let d = room_with_glass();
        let (want, _) = render(&d, bdpt(5), 1024, 1, 2);
        let want = want.image(1.0);
        // The scene has a caustic: path tracing alone is far from bdpt somewhere.
        let (pt, _) = render(&d, path(5), 256, 2, 2);
        let (worst_pt, _) = compare(&pt.image(1.0), &want);
        assert!(worst_pt > 0.3, "path tracing's worst block {worst_pt}");
        for paths in [1.0, 0.25] {
            let (got, stats) = render(&d, caustics(paths), 256, 2, 2);
            let (worst, ratio) = compare(&got.image(1.0), &want);
            assert!(
                worst < 0.1 && (ratio - 1.0).abs() < 0.02,
                "causticpaths {paths}: worst block {worst}, mean ratio {ratio}"
            );
            assert!(stats.light_paths > 0 && stats.connections > 0);
        }
    }

    #[test]
    fn without_specular_surfaces_it_is_the_path_tracer() {
        // No caster: no light path goes anywhere, and the camera paths are path's, bit for bit.
        let d = room_desc(false, path(5));
        let (want, _) = render(&d, path(5), 16, 3, 2);
        let (got, stats) = render(&d, caustics(1.0), 16, 3, 2);
        assert_eq!(got.image(1.0), want.image(1.0));
        assert_eq!(stats.connections, 0);
    }

    #[test]
    fn bits_do_not_depend_on_threads() {
        let d = room_with_glass();
        let (one, _) = render(&d, caustics(0.5), 8, 4, 1);
        let (three, _) = render(&d, caustics(0.5), 8, 4, 3);
        assert_eq!(one, three);
    }

    /// A glass sphere over a floor (z up) under a sun and sky, the sun from the left at 50°:
    /// the sun's caustic lies on the floor beside the sphere, in view.
    fn sun_and_glass() -> SceneDesc {
        let floor = quad(
            [
                [-2.0, -2.0, 0.0],
                [2.0, -2.0, 0.0],
                [2.0, 2.0, 0.0],
                [-2.0, 2.0, 0.0],
            ],
            0,
        );
        let glass = sphere(Vec3::new(-0.2, 0.0, 0.6), 0.4, 1);
        SceneDesc {
            materials: vec![diffuse(Rgb::splat(0.6)), smooth_glass()],
            shapes: vec![floor, glass],
            lights: vec![LightDesc::Sunsky(SunskyDesc {
                light_to_world: Transform::IDENTITY,
                params: SunskyParams::new(Vec3::new(-1.0, 0.2, 1.2)),
            })],
            ..view(
                Vec3::new(0.0, -3.0, 2.6),
                Vec3::new(0.2, 0.0, 0.2),
                Vec3::new(0.0, 0.0, 1.0),
                30.0,
                path(5),
            )
        }
    }

    #[test]
    fn the_suns_caustic_is_light_tracings_and_the_rest_path_tracings() {
        // The sun is a disk: path tracing finds its caustic through the glass now and then, so
        // the camera paths of `caustics` must leave it out (alone, with light paths almost
        // never traced, they fall short of bdpt there, where path tracing does not), and light
        // tracing (aimed at the glass) must bring it in full; the sky's light through the
        // glass stays the camera paths'.
        let d = sun_and_glass();
        let sum = |img: &[Rgb]| {
            blocks(img)
                .iter()
                .map(|c| c.x + c.y + c.z)
                .collect::<Vec<_>>()
        };
        let (want, _) = render(&d, bdpt(5), 1024, 1, 2);
        let (pt, _) = render(&d, path(5), 4096, 2, 2);
        let (cam, _) = render(&d, caustics(1e-9), 4096, 2, 2);
        let (full, stats) = render(&d, caustics(1.0), 256, 3, 2);
        let (worst, ratio) = compare(&full.image(1.0), &want.image(1.0));
        assert!(
            worst < 0.1 && (ratio - 1.0).abs() < 0.02,
            "worst block {worst}, mean ratio {ratio}"
        );
        assert!(stats.connections > 0);
        let [want, pt, cam, full] = [&want, &pt, &cam, &full].map(|f| sum(&f.image(1.0)));
        // The block where the caustic is: where the camera paths alone fall shortest of bdpt.
        let k = (0..want.len())
            .max_by(|&a, &b| (want[a] - cam[a]).total_cmp(&(want[b] - cam[b])))
            .unwrap();
        let caustic = want[k] - cam[k];
        let msg = format!(
            "bdpt {} path {} camera paths {} both {}",
            want[k], pt[k], cam[k], full[k]
        );
        assert!(caustic > 0.25 * want[k], "no caustic: {msg}");
        assert!(pt[k] - cam[k] > 0.5 * caustic, "{msg}");
        assert!((full[k] - want[k]).abs() < 0.1 * caustic, "{msg}");
    }
}
