//! Light sources: where the course's "comment il est éclairé" gets its light.
//!
//! [`Light::sample_li`] answers, for a point being shaded, "from which direction does this
//! light arrive, how much, and where must a shadow ray go to check that nothing is in the way";
//! [`Light::sample_le`] starts a ray of light from a light, for methods that trace paths from
//! the lights.
//!
//! A kind of light is a file: its description (what a scene says, plain data), its rules and
//! its build ([`LightDescKind`]), and every operation of the family ([`LightKind`]). This file
//! holds the family's list (`light_family!`), which makes the [`Light`] and [`LightDesc`]
//! enums and the one `match` each operation goes through, all static. Adding a kind: its file
//! (or folder, as `sunsky/`), its `mod` and `pub use` lines, one line in the list below, and
//! its reader (`crates/lancer-scene/src/pbrt/lights.rs`).

mod area;
mod area_image;
mod bounds;
mod bvh;
mod bvh_build;
mod compact;
mod distant;
mod distribution;
mod goniometric;
mod image_infinite;
mod infinite;
mod kind;
mod point;
mod portal;
mod projection;
mod sample;
mod sampler;
mod spot;
pub mod sunsky;
#[cfg(test)]
mod testing;

pub use area::{AreaLight, AreaLightDesc, Emitter};
pub use area_image::{AreaImage, mean_texel};
pub use bounds::{DirectionCone, LightBounds, LightExtent};
pub use bvh::BvhLightSampler;
pub use compact::CompactLightBounds;
pub use distant::{DistantDesc, DistantLight};
pub use distribution::LightDistribution;
pub use goniometric::{GoniometricDesc, GoniometricLight};
pub use image_infinite::{EnvMapping, ImageInfiniteDesc, ImageInfiniteLight, environment_mapping};
pub use infinite::{UniformInfiniteDesc, UniformInfiniteLight};
pub use kind::{LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere};
pub use point::{PointDesc, PointLight};
pub use portal::{PortalInfiniteDesc, PortalInfiniteLight, portal_frame};
pub use projection::{ProjectionDesc, ProjectionLight, projected_sum};
pub use sample::{LightLiSample, LightSampleContext};
pub use sampler::{LightSampler, LightSamplerKind};
pub use spot::{SpotDesc, SpotLight};
pub use sunsky::{SunskyDesc, SunskyLight, SunskyParams};

use crate::image::Image;
use crate::math::{Rgb, SampledSpectrum, Vec2, Vec3};
use crate::shape::{Shape, TriangleMesh};
use crate::spectrum::sampled::SampledWavelengths;
use std::sync::Arc;

/// A kind stored in the family's enums as it is (the small kinds, whose records are read in
/// the hot loop); the others are boxed, so that [`Light`] stays small.
type Inline<T> = T;

