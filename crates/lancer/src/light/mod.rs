//! Light sources: where the course's "comment il est éclairé" gets its light.
//!
//! [`Light::sample_li`] answers, for a point being shaded, "from which direction does this
//! light arrive, how much, and where must a shadow ray go to check that nothing is in the way".

mod area;
mod area_image;
mod bounds;
mod bvh;
mod bvh_build;
mod compact;
mod distribution;
mod extent;
mod goniometric;
mod image_infinite;
mod portal;
mod projection;
mod sample;
mod sampler;
pub mod sunsky;

pub use area::Emitter;
pub use area_image::{AreaImage, mean_texel};
pub use bounds::{DirectionCone, LightBounds, LightExtent};
pub use bvh::BvhLightSampler;
pub use compact::CompactLightBounds;
pub use distribution::LightDistribution;
pub use goniometric::GoniometricLight;
pub use image_infinite::{EnvMapping, ImageInfiniteLight, environment_mapping};
pub use portal::{PortalInfiniteLight, portal_frame};
pub use projection::{ProjectionLight, projected_sum};
pub use sample::{LightLiSample, LightSampleContext};
pub use sampler::{LightSampler, LightSamplerKind};
pub use sunsky::{SunskyLight, SunskyParams};

use crate::math::{Frame, INV_PI, PackedRgb, Rgb, Vec2, Vec3, smooth_step};
use crate::shape::{Shape, TriangleMesh};

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
        /// Unit axis: the direction of full intensity.
        axis: Vec3,
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
    /// A diffuse area light: a primitive of the scene that emits radiance L from its surface.
    /// There is one per emitting primitive, so its vectors are packed.
    Area {
        /// Index of the primitive in the scene's shapes.
        prim: u32,
        /// Emitted radiance.
        l: PackedRgb,
        /// Emits from both sides (otherwise only from the side its normal faces).
        two_sided: bool,
        /// Surface area, world space.
        area: f32,
        /// Its surface, prepared for sampling (a whole sphere is sampled by the cone of
        /// directions it subtends rather than by area).
        emitter: Emitter,
        /// The image the radiance comes from (pbrt-v4's `filename`; `l` is then its mean
        /// times its scale).
        image: Option<Box<AreaImage>>,
    },
    /// Constant-radiance environment ("sky").
    UniformInfinite {
        /// Radiance from every direction.
        l: Rgb,
        /// Radius of the scene's bounding sphere.
        scene_radius: f32,
    },
    /// Environment radiance from an image, importance-sampled (boxed: it holds the image's
    /// sampling tables, much larger than the other variants).
    ImageInfinite(Box<ImageInfiniteLight>),
    /// An image environment that lets light in only through a rectangular portal, sampled
    /// through it (pbrt-v4's `PortalImageInfiniteLight`).
    PortalInfinite(Box<PortalInfiniteLight>),
    /// pbrt-v4's `goniometric`: a point light with an equal-area intensity image.
    Goniometric(Box<GoniometricLight>),
    /// pbrt-v4's `projection`: a point light projecting an image.
    Projection(Box<ProjectionLight>),
    /// lancer's `sunsky`: the Hosek–Wilkie sky and sun (boxed: its sampling table).
    Sunsky(Box<SunskyLight>),
}

impl Light {
    /// True for environment lights, which rays leaving the scene see.
    pub fn is_infinite(&self) -> bool {
        matches!(
            self,
            Light::UniformInfinite { .. }
                | Light::ImageInfinite(_)
                | Light::PortalInfinite(_)
                | Light::Sunsky(_)
        )
    }

