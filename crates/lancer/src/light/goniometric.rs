//! pbrt-v4's `goniometric` light: a point light whose intensity varies with direction as an
//! equal-area octahedral image says (a photometric web, as measured for real luminaires).
//!
//! I(ω) = I · Y(ω), with Y the image's channel average at the nearest texel of
//! (u, v) = EqualAreaSphereToSquare(ω_light). The light's frame is the CTM with y and z swapped
//! (pbrt-v4's `swapYZ`), so that the image's pole is the light's +y axis. Emitted power:
//! Φ = I · 4π · mean(Y).

use super::bounds::{LightBounds, LightExtent};
use super::kind::{LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere};
use super::sample::{LightLiSample, LightSampleContext};
use crate::image::Image;
use crate::math::{PI, Rgb, Transform, Vec2, Vec3};
use crate::sampling::{
    PiecewiseConstant2D, equal_area_sphere_to_square, equal_area_square_to_sphere,
};
use crate::shape::{Shape, TriangleMesh};
use std::sync::Arc;

/// A goniometric light as a scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct GoniometricDesc {
    /// Light space → world space (the CTM).
    pub light_to_world: Transform,
    /// Intensity colour (scaled and normalised).
    pub intensity: Rgb,
    /// Square equal-area image; its channel average modulates the intensity.
    pub image: Arc<Image>,
}

impl LightDescKind for GoniometricDesc {
    type Light = GoniometricLight;

    fn pbrt_name(&self) -> &'static str {
        "goniometric"
    }

    /// The image is checked as the light is made ([`GoniometricLight::new`]).
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    fn build(&self, _: &SceneSphere) -> Result<GoniometricLight, String> {
        GoniometricLight::new(self.light_to_world, self.intensity, &self.image)
    }
}

/// A point light with an equal-area intensity image.
#[derive(Clone, Debug, PartialEq)]
pub struct GoniometricLight {
    /// Position, world space.
    p: Vec3,
    /// World space → light space (the image's frame).
    light_from_world: Transform,
    /// Light space → world space.
    world_from_light: Transform,
    /// Intensity colour (times `scale`).
    intensity: Rgb,
    /// Channel averages of the image, row-major, square.
    y: Vec<f32>,
    /// The image's side in texels.
    side: usize,
    /// Over the texels, in proportion to Y (pbrt-v4's sampling of emitted directions).
    distribution: PiecewiseConstant2D,
}

impl GoniometricLight {
    /// The light placed by `light_to_world` (the CTM, before pbrt-v4's swap of y and z), of
    /// intensity `intensity` times the square `image`'s channel average.
    pub fn new(
        light_to_world: Transform,
        intensity: Rgb,
        image: &Image,
    ) -> Result<GoniometricLight, String> {
        if image.width != image.height {
            return Err(format!(
                "a goniometric light's image must be square (equal-area), not {}×{}",
                image.width, image.height
            ));
        }
        if image.texels.iter().any(|t| !t.is_finite()) {
            return Err("the goniometric image holds infinite or NaN values".into());
        }
        let swap_yz = Transform::from_matrix(crate::math::Mat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]))
        .expect("a permutation is invertible");
        let world = light_to_world * swap_yz;
        let y: Vec<f32> = image
            .texels
            .iter()
            .map(|&t| {
                let c = Rgb::from(t);
                (c.x + c.y + c.z) / 3.0
            })
            .collect();
        let side = image.width as usize;
        let weights: Vec<f32> = y.iter().map(|v: &f32| v.max(0.0)).collect();
        let distribution =
            PiecewiseConstant2D::new(&weights, side, side).expect("one weight per texel");
        Ok(GoniometricLight {
            p: world.point(Vec3::ZERO),
            light_from_world: world.inverse(),
            world_from_light: world,
            intensity,
            y,
            side,
            distribution,
        })
    }

    /// The intensity colour the image's values multiply.
    pub fn intensity(&self) -> Rgb {
        self.intensity
    }

    /// The image's value in light-space direction `w` (unit), nearest texel.
    fn image_y(&self, w: Vec3) -> f32 {
        let uv: Vec2 = equal_area_sphere_to_square(w);
        let n = self.side;
        let x = ((uv.x * n as f32) as usize).min(n - 1);
        let y = ((uv.y * n as f32) as usize).min(n - 1);
        self.y[y * n + x]
    }

    /// The light arriving at `ctx`: I(ω) / r² from the light's position.
    pub fn sample_li(&self, ctx: &LightSampleContext) -> Option<LightLiSample> {
        let d = self.p - ctx.p;
        let r2 = d.length_squared();
        if r2 == 0.0 {
            return None;
        }
        let wi = d / r2.sqrt();
        let w = self.light_from_world.vector(-wi).normalize_or_zero();
        let factor = self.image_y(w) / r2;
        (factor > 0.0).then_some(LightLiSample {
            l: self.intensity * factor,
            factor,
            wi,
            pdf: 1.0,
            p_light: self.p,
        })
    }

    /// Where the goniometric light sits, world space.
    pub fn position(&self) -> Vec3 {
        self.p
    }

    /// Φ = I · 4π · mean(Y), averaged over the channels.
    pub fn power(&self) -> f32 {
        let mean = self.y.iter().map(|&v| v as f64).sum::<f64>() / self.y.len() as f64;
        let i = (self.intensity.x + self.intensity.y + self.intensity.z) / 3.0;
        4.0 * PI * i * mean as f32
    }
}

