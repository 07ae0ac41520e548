//! A diffuse area light whose radiance comes from an image (pbrt-v4's `DiffuseAreaLight` with
//! `"string filename"`): the radiance at a point of uv (u, v) is
//! L = scale · max(0, bilerp(image, (u, 1 − v))), the image read with clamped edges, and in
//! spectral mode that RGB is an illuminant spectrum (pbrt-v4's `RGBIlluminantSpectrum`),
//! uplifted at each lookup.
//!
//! As pbrt-v4, the light's power (for choosing lights) is π·A·sides times the image's mean
//! texel times scale, and `"float power"` Φ makes scale = Φ / (π·sides·A·k) with k the
//! image's mean luminance (the reader divides by k, the build by π·sides·A per primitive).

use crate::image::WrapMode;
use crate::math::{PackedRgb, Rgb, Vec2, Vec3};
use crate::ray::Ray;
use crate::shape::{Shape, TriangleMesh};
use crate::texture::{MipMap, SpectrumTexture};
use std::sync::Arc;

/// The image of an area light and the factor its texels are multiplied by.
#[derive(Clone, Debug)]
pub struct AreaImage {
    /// The image (its level 0 is read: pbrt-v4 looks area-light images up unfiltered).
    pub mipmap: Arc<MipMap>,
    /// Multiplies every texel: the light's `scale` (and power normalisation).
    pub scale: f32,
}

impl PartialEq for AreaImage {
    /// The same image (by address) and scale.
    fn eq(&self, o: &AreaImage) -> bool {
        Arc::ptr_eq(&self.mipmap, &o.mipmap) && self.scale == o.scale
    }
}

impl AreaImage {
    /// The image of an area light whose radiance is texture `tex` times `factor` (grey),
    /// `None` when that is not an image texture (the readers make only those).
    pub fn from_texture(tex: Option<&SpectrumTexture>, factor: Rgb) -> Option<Box<AreaImage>> {
        match tex? {
            SpectrumTexture::Image(it) => Some(Box::new(AreaImage {
                mipmap: it.mipmap.clone(),
                scale: it.scale * factor.x,
            })),
            _ => None,
        }
    }

    /// Radiance at surface coordinates `uv`: scale · max(0, bilinear lookup at (u, 1 − v))
    /// with clamped edges (pbrt-v4's `DiffuseAreaLight::L`; [`crate::image::Image::lookup`]
    /// flips v itself).
    #[inline]
    pub fn le(&self, uv: Vec2) -> Rgb {
        self.mipmap
            .level(0)
            .lookup(uv, WrapMode::Clamp, false)
            .max(Rgb::ZERO)
            * self.scale
    }

    /// The image's mean texel (negatives as 0), without the scale.
    pub fn mean(&self) -> Rgb {
        mean_texel(self.mipmap.level(0))
    }

    /// Radiance at `p`, a point sampled on `shape`, seen from `from`: its uv found by tracing
    /// the segment from `from` to just past `p` against the shape (the samplers give points
    /// without uv); `mean`, the light's mean radiance (kept by the light, so that no sample
    /// sums the image), when that ray misses (a grazing segment).
    #[cold]
    #[inline(never)]
    pub fn le_towards(
        &self,
        shape: &Shape,
        meshes: &[TriangleMesh],
        from: Vec3,
        p: Vec3,
        mean: Rgb,
    ) -> Rgb {
        // t ∈ (0, 1 + 10⁻³]: p is at t = 1; the margin absorbs its rounding.
        let ray = Ray {
            t_max: 1.0 + 1e-3,
            ..Ray::new(from, p - from)
        };
        match shape.intersect(&ray) {
            Some(h) => self.le(shape.interaction(&ray, &h, meshes).uv),
            None => mean,
        }
    }
}

/// The mean of an image's texels, negatives counted as 0.
pub fn mean_texel(image: &crate::image::Image) -> Rgb {
    let sum: glam::DVec3 = image
        .texels
        .iter()
        .map(|&t| Rgb::from(t).max(Rgb::ZERO).as_dvec3())
        .sum();
    (sum / image.texels.len().max(1) as f64).as_vec3a()
}