    /// True for lights that only sampling can reach (points and directions).
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point { .. }
                | Light::Spot { .. }
                | Light::Distant { .. }
                | Light::Goniometric(_)
                | Light::Projection(_)
        )
    }

    /// Samples incident light at `ctx`; `None` when the light contributes nothing there.
    /// `shapes` and `meshes` are the scene's, where area lights find their surface.
    ///
    /// Triangles of emitting meshes, the commonest lights, are sampled in the caller's code;
    /// the other lights through a call.
    #[inline(always)]
    pub fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        shapes: &[Shape],
        meshes: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        if let Light::Area {
            l,
            two_sided,
            area,
            emitter: Emitter::Triangle { p, n },
            image: None,
            ..
        } = self
        {
            return area::sample_triangle_li(p, n, *l, *two_sided, *area, ctx, u);
        }
        self.sample_li_other(ctx, u, shapes, meshes)
    }

    /// [`Light::sample_li`] for every light but a triangle.
    #[inline(never)]
    fn sample_li_other(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        shapes: &[Shape],
        meshes: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        match self {
            Light::Area {
                prim,
                l,
                two_sided,
                area,
                emitter,
                image,
            } => {
                let mut s = area::sample_area_li(
                    *prim, *l, *two_sided, *area, emitter, ctx, u, shapes, meshes,
                )?;
                if image.is_some() {
                    s.l = area_image::sampled_radiance(
                        image, *l, shapes, *prim, meshes, ctx.p, s.p_light,
                    );
                }
                Some(s)
            }
            Light::Point { p, intensity } => {
                let d = *p - ctx.p;
                let r2 = d.length_squared();
                if r2 == 0.0 {
                    return None;
                }
                Some(LightLiSample {
                    l: *intensity / r2,
                    factor: 1.0 / r2,
                    wi: d / r2.sqrt(),
                    pdf: 1.0,
                    p_light: *p,
                })
            }
            Light::Spot {
                p,
                axis,
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
                let cos_theta = axis.dot(-wi);
                let falloff = smooth_step(cos_theta, *cos_falloff_end, *cos_falloff_start);
                if falloff == 0.0 {
                    return None;
                }
                Some(LightLiSample {
                    l: *intensity * falloff / r2,
                    factor: falloff / r2,
                    wi,
                    pdf: 1.0,
                    p_light: *p,
                })
            }
            Light::Distant { w, l, scene_radius } => Some(LightLiSample {
                l: *l,
                factor: 1.0,
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
                    factor: 1.0,
                    wi,
                    pdf,
                    p_light: ctx.p + wi * (2.0 * scene_radius.max(1e-3)),
                })
            }
            Light::ImageInfinite(light) => light.sample_li(ctx, u),
            Light::PortalInfinite(light) => light.sample_li(ctx, u),
            Light::Sunsky(light) => light.sample_li(ctx, u),
            Light::Goniometric(light) => light.sample_li(ctx),
            Light::Projection(light) => light.sample_li(ctx),
        }
    }

    /// Density with which [`Light::sample_li`] picks direction `wi` at `ctx` (0 for delta
    /// lights). For area lights, `hit` is the point where `wi` meets the light and its
    /// geometric normal.
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, hit: Option<(Vec3, Vec3)>) -> f32 {
        match self {
            Light::Area { area, emitter, .. } => area::area_pdf_li(*area, emitter, ctx, wi, hit),
            Light::UniformInfinite { .. } => {
                if ctx.ns != Vec3::ZERO {
                    wi.dot(ctx.ns).max(0.0) * INV_PI
                } else {
                    crate::sampling::uniform_sphere_pdf()
                }
            }
            Light::ImageInfinite(light) => light.pdf_li(wi),
            Light::PortalInfinite(light) => light.pdf_li(ctx.p, wi),
            Light::Sunsky(light) => light.pdf_li(wi),
            _ => 0.0,
        }
    }

    /// Total emitted power Φ (averaged over the channels), by which lights are chosen.
    pub fn power(&self) -> f32 {
        use std::f32::consts::PI;
        let avg = |c: Rgb| (c.x + c.y + c.z) / 3.0;
        match self {
            // Φ = 4π·I.
            Light::Point { intensity, .. } => 4.0 * PI * avg(*intensity),
            // Φ = 2π·I·(1 − (cos θ_start + cos θ_end)/2): full inside, half over the falloff.
            Light::Spot {
                intensity,
                cos_falloff_start,
                cos_falloff_end,
                ..
            } => 2.0 * PI * avg(*intensity) * (1.0 - 0.5 * (cos_falloff_start + cos_falloff_end)),
            // Φ = π·r²·L through the scene's bounding disk.
            Light::Distant {
                l, scene_radius, ..
            } => PI * scene_radius * scene_radius * avg(*l),
            // Φ = π·A·L per emitting side.
            Light::Area {
                l, two_sided, area, ..
            } => PI * area * avg((*l).into()) * if *two_sided { 2.0 } else { 1.0 },
            // Φ = 4π²·r²·L.
            Light::UniformInfinite { l, scene_radius } => {
                4.0 * PI * PI * scene_radius * scene_radius * avg(*l)
            }
            // Φ = π·r²·∫L dω.
            Light::ImageInfinite(light) => light.power(),
            Light::PortalInfinite(light) => light.power(),
            Light::Sunsky(light) => light.power(),
            Light::Goniometric(light) => light.power(),
            Light::Projection(light) => light.power(),
        }
    }

    /// The constant colour this light's emission is a multiple of (intensity or radiance), or
    /// `None` when it varies over directions (an image environment). Spectral mode turns it
    /// into a spectrum once ([`crate::spectrum::sampled::RgbSpectrum`]).
    pub fn constant_colour(&self) -> Option<Rgb> {
        match self {
            Light::Point { intensity, .. } | Light::Spot { intensity, .. } => Some(*intensity),
            Light::Distant { l, .. } | Light::UniformInfinite { l, .. } => Some(*l),
            Light::Area { l, image: None, .. } => Some((*l).into()),
            Light::Area { .. } => None,
            Light::Goniometric(light) => Some(light.intensity()),
            Light::ImageInfinite(_)
            | Light::PortalInfinite(_)
            | Light::Projection(_)
            | Light::Sunsky(_) => None,
        }
    }

    /// Radiance arriving along a ray that escapes the scene in direction `d` (environment
    /// lights only; `d` need not be normalised).
    pub fn le(&self, d: Vec3) -> Rgb {
        match self {
            Light::UniformInfinite { l, .. } => *l,
            Light::ImageInfinite(light) => light.le(d),
            Light::PortalInfinite(light) => light.le(d),
            Light::Sunsky(light) => light.le(d),
            _ => Rgb::ZERO,
        }
    }
}
