//! Light leaving the lights, as light paths start it: pbrt-v4's `SampleLe` and `PDF_Le`.
//!
//! STAND-IN: the architecture issue gives every light kind its own `sample_le` / `pdf_le`
//! (branch `arch-lights`); until that lands, the light tracers use these, which cover the
//! kinds the transport scenes use (point, spot, distant, diffuse area without alpha, uniform
//! environment). The other kinds (image and portal environments, goniometric, projection)
//! emit no light paths here: connections from the camera side still see them.

use crate::light::Light;
use crate::math::{Frame, PI, Rgb, Vec2, Vec3, smooth_step};
use crate::sampling::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_cone,
    sample_uniform_disk_concentric, sample_uniform_sphere, uniform_cone_pdf, uniform_sphere_pdf,
};
use crate::scene::Scene;

/// A ray of light leaving a light (pbrt-v4's `LightLeSample`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LeSample {
    /// Where the ray starts.
    pub o: Vec3,
    /// Bound on the rounding error of `o` (rays leave it offset by that much).
    pub o_error: Vec3,
    /// Unit direction.
    pub d: Vec3,
    /// The emitting surface's normal (area lights); `None` for points and directions.
    pub n: Option<Vec3>,
    /// The emitted colour (radiance, or intensity for point lights) before `factor`, as
    /// [`Scene::light_radiance`] takes it.
    pub l: Rgb,
    /// What the light's constant colour is multiplied by here (see
    /// [`crate::light::LightLiSample::factor`]).
    pub factor: f32,
    /// Density of `o` (per unit area; 1 for point lights, whose position is certain).
    pub pdf_pos: f32,
    /// Density of `d` (per unit solid angle; 1 for distant lights).
    pub pdf_dir: f32,
}

impl LeSample {
    /// |cos θ| between the ray and the emitting surface's normal (1 off surfaces).
    pub fn abs_cos(&self) -> f32 {
        self.n.map_or(1.0, |n| n.dot(self.d).abs())
    }
}

/// The scene's bounding sphere, which distant and environment lights shine through.
pub(crate) fn scene_sphere(scene: &Scene) -> (Vec3, f32) {
    let (c, r) = scene.bounds().bounding_sphere();
    (c, r.max(1e-3))
}

/// A conservative bound on the rounding error of a point sampled on a surface (a few ulps of
/// its largest coordinate).
fn point_error(p: Vec3) -> Vec3 {
    Vec3::splat(p.abs().max_element() * 64.0 * f32::EPSILON)
}

/// Samples a ray leaving light `i` from `u1` (position) and `u2` (direction); `None` when the
/// light emits no light paths (see the module's note) or the sample carries nothing.
pub(crate) fn sample_le(scene: &Scene, i: usize, u1: Vec2, u2: Vec2) -> Option<LeSample> {
    let point = |p: Vec3, d: Vec3, l: Rgb, factor: f32, pdf_dir: f32| LeSample {
        o: p,
        o_error: Vec3::ZERO,
        d,
        n: None,
        l,
        factor,
        pdf_pos: 1.0,
        pdf_dir,
    };
    let s = match &scene.lights()[i] {
        // A uniform direction: p_dir = 1/4π.
        Light::Point { p, intensity } => point(
            *p,
            sample_uniform_sphere(u1),
            *intensity,
            1.0,
            uniform_sphere_pdf(),
        ),
        Light::Spot {
            p,
            axis,
            intensity,
            cos_falloff_start,
            cos_falloff_end,
        } => {
            // The cone of full intensity or the falloff ring, chosen in proportion to their
            // share of the power: (1 − cos θ_s) and (cos θ_s − cos θ_e)/2.
            let (cs, ce) = (*cos_falloff_start, *cos_falloff_end);
            let w = [1.0 - cs, (cs - ce) / 2.0];
            let total = w[0] + w[1];
            if total <= 0.0 {
                return None;
            }
            let frame = Frame::from_z(*axis);
            let (local, pdf_dir) = if u2.x * total < w[0] {
                (
                    sample_uniform_cone(u1, cs),
                    uniform_cone_pdf(cs) * w[0] / total,
                )
            } else {
                let cos = sample_smooth_step(u1.x, ce, cs);
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = 2.0 * PI * u1.y;
                (
                    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos),
                    smooth_step_pdf(cos, ce, cs) * w[1] / (total * 2.0 * PI),
                )
            };
            let falloff = smooth_step(local.z, ce, cs);
            point(
                *p,
                frame.from_local(local),
                *intensity * falloff,
                falloff,
                pdf_dir,
            )
        }
        // A point of the scene's disk facing the light, the ray along the light's direction:
        // p_pos = 1/(π r²).
        Light::Distant { w, l, .. } => {
            let (c, r) = scene_sphere(scene);
            let cd = sample_uniform_disk_concentric(u1);
            let o = c + r * Frame::from_z(*w).from_local(Vec3::new(cd.x, cd.y, 0.0)) + r * *w;
            LeSample {
                o,
                o_error: point_error(o),
                d: -*w,
                n: None,
                l: *l,
                factor: 1.0,
                pdf_pos: 1.0 / (PI * r * r),
                pdf_dir: 1.0,
            }
        }
        Light::UniformInfinite { l, .. } => {
            // A uniform direction w, then a point of the disk facing it, one radius back.
            let (c, r) = scene_sphere(scene);
            let w = sample_uniform_sphere(u1);
            let cd = sample_uniform_disk_concentric(u2);
            let o = c + r * Frame::from_z(-w).from_local(Vec3::new(cd.x, cd.y, 0.0)) - r * w;
            LeSample {
                o,
                o_error: point_error(o),
                d: w,
                n: None,
                l: *l,
                factor: 1.0,
                pdf_pos: 1.0 / (PI * r * r),
                pdf_dir: uniform_sphere_pdf(),
            }
        }
        Light::Area {
            prim,
            l,
            two_sided,
            area,
            image,
            ..
        } => {
            // A point uniform by area, a cosine-weighted direction about its normal (either
            // side, by halves of u2.x, when two-sided).
            let ss = scene.shapes()[*prim as usize].sample_area(u1, scene.meshes())?;
            let (local, pdf_dir) = if *two_sided {
                let (ux, flip) = if u2.x < 0.5 {
                    (u2.x * 2.0, false)
                } else {
                    ((u2.x - 0.5) * 2.0, true)
                };
                let mut w = sample_cosine_hemisphere(Vec2::new(ux.min(ONE_MINUS_EPSILON), u2.y));
                if flip {
                    w.z = -w.z;
                }
                (w, cosine_hemisphere_pdf(w.z.abs()) / 2.0)
            } else {
                let w = sample_cosine_hemisphere(u2);
                (w, cosine_hemisphere_pdf(w.z))
            };
            if pdf_dir <= 0.0 {
                return None;
            }
            let d = Frame::from_z(ss.n).from_local(local);
            // An image emitter leaves with its mean colour (`l`): the stand-in has no (u, v)
            // of the sampled point.
            let _ = image;
            let colour: Rgb = (*l).into();
            LeSample {
                o: ss.p,
                o_error: point_error(ss.p),
                d,
                n: Some(ss.n),
                l: colour,
                factor: 1.0,
                pdf_pos: 1.0 / area,
                pdf_dir,
            }
        }
        _ => return None,
    };
    (s.pdf_pos > 0.0 && s.pdf_dir > 0.0 && s.l != Rgb::ZERO).then_some(s)
}