impl LightKind for GoniometricLight {
    fn light_type(&self) -> LightType {
        LightType::DeltaPosition
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        _: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        GoniometricLight::sample_li(self, ctx)
    }

    fn power(&self) -> f32 {
        GoniometricLight::power(self)
    }

    /// Bounded by its total power over the whole sphere of directions (coarser than
    /// pbrt-v4's per-light cones, but never zero where it shines, so the choice stays
    /// unbiased).
    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        LightBounds::point(self.p, GoniometricLight::power(self)).extent()
    }

    fn constant_colour(&self) -> Option<Rgb> {
        Some(self.intensity)
    }

    /// pbrt-v4's: a direction chosen by the image from `u1` (p_dir = p(u, v)/4π, the
    /// equal-area map's Jacobian being 4π).
    fn sample_le(
        &self,
        u1: Vec2,
        _: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        let (uv, pdf) = self.distribution.sample(u1);
        let wl = equal_area_square_to_sphere(uv);
        let factor = self.image_y(wl);
        let w = self.world_from_light.vector(wl).normalize_or_zero();
        (factor > 0.0 && pdf > 0.0 && w != Vec3::ZERO).then(|| LightLeSample {
            l: self.intensity * factor,
            factor,
            p: self.p,
            p_error: Vec3::ZERO,
            w,
            n: Vec3::ZERO,
            pdf_pos: 1.0,
            pdf_dir: pdf / (4.0 * PI),
        })
    }

    fn pdf_le(&self, _: Vec3, _: Vec3, w: Vec3) -> LightLePdf {
        let wl = self.light_from_world.vector(w).normalize_or_zero();
        let dir = if wl == Vec3::ZERO {
            0.0
        } else {
            self.distribution.pdf(equal_area_sphere_to_square(wl)) / (4.0 * PI)
        };
        LightLePdf { pos: 0.0, dir }
    }

    fn heap_bytes(&self) -> usize {
        size_of_val(self) + self.y.capacity() * size_of::<f32>() + self.distribution.memory_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::PackedRgb;
    use crate::sampling::equal_area_square_to_sphere;

    fn ctx(p: Vec3) -> LightSampleContext {
        LightSampleContext::in_medium(p)
    }

    #[test]
    fn intensity_follows_the_image_about_the_lights_y_axis() {
        // 4×4 image: the texel at (2, 1) is 3, the rest 1. Its centre direction in the
        // image's frame, with y and z swapped, is where the light is brightest.
        let mut texels = vec![PackedRgb::ONE; 16];
        texels[4 + 2] = PackedRgb::splat(3.0);
        let image = Image::new(4, 4, texels).unwrap();
        let at = Transform::translate(Vec3::new(1.0, 2.0, 3.0));
        let light = GoniometricLight::new(at, Rgb::new(1.0, 2.0, 4.0), &image).unwrap();
        let w = equal_area_square_to_sphere(Vec2::new(2.5 / 4.0, 1.5 / 4.0));
        // Light space (x, y, z) is world (x, z, y) here.
        let world_dir = Vec3::new(w.x, w.z, w.y);
        let p = Vec3::new(1.0, 2.0, 3.0) + 2.0 * world_dir;
        let s = light.sample_li(&ctx(p)).unwrap();
        // I = (1, 2, 4) · 3 at distance 2: / 4.
        assert!(
            (s.l - Rgb::new(0.75, 1.5, 3.0)).abs().max_element() < 1e-5,
            "{}",
            s.l
        );
        assert!((s.wi + world_dir).length() < 1e-5);
        assert_eq!((s.pdf, s.factor), (1.0, 0.75));
        // Elsewhere the image is 1: plain inverse square law.
        let q = Vec3::new(1.0, 2.0, 3.0) + 2.0 * Vec3::new(0.0, -1.0, 0.0);
        let s = light.sample_li(&ctx(q)).unwrap();
        assert!((s.l - Rgb::new(0.25, 0.5, 1.0)).abs().max_element() < 1e-5);
        // Φ = 4π · mean(Y) · I: mean(Y) = 18/16.
        let want = 4.0 * PI * (18.0 / 16.0) * (7.0 / 3.0);
        assert!((light.power() - want).abs() < 1e-4 * want);
        assert!(
            GoniometricLight::new(
                at,
                Rgb::ONE,
                &Image::new(2, 1, vec![PackedRgb::ONE; 2]).unwrap()
            )
            .is_err()
        );
    }

    #[test]
    fn emitted_rays_carry_the_power() {
        use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};
        let texels = (0..64)
            .map(|i| PackedRgb::splat(((i * 37) % 11) as f32 / 5.0))
            .collect();
        let image = Image::new(8, 8, texels).unwrap();
        let at = Transform::translate(Vec3::new(1.0, 2.0, 3.0))
            * Transform::rotate(40.0, Vec3::new(1.0, 1.0, 0.0)).unwrap();
        let light = GoniometricLight::new(at, Rgb::new(1.0, 2.0, 4.0), &image).unwrap();
        let phi = le_power(&light, &[], &[], 1 << 14);
        let want = GoniometricLight::power(&light);
        assert!((phi - want).abs() < 0.01 * want, "{phi} vs {want}");
        le_pdfs_agree(&light, &[], &[], 256, 1e-3);
        let total = le_dir_integral(&light, light.p, Vec3::ZERO, 1 << 16);
        assert!((total - 1.0).abs() < 0.03, "{total}");
    }
}