/// Makes the family from its list: [`Light`] (one variant per kind of the list, and the area
/// lights, which the shapes make: [`AreaLightDesc`]) and [`LightDesc`] (one per kind of the
/// list), and the two macros their operations go through: `dispatch!` (`$body` with `$l`
/// bound to the kind inside a [`Light`], boxes opened) and `dispatch_desc!` (`$body` with
/// `$d` bound to the description inside a [`LightDesc`] and `$wrap` to its [`Light`]
/// variant). Bodies call an operation as `LightKind::op(l, …)`, which no inherent method of a
/// kind can shadow. `$d` is a `$` passed in, so that the macros made here can have variables
/// of their own.
macro_rules! light_family {
    ($d:tt $(
        $(#[$doc:meta])*
        $kind:ident($desc:ident) => $store:ident<$light:ident>;
    )*) => {
        /// A light source of the scene, one variant per kind.
        #[derive(Clone, Debug, PartialEq)]
        pub enum Light {
            /// A diffuse area light: a primitive of the scene that emits radiance L from its
            /// surface (one per emitting primitive; a mesh light is one per triangle).
            Area(AreaLight),
            $( $(#[$doc])* $kind($store<$light>), )*
        }

        /// A light source as a scene describes it: plain data, built into a [`Light`] by
        /// [`LightDesc::build`]. Area lights are not here: they belong to their shapes
        /// ([`AreaLightDesc`]).
        #[derive(Clone, Debug, PartialEq)]
        pub enum LightDesc {
            $( $(#[$doc])* $kind($desc), )*
        }

        /// `$body` with `$l` bound to the kind inside a [`Light`] (boxed kinds unboxed).
        macro_rules! dispatch {
            ($d x:expr, $d l:ident => $d body:expr) => {
                match $d x {
                    Light::Area($d l) => $d body,
                    $( Light::$kind(kind) => {
                        let $d l: &$light = kind;
                        $d body
                    } )*
                }
            };
        }

        /// `$body` with `$d` bound to the kind inside a [`LightDesc`] and `$wrap` to the
        /// [`Light`] variant of that kind.
        macro_rules! dispatch_desc {
            ($d x:expr, $d d:ident, $d wrap:ident => $d body:expr) => {
                match $d x {
                    $( LightDesc::$kind($d d) => {
                        let $d wrap = Light::$kind;
                        $d body
                    } )*
                }
            };
        }
    };
}

light_family! {$
    /// An isotropic point light: Li = I / r².
    Point(PointDesc) => Inline<PointLight>;
    /// A spot light, a point light limited to a cone with a smooth falloff:
    /// I(θ) = I · smoothstep(cos θ_total, cos θ_falloff, cos θ).
    Spot(SpotDesc) => Inline<SpotLight>;
    /// A directional light (the sun): radiance L along a single direction.
    Distant(DistantDesc) => Inline<DistantLight>;
    /// Constant radiance from infinitely far away in every direction ("sky").
    UniformInfinite(UniformInfiniteDesc) => Inline<UniformInfiniteLight>;
    /// Environment radiance from an image, importance-sampled (boxed: it holds the image's
    /// sampling tables).
    ImageInfinite(ImageInfiniteDesc) => Box<ImageInfiniteLight>;
    /// An image environment that lets light in only through a rectangular portal, sampled
    /// through it (pbrt-v4's `PortalImageInfiniteLight`).
    PortalInfinite(PortalInfiniteDesc) => Box<PortalInfiniteLight>;
    /// pbrt-v4's `goniometric`: a point light with an equal-area intensity image.
    Goniometric(GoniometricDesc) => Box<GoniometricLight>;
    /// pbrt-v4's `projection`: a point light projecting an image (a slide projector).
    Projection(ProjectionDesc) => Box<ProjectionLight>;
    /// lancer's `sunsky`: the Hosek–Wilkie sky and sun (boxed: its sampling table).
    Sunsky(SunskyDesc) => Box<SunskyLight>;
}

impl LightDesc {
    /// The pbrt-v4 name of this light (`LightSource "…"`; lancer's extensions by their own
    /// names, as `sunsky`).
    pub fn pbrt_name(&self) -> &'static str {
        dispatch_desc!(self, d, _wrap => d.pbrt_name())
    }

    /// The kind as `lancer info` counts it: the pbrt-v4 name, `infinite (image)` for an
    /// environment image.
    pub fn count_name(&self) -> &'static str {
        dispatch_desc!(self, d, _wrap => d.count_name())
    }

    /// Checks the rules without which the light means nothing, and returns the first one
    /// broken (one message per rule: each kind's [`LightDescKind::validate`]).
    pub fn validate(&self) -> Result<(), String> {
        dispatch_desc!(self, d, _wrap => d.validate())
    }

    /// The light, checked, for a scene bounded by `scene`.
    // `into` boxes the kinds whose variant is boxed, and is the identity for the others.
    #[allow(clippy::useless_conversion)]
    pub fn build(&self, scene: &SceneSphere) -> Result<Light, String> {
        dispatch_desc!(self, d, wrap => {
            d.validate()?;
            Ok(wrap(d.build(scene)?.into()))
        })
    }
}

impl Light {
    /// How the light emits (pbrt-v4's `LightType`).
    #[inline]
    pub fn light_type(&self) -> LightType {
        dispatch!(self, l => LightKind::light_type(l))
    }

    /// The area light this is, if it is one (what the integrators read of an emitter they
    /// hit: its primitive, its image).
    #[inline]
    pub fn as_area(&self) -> Option<&AreaLight> {
        match self {
            Light::Area(a) => Some(a),
            _ => None,
        }
    }

    /// True for environment lights, which rays leaving the scene see.
    #[inline]
    pub fn is_infinite(&self) -> bool {
        self.light_type() == LightType::Infinite
    }

    /// True for lights that only sampling can reach (points and directions).
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.light_type().is_delta()
    }

    /// [`LightKind::caustic_source`]: light leaving along `w` is light tracing's in `path`
    /// with `caustics`.
    #[inline]
    pub fn caustic_source(&self, w: Vec3) -> bool {
        dispatch!(self, l => LightKind::caustic_source(l, w))
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
        if let Light::Area(a) = self
            && let Some((p, n)) = a.plain_triangle()
        {
            return area::sample_triangle_li(p, n, a.l, a.two_sided, a.area, ctx, u);
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
        dispatch!(self, l => LightKind::sample_li(l, ctx, u, shapes, meshes))
    }

    /// Density with which [`Light::sample_li`] picks direction `wi` at `ctx` (0 for delta
    /// lights). For area lights, `hit` is the point where `wi` meets the light and its
    /// geometric normal.
    pub fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, hit: Option<(Vec3, Vec3)>) -> f32 {
        dispatch!(self, l => LightKind::pdf_li(l, ctx, wi, hit))
    }

    /// Total emitted power Φ (averaged over the channels), by which lights are chosen.
    pub fn power(&self) -> f32 {
        dispatch!(self, l => LightKind::power(l))
    }

    /// The bounds of this light (pbrt-v4's `Light::Bounds`); distant and infinite lights have
    /// none, and lights that emit nothing are left out.
    pub fn extent(&self, shapes: &[Shape], meshes: &[TriangleMesh]) -> LightExtent {
        dispatch!(self, l => LightKind::extent(l, shapes, meshes))
    }

    /// The constant colour this light's emission is a multiple of (intensity or radiance), or
    /// `None` when it varies over directions (an image environment). Spectral mode turns it
    /// into a spectrum once ([`crate::spectrum::sampled::RgbSpectrum`]).
    pub fn constant_colour(&self) -> Option<Rgb> {
        dispatch!(self, l => LightKind::constant_colour(l))
    }

    /// Radiance arriving along a ray that escapes the scene in direction `d` (environment
    /// lights only; `d` need not be normalised).
    pub fn le(&self, d: Vec3) -> Rgb {
        dispatch!(self, l => LightKind::le(l, d))
    }

    /// Spectral radiance arriving along `wi` (towards the light) for a light spectral by
    /// nature (the sun and sky), `None` for the others.
    #[inline]
    pub fn le_spectral(&self, wi: Vec3, lambda: &SampledWavelengths) -> Option<SampledSpectrum> {
        dispatch!(self, l => LightKind::le_spectral(l, wi, lambda))
    }

    /// A ray of light leaving this light (pbrt-v4's `Light::SampleLe`), from two 2D samples;
    /// see [`LightLeSample`] for what its densities are per, and [`LightKind::sample_le`]
    /// for what each sample chooses. `None` when the ray would carry nothing (a density or
    /// its light zero).
    pub fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        shapes: &[Shape],
        meshes: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        dispatch!(self, l => LightKind::sample_le(l, u1, u2, shapes, meshes))
            .filter(|s| s.pdf_pos > 0.0 && s.pdf_dir > 0.0 && s.l != Rgb::ZERO)
    }

    /// The densities with which [`Light::sample_le`] emits the ray leaving `p` in unit
    /// direction `w` (pbrt-v4's `Light::PDF_Le`, both forms): for an area light `p` is the
    /// point on its surface and `n` the geometric normal there; for the others `p` is any
    /// point of the ray and `n` is ignored.
    pub fn pdf_le(&self, p: Vec3, n: Vec3, w: Vec3) -> LightLePdf {
        dispatch!(self, l => LightKind::pdf_le(l, p, n, w))
    }

    /// The image this light reads (environment and projection lights), for memory
    /// accounting.
    pub fn image(&self) -> Option<&Arc<Image>> {
        dispatch!(self, l => LightKind::image(l))
    }

    /// Bytes this light holds outside its record (boxes and sampling tables, its image
    /// aside).
    pub fn heap_bytes(&self) -> usize {
        dispatch!(self, l => LightKind::heap_bytes(l))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{PackedRgb, Transform};

    #[test]
    fn descriptions_break_their_rules_with_one_message_each() {
        let spot = LightDesc::Spot(SpotDesc {
            from: Vec3::ONE,
            to: Vec3::ONE,
            intensity: Rgb::ONE,
            cone_angle: 30.0,
            cone_delta_angle: 5.0,
        });
        let rule = "spot light with \"from\" equal to \"to\"";
        assert_eq!(spot.validate(), Err(rule.into()));
        assert_eq!(spot.build(&SceneSphere::default()), Err(rule.into()));
        let sun = LightDesc::Distant(DistantDesc {
            direction: Vec3::ZERO,
            l: Rgb::ONE,
        });
        assert_eq!(
            sun.validate(),
            Err("distant light with \"from\" equal to \"to\"".into())
        );
        let env = LightDesc::ImageInfinite(ImageInfiniteDesc {
            light_to_world: Transform::IDENTITY,
            l: Rgb::ONE,
            image: Arc::new(Image {
                width: 3,
                height: 2,
                texels: vec![PackedRgb::ONE; 6],
            }),
        });
        assert_eq!(
            env.validate(),
            Err("an environment image must be square (equal-area octahedral) or twice as wide as high (latitude-longitude), not 3×2".into())
        );
        assert_eq!(env.pbrt_name(), "infinite");
        assert_eq!(env.count_name(), "infinite (image)");
    }

    #[test]
    fn a_description_builds_its_own_kind() {
        let scene = SceneSphere {
            centre: Vec3::ONE,
            radius: 2.0,
        };
        let sky = LightDesc::UniformInfinite(UniformInfiniteDesc { l: Rgb::ONE });
        let Ok(Light::UniformInfinite(l)) = sky.build(&scene) else {
            panic!("a sky")
        };
        assert_eq!(l.scene, scene);
        assert!(sky.build(&scene).unwrap().is_infinite());
        let point = LightDesc::Point(PointDesc {
            from: Vec3::X,
            intensity: Rgb::ONE,
        });
        let light = point.build(&scene).unwrap();
        assert!(light.is_delta() && !light.is_infinite());
        assert_eq!(light.light_type(), LightType::DeltaPosition);
        assert_eq!(point.count_name(), "point");
    }
}
