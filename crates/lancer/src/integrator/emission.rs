//! Light given off by the surface a path hits (area lights): its colour there, the radiance
//! towards the path; and by the environment a path escapes to.

use crate::math::{Rgb, SampledSpectrum, Vec3};
use crate::ray::Ray;
use crate::scene::{Scene, SceneHit};
use crate::spectrum::sampled::SampledWavelengths;

/// An image emitter's radiance at surface coordinates `uv` (its light holds the image:
/// pbrt-v4's `DiffuseAreaLight::L` by uv); out of line, so that other emitters pay only the
/// test.
#[cold]
#[inline(never)]
fn image_emission(
    scene: &Scene,
    light: u32,
    l: crate::math::PackedRgb,
    uv: crate::math::Vec2,
) -> Rgb {
    match scene.lights()[light as usize].as_area() {
        Some(a) if let Some(img) = &a.image => img.le(uv),
        _ => l.into(),
    }
}

/// If the surface at `hit` emits towards `wo`: its light's index and the colour it gives off
/// there (its constant `l`, or with an image the image at the hit's uv).
#[inline(always)]
pub(crate) fn emission_towards(scene: &Scene, hit: &SceneHit, wo: Vec3) -> Option<(usize, Rgb)> {
    emission_at(scene, hit.prim, hit.si.n, hit.si.uv, wo)
}

/// Radiance emitted by the surface at `hit` towards `wo` (area lights), at the wavelengths
/// `lambda` in spectral mode.
pub(crate) fn emitted(
    scene: &Scene,
    hit: &SceneHit,
    wo: Vec3,
    lambda: Option<&SampledWavelengths>,
) -> SampledSpectrum {
    emission_towards(scene, hit, wo).map_or(SampledSpectrum::ZERO, |(i, l)| {
        scene.light_radiance(i, lambda, l, 1.0, -wo)
    })
}

/// The light on primitive `prim` (geometric normal `n`, surface coordinates `uv` at the
/// point) and the colour it gives off towards `w`, if it emits that way: what
/// [`emission_towards`] asks of a hit, and what the vertices of light paths, which keep no
/// [`SceneHit`], ask directly.
#[inline(always)]
pub(crate) fn emission_at(
    scene: &Scene,
    prim: u32,
    n: Vec3,
    uv: crate::math::Vec2,
    w: Vec3,
) -> Option<(usize, Rgb)> {
    let e = scene.prim(prim).emission?;
    if !(e.two_sided || n.dot(w) > 0.0) {
        return None;
    }
    let l = if e.spectrum == crate::scene::IMAGE_EMISSION {
        image_emission(scene, e.light, e.l, uv)
    } else {
        e.l.into()
    };
    Some((e.light as usize, l))
}

/// Radiance from the environment lights along a ray leaving the scene in direction `d`:
/// Σ Le(d) over [`Scene::infinite_lights`] ([`Scene::environment_radiance`] each), at the
/// wavelengths `lambda` in spectral mode.
pub(crate) fn environment(
    scene: &Scene,
    d: Vec3,
    lambda: Option<&SampledWavelengths>,
) -> SampledSpectrum {
    let mut le = SampledSpectrum::ZERO;
    for &i in scene.infinite_lights() {
        le += scene.environment_radiance(i as usize, lambda, d);
    }
    le
}

/// The normal of area light `i` at `p`, a point its `sample_li` chose (zero for the other
/// lights). Triangles and spheres know it; other shapes are asked by a ray from `from`, the
/// lit point (position, rounding error, geometric normal).
pub(crate) fn light_normal(scene: &Scene, i: usize, p: Vec3, from: (Vec3, Vec3, Vec3)) -> Vec3 {
    match scene.lights()[i].as_area() {
        Some(crate::light::AreaLight { emitter, prim, .. }) => match emitter {
            crate::light::Emitter::Triangle { n, .. } => Vec3::from(*n),
            crate::light::Emitter::Sphere {
                centre,
                radius,
                flip,
                ..
            } => {
                let n = (p - Vec3::from(*centre)) / *radius;
                if *flip { -n } else { n }
            }
            crate::light::Emitter::Shape => {
                let d = p - from.0;
                let ray = Ray::spawn(from.0, from.1, from.2, d * 1.001);
                scene
                    .intersect(&ray)
                    .filter(|h| h.prim == *prim)
                    .map_or(Vec3::ZERO, |h| h.si.n)
            }
        },
        _ => Vec3::ZERO,
    }
}

/// Whether the rays of a light at infinity arriving along ±`w` can reach `p`: they start on
/// the scene's disk (the bounding sphere's radius r, centre c, facing w), so they pass only
/// through the cylinder that disk sweeps, |(p − c) − ((p − c)·w)·w| ≤ r (`w` of unit length).
/// pbrt-v4's surfaces all lie within it; lancer's infinite planes reach past it, where the
/// light subpaths' strategies must weigh nothing in MIS (bdpt, vcm).
pub(crate) fn reached_from_infinity(scene: &Scene, p: Vec3, w: Vec3) -> bool {
    let (c, r) = scene.bounds().bounding_sphere();
    let d = p - c;
    (d - w * d.dot(w)).length_squared() <= r * r
}