/// What an area light's sample carries: its constant radiance `l`, or with an image the
/// radiance at the point `p` sampled on primitive `prim` of `shapes`, seen from `from` (`l`
/// is then the image's mean radiance, used where the uv cannot be found).
#[inline(always)]
pub fn sampled_radiance(
    image: &Option<Box<AreaImage>>,
    l: PackedRgb,
    shapes: &[Shape],
    prim: u32,
    meshes: &[TriangleMesh],
    from: Vec3,
    p: Vec3,
) -> Rgb {
    match image {
        None => l.into(),
        Some(img) => img.le_towards(&shapes[prim as usize], meshes, from, p, l.into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Image;

    fn two_by_one() -> AreaImage {
        // Left texel (1, 0, 0), right texel (0, 0, 3).
        let img = Image::new(
            2,
            1,
            vec![
                Rgb::new(1.0, 0.0, 0.0).into(),
                Rgb::new(0.0, 0.0, 3.0).into(),
            ],
        )
        .unwrap();
        AreaImage {
            mipmap: Arc::new(MipMap::single(Arc::new(img))),
            scale: 2.0,
        }
    }

    #[test]
    fn lookups_are_bilinear_with_clamped_edges_times_scale() {
        let a = two_by_one();
        // u = 0.25 is the left texel's centre; u = 0.5 halfway: ((1, 0, 0) + (0, 0, 3))/2.
        assert_eq!(a.le(Vec2::new(0.25, 0.5)), Rgb::new(2.0, 0.0, 0.0));
        assert_eq!(a.le(Vec2::new(0.5, 0.9)), Rgb::new(1.0, 0.0, 3.0));
        // Past the edges the edge texels stay (clamp).
        assert_eq!(a.le(Vec2::new(-3.0, 0.5)), Rgb::new(2.0, 0.0, 0.0));
        assert_eq!(a.le(Vec2::new(7.0, 0.5)), Rgb::new(0.0, 0.0, 6.0));
        assert_eq!(a.mean(), Rgb::new(0.5, 0.0, 1.5));
    }

    #[test]
    fn sampled_points_find_their_uv() {
        use crate::math::Transform;
        use crate::shape::{Disk, Placement};
        // A unit disk in z = 0: pbrt's disk has u = φ/2π, v = (1 − r)/(1 − rᵢ).
        let disk = Shape::Disk(Box::new(Disk::new(
            Placement::new(Transform::IDENTITY, false),
            0.0,
            1.0,
            0.0,
            360.0,
        )));
        let a = two_by_one();
        // The point (0, 0.5, 0): φ = 90°, u = 0.25 (left texel's centre), v = 0.5.
        let l = a.le_towards(
            &disk,
            &[],
            Vec3::new(0.0, 0.5, 2.0),
            Vec3::new(0.0, 0.5, 0.0),
            Rgb::splat(-1.0),
        );
        assert!(
            (l - Rgb::new(2.0, 0.0, 0.0)).abs().max_element() < 1e-4,
            "{l:?}"
        );
        // A segment that misses gives the mean radiance it is handed.
        let mean = a.mean() * a.scale;
        let l = a.le_towards(
            &disk,
            &[],
            Vec3::new(5.0, 0.0, 2.0),
            Vec3::new(5.0, 0.0, 0.0),
            mean,
        );
        assert_eq!(l, Rgb::new(1.0, 0.0, 3.0));
        // Through the light's sample, whose constant is that mean.
        let shapes = [disk.clone()];
        let p = Vec3::new(5.0, 0.0, 0.0);
        let l = sampled_radiance(
            &Some(Box::new(a)),
            mean.into(),
            &shapes,
            0,
            &[],
            p + Vec3::Z,
            p,
        );
        assert_eq!(l, Rgb::new(1.0, 0.0, 3.0));
        // Without an image, the constant.
        let shapes = [disk];
        let c = sampled_radiance(&None, Rgb::ONE.into(), &shapes, 0, &[], Vec3::Z, Vec3::ZERO);
        assert_eq!(c, Rgb::ONE);
    }
}