/// Densities (p_pos, p_dir) with which [`sample_le`] leaves light `i` from `p` (on the light,
/// with normal `n` for area lights) in unit direction `w`.
pub(crate) fn pdf_le(scene: &Scene, i: usize, n: Option<Vec3>, w: Vec3) -> (f32, f32) {
    match &scene.lights()[i] {
        Light::Point { .. } => (0.0, uniform_sphere_pdf()),
        Light::Spot {
            axis,
            cos_falloff_start,
            cos_falloff_end,
            ..
        } => {
            let (cs, ce) = (*cos_falloff_start, *cos_falloff_end);
            let total = (1.0 - cs) + (cs - ce) / 2.0;
            let cos = axis.dot(w);
            let dir = if cos >= cs {
                uniform_cone_pdf(cs) * (1.0 - cs) / total
            } else {
                smooth_step_pdf(cos, ce, cs) * ((cs - ce) / 2.0) / (total * 2.0 * PI)
            };
            (0.0, dir)
        }
        Light::Distant { .. } => {
            let (_, r) = scene_sphere(scene);
            (1.0 / (PI * r * r), 0.0)
        }
        Light::UniformInfinite { .. } => {
            let (_, r) = scene_sphere(scene);
            (1.0 / (PI * r * r), uniform_sphere_pdf())
        }
        Light::Area {
            two_sided, area, ..
        } => {
            let cos = n.map_or(0.0, |n| n.dot(w));
            let dir = if *two_sided {
                cosine_hemisphere_pdf(cos.abs()) / 2.0
            } else {
                cosine_hemisphere_pdf(cos.max(0.0))
            };
            (1.0 / area, dir)
        }
        _ => (0.0, 0.0),
    }
}

/// The largest f32 below 1.
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// Density of the smoothstep ramp between `a` and `b` as a distribution of x over [a, b]:
/// smoothstep's integral over [a, b] is (b − a)/2, so p(x) = 2·smoothstep(x)/(b − a).
fn smooth_step_pdf(x: f32, a: f32, b: f32) -> f32 {
    if x < a || x > b || b <= a {
        return 0.0;
    }
    2.0 * smooth_step(x, a, b) / (b - a)
}

/// Samples x ∈ [a, b] with [`smooth_step_pdf`]: t = (x − a)/(b − a) has density
/// 2·smoothstep(t) = 6t² − 4t³ and cdf t³(2 − t), inverted by safeguarded Newton steps.
fn sample_smooth_step(u: f32, a: f32, b: f32) -> f32 {
    let cdf = |t: f32| t * t * t * (2.0 - t);
    let (mut lo, mut hi) = (0.0f32, 1.0f32);
    let mut t = 0.5f32;
    for _ in 0..32 {
        let f = cdf(t) - u;
        if f.abs() < 1e-7 {
            break;
        }
        if f < 0.0 {
            lo = t;
        } else {
            hi = t;
        }
        let df = 2.0 * (3.0 * t * t - 2.0 * t * t * t);
        let next = t - f / df;
        t = if df > 0.0 && next > lo && next < hi {
            next
        } else {
            0.5 * (lo + hi)
        };
    }
    a + t * (b - a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_step_sampling_inverts_its_cdf() {
        // pdf integrates to 1 over [a, b].
        let (a, b) = (0.3f32, 0.8f32);
        let n = 10_000;
        let integral: f32 = (0..n)
            .map(|i| smooth_step_pdf(a + (i as f32 + 0.5) / n as f32 * (b - a), a, b))
            .sum::<f32>()
            * (b - a)
            / n as f32;
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
        // Samples of evenly spaced u follow the cdf: the share below the middle is cdf(½) = 3/16.
        let below = (0..n)
            .filter(|i| sample_smooth_step((*i as f32 + 0.5) / n as f32, a, b) < 0.55)
            .count();
        assert!((below as f32 / n as f32 - 3.0 / 16.0).abs() < 1e-3);
    }
}
