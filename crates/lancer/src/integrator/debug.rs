//! Debug views: normals, depth, ambient occlusion.

use crate::math::{Frame, Rgb};
use crate::ray::Ray;
use crate::sampling::{Sampler, sample_cosine_hemisphere, sample_uniform_hemisphere};
use crate::scene::Scene;

/// The shading normal of the first hit, mapped from [−1, 1] to [0, 1].
pub fn normals(scene: &Scene, ray: &Ray) -> Rgb {
    scene
        .intersect(ray)
        .map_or(Rgb::ZERO, |h| (h.si.shading.n + Rgb::ONE) * 0.5)
}

/// The distance to the first hit (0 for a miss).
pub fn depth(scene: &Scene, ray: &Ray) -> Rgb {
    scene
        .intersect(ray)
        .map_or(Rgb::ZERO, |h| Rgb::splat(h.si.t * ray.d.length()))
}

/// Fraction of the hemisphere above the first hit left open (cosine-weighted when asked),
/// within `max_distance`.
pub fn ambient_occlusion(
    scene: &Scene,
    ray: &Ray,
    sampler: &mut Sampler,
    cos_sample: bool,
    max_distance: f32,
) -> Rgb {
    let Some(h) = scene.intersect(ray) else {
        return Rgb::ZERO;
    };
    let n = if h.si.n.dot(h.si.wo) < 0.0 {
        -h.si.shading.n
    } else {
        h.si.shading.n
    };
    let frame = Frame::from_z(n);
    let u = sampler.get_2d();
    let local = if cos_sample {
        sample_cosine_hemisphere(u)
    } else {
        sample_uniform_hemisphere(u)
    };
    // With cosine sampling the estimator of (1/π)∫V cos dω is V; with uniform sampling it is
    // V·cos θ·2π/π = 2V cos θ.
    let weight = if cos_sample { 1.0 } else { 2.0 * local.z };
    let mut r = h.si.spawn_ray(frame.from_local(local));
    r.t_max = max_distance / r.d.length();
    if scene.intersect_p(&r) {
        Rgb::ZERO
    } else {
        Rgb::splat(weight)
    }
}
