//! What a light sample is: the point being lit and the light arriving there (a leaf module,
//! shared by every kind of light).

use crate::math::{Rgb, Vec3};

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

impl LightSampleContext {
    /// The surface point of `si`: its position, geometric and shading normals.
    #[inline]
    pub fn at(si: &crate::shape::SurfaceInteraction) -> Self {
        LightSampleContext {
            p: si.p,
            n: si.n,
            ns: si.shading.n,
        }
    }

    /// A point `p` in a medium (or anywhere, for a light that ignores the receiver): no
    /// normals.
    #[inline]
    pub fn in_medium(p: Vec3) -> Self {
        LightSampleContext {
            p,
            n: Vec3::ZERO,
            ns: Vec3::ZERO,
        }
    }
}

/// Incident light from a sampled point on a light.
#[derive(Clone, Copy, Debug)]
pub struct LightLiSample {
    /// Radiance arriving (for delta lights: the intensity already divided by distance²).
    pub l: Rgb,
    /// `l` divided by the light's constant colour ([`super::Light::constant_colour`]): 1/r²
    /// for a point light, falloff/r² for a spot, 1 for the others. Spectral mode multiplies
    /// the colour's prepared spectrum by it instead of uplifting `l` at each sample.
    pub factor: f32,
    /// Unit direction from the lit point towards the light.
    pub wi: Vec3,
    /// Density of the sample with respect to solid angle (1 for delta lights).
    pub pdf: f32,
    /// The point on the light the shadow ray must reach.
    pub p_light: Vec3,
}
