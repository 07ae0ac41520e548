//! Light sources: where the course's "comment il est éclairé" gets its light.
//!
//! [`Light::sample_li`] answers, for a point being shaded, "from which direction does this
//! light arrive, how much, and where must a shadow ray go to check that nothing is in the way".

use crate::math::{Frame, INV_PI, Rgb, Vec2, Vec3, smooth_step};

/// The point being lit.
#[derive(Clone, Copy, Debug)]
pub struct LightSampleContext {
    /// Position.
    pub p: Vec3,
    /// Geometric normal (zero for points in a medium).
    pub n: Vec3,
    /// Shading normal.
    pub ns: Vec3,
}

/// Incident light from a sampled point on a light.
#[derive(Clone, Copy, Debug)]
pub struct LightLiSample {
    /// Radiance arriving (for delta lights: the intensity already divided by distance²).
    pub l: Rgb,
    /// Unit direction from the lit point towards the light.
    pub wi: Vec3,
    /// Density of the sample with respect to solid angle (1 for delta lights).
    pub pdf: f32,
    /// The point on the light the shadow ray must reach.
    pub p_light: Vec3,
}

/// A light source of the scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Light {
    /// Isotropic point light: Li = I / r².
    Point {
        /// Position.
        p: Vec3,
        /// Radiant intensity I.
        intensity: Rgb,
    },
    /// Spot light: I(θ) = I · smoothstep(cos θ_total, cos θ_falloff, cos θ).
    Spot {
        /// Position.
        p: Vec3,
        /// Frame whose z is the spot's axis.
        frame: Frame,
        /// Intensity on the axis.
        intensity: Rgb,
        /// cos of the angle where the falloff starts (full intensity inside).
        cos_falloff_start: f32,
        /// cos of the cone's total half-angle (zero outside).
        cos_falloff_end: f32,
    },
    /// Directional light: radiance L along a single direction.
    Distant {
        /// Unit direction towards the light.
        w: Vec3,
        /// Radiance.
        l: Rgb,
        /// Radius of the scene's bounding sphere: shadow rays go twice as far.
        scene_radius: f32,
    },
    /// Constant-radiance environment ("sky").
    UniformInfinite {
        /// Radiance from every direction.
        l: Rgb,
        /// Radius of the scene's bounding sphere.
        scene_radius: f32,
    },
}

impl Light {
    /// True for lights that only sampling can reach (points and directions).
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point { .. } | Light::Spot { .. } | Light::Distant { .. }
        )
    }

    /// Samples incident light at `ctx`; `None` when the light contributes nothing there.
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LightLiSample> {
        match self {
            Light::Point { p, intensity } => {
                let d = *p - ctx.p;
                let r2 = d.length_squared();
                if r2 == 0.0 {
                    return None;
                }
                Some(LightLiSample {
                    l: *intensity / r2,
                    wi: d / r2.sqrt(),
                    pdf: 1.0,
                    p_light: *p,
                })
            }
            Light::Spot {
                p,
                frame,
                intensity,
                cos_falloff_start,
                cos_falloff_end,
            } => {
                let d = *p - ctx.p;
                let r2 = d.length_squared();
                if r2 == 0.0 {
                    return None;
                }
                let wi = d / r2.sqrt();
                let cos_theta = frame.z.dot(-wi);
                let falloff = smooth_step(cos_theta, *cos_falloff_end, *cos_falloff_start);
                if falloff == 0.0 {
                    return None;
                }
                Some(LightLiSample {
                    l: *intensity * falloff / r2,
                    wi,
                    pdf: 1.0,
                    p_light: *p,
                })
            }
            Light::Distant { w, l, scene_radius } => Some(LightLiSample {
                l: *l,
                wi: *w,
                pdf: 1.0,
                p_light: ctx.p + *w * (2.0 * scene_radius.max(1e-3)),
            }),
            Light::UniformInfinite { l, scene_radius } => {
                // Cosine-weighted about the shading normal when there is one.
                let (wi, pdf) = if ctx.ns != Vec3::ZERO {
                    let local = crate::sampling::sample_cosine_hemisphere(u);
                    (Frame::from_z(ctx.ns).from_local(local), local.z * INV_PI)
                } else {
                    (
                        crate::sampling::sample_uniform_sphere(u),
                        crate::sampling::uniform_sphere_pdf(),
                    )
                };
                (pdf > 0.0).then_some(LightLiSample {
                    l: *l,
                    wi,
                    pdf,
                    p_light: ctx.p + wi * (2.0 * scene_radius.max(1e-3)),
                })
            }
        }
    }

    /// Density with which [`Light::sample_li`] picks direction `wi` at `ctx` (0 for delta
    /// lights).
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3) -> f32 {
        match self {
            Light::UniformInfinite { .. } => {
                if ctx.ns != Vec3::ZERO {
                    wi.dot(ctx.ns).max(0.0) * INV_PI
                } else {
                    crate::sampling::uniform_sphere_pdf()
                }
            }
            _ => 0.0,
        }
    }

    /// Radiance arriving along a ray that escapes the scene in direction `d` (environment
    /// lights only).
    pub fn le(&self, _d: Vec3) -> Rgb {
        match self {
            Light::UniformInfinite { l, .. } => *l,
            _ => Rgb::ZERO,
        }
    }
}
