//! pbrt-v4's `projection` light: a point light that projects an image like a slide projector.
//!
//! In the light's frame (the CTM with y flipped, as pbrt-v4), a direction ω with ω_z above
//! 10⁻³ lands on the screen at s = (ω_x, ω_y)/(ω_z tan(fov/2)); inside the screen window
//! ([−a, a] × [−1, 1] for an image of aspect a ≥ 1, [−1, 1] × [−1/a, 1/a] otherwise) its
//! intensity is `scale` times the nearest texel, I(ω) = scale · image((s − min)/(max − min)).
//! Power: Φ = scale · A · mean over texels of (colour · cos³θ), with A = 4 tan²(fov/2)·max(a,
//! 1/a) the window's area on the plane z = 1 (each texel's solid angle is its area times
//! cos³θ).

use super::bounds::{LightBounds, LightExtent};
use super::kind::{LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere};
use super::sample::{LightLiSample, LightSampleContext};
use crate::image::Image;
use crate::math::{Rgb, Transform, Vec2, Vec3, normalize};
use crate::sampling::PiecewiseConstant2D;
use crate::shape::{Shape, TriangleMesh};
use std::sync::Arc;

/// A projection light as a scene describes it.
#[derive(Clone, Debug, PartialEq)]
pub struct ProjectionDesc {
    /// Light space → world space (the CTM).
    pub light_to_world: Transform,
    /// Multiplies the image's texels (scaled and normalised).
    pub scale: f32,
    /// Field of view of the image's shorter side, degrees.
    pub fov: f32,
    /// The slide.
    pub image: Arc<Image>,
}

impl LightDescKind for ProjectionDesc {
    type Light = ProjectionLight;

    fn pbrt_name(&self) -> &'static str {
        "projection"
    }

    /// The image and the field of view are checked as the light is made
    /// ([`ProjectionLight::new`]).
    fn validate(&self) -> Result<(), String> {
        Ok(())
    }

    fn build(&self, _: &SceneSphere) -> Result<ProjectionLight, String> {
        ProjectionLight::new(
            self.light_to_world,
            self.image.clone(),
            self.scale,
            self.fov,
        )
    }
}

/// Directions closer to the light's plane than this (ω_z) get nothing (pbrt-v4's `hither`).
const HITHER: f32 = 1e-3;

/// A slide projector.
#[derive(Clone, Debug, PartialEq)]
pub struct ProjectionLight {
    /// Position, world space.
    p: Vec3,
    /// World space → light space.
    light_from_world: Transform,
    /// Light space → world space.
    world_from_light: Transform,
    /// The slide (linear RGB, row 0 at the top).
    image: Arc<Image>,
    /// Multiplies the texels.
    scale: f32,
    /// tan(fov/2).
    tan_half: f32,
    /// Screen window: (x_min, y_min), (x_max, y_max).
    window: (Vec2, Vec2),
    /// Over the texels, in proportion to their channel average times cos³θ (the solid angle
    /// a texel covers per unit screen area): pbrt-v4's sampling of emitted directions.
    distribution: PiecewiseConstant2D,
}

impl ProjectionLight {
    /// The projector placed by `light_to_world` (the CTM, before pbrt-v4's flip of y), of
    /// field of view `fov` degrees over the image's shorter side.
    pub fn new(
        light_to_world: Transform,
        image: Arc<Image>,
        scale: f32,
        fov: f32,
    ) -> Result<ProjectionLight, String> {
        if image.texels.iter().any(|t| !t.is_finite()) {
            return Err("the projection light's image holds infinite or NaN values".into());
        }
        if !(fov > 0.0 && fov < 180.0) {
            return Err(format!(
                "the projection light's fov must be in (0, 180), not {fov}"
            ));
        }
        let world =
            light_to_world * Transform::scale(Vec3::new(1.0, -1.0, 1.0)).expect("non-zero scale");
        let aspect = image.width as f32 / image.height as f32;
        let window = if aspect > 1.0 {
            (Vec2::new(-aspect, -1.0), Vec2::new(aspect, 1.0))
        } else {
            (Vec2::new(-1.0, -1.0 / aspect), Vec2::new(1.0, 1.0 / aspect))
        };
        let tan_half = (fov.to_radians() / 2.0).tan();
        let (w, h) = (image.width as usize, image.height as usize);
        let mut weights = Vec::with_capacity(w * h);
        for y in 0..h {
            for x in 0..w {
                let t = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let cos = screen_direction(window, tan_half, t).z;
                let c = Rgb::from(image.texels[y * w + x]).max(Rgb::ZERO);
                weights.push((c.x + c.y + c.z) / 3.0 * cos * cos * cos);
            }
        }
        let distribution = PiecewiseConstant2D::new(&weights, w, h).expect("one weight per texel");
        Ok(ProjectionLight {
            p: world.point(Vec3::ZERO),
            light_from_world: world.inverse(),
            world_from_light: world,
            image,
            scale,
            tan_half,
            window,
            distribution,
        })
    }

    /// The image, for memory accounting.
    pub fn image(&self) -> &Arc<Image> {
        &self.image
    }

    /// Where light-space direction `w` lands on the screen, as t ∈ [0, 1]² across the
    /// window; `None` behind the light's plane (ω_z below [`HITHER`]) or outside the window.
    fn screen_point(&self, w: Vec3) -> Option<Vec2> {
        if w.z < HITHER {
            return None;
        }
        let s = Vec2::new(w.x, w.y) / (w.z * self.tan_half);
        let (lo, hi) = self.window;
        if s.x < lo.x || s.y < lo.y || s.x > hi.x || s.y > hi.y {
            return None;
        }
        Some((s - lo) / (hi - lo))
    }

    /// A = 4 tan²(fov/2)·max(a, 1/a): the window's area on the plane z = 1.
    fn screen_area(&self) -> f32 {
        let (lo, hi) = self.window;
        let d = (hi - lo) * self.tan_half;
        d.x * d.y
    }

    /// Intensity in light-space direction `w`.
    fn intensity(&self, w: Vec3) -> Rgb {
        let Some(uv) = self.screen_point(w) else {
            return Rgb::ZERO;
        };
        let (iw, ih) = (self.image.width, self.image.height);
        let x = ((uv.x * iw as f32) as u32).min(iw - 1);
        let y = ((uv.y * ih as f32) as u32).min(ih - 1);
        Rgb::from(self.image.texels[(y * iw + x) as usize]).max(Rgb::ZERO) * self.scale
    }

    /// The light arriving at `ctx`: I(ω) / r².
    pub fn sample_li(&self, ctx: &LightSampleContext) -> Option<LightLiSample> {
        let d = self.p - ctx.p;
        let r2 = d.length_squared();
        if r2 == 0.0 {
            return None;
        }
        let wi = d / r2.sqrt();
        let i = self.intensity(self.light_from_world.vector(-wi).normalize_or_zero());
        (i != Rgb::ZERO).then_some(LightLiSample {
            l: i / r2,
            factor: 1.0,
            wi,
            pdf: 1.0,
            p_light: self.p,
        })
    }

    /// Where the projector sits, world space.
    pub fn position(&self) -> Vec3 {
        self.p
    }

    /// Φ = scale · A · mean(colour · cos³θ) over the texels, averaged over the channels.
    pub fn power(&self) -> f32 {
        self.scale * projected_sum(&self.image, self.tan_half, |c| (c.x + c.y + c.z) / 3.0)
    }
}

/// The unit light-space direction through the point `t` ∈ [0, 1]² of the screen `window`
/// (on the plane z = 1 the screen is the window times tan(fov/2)).
fn screen_direction((lo, hi): (Vec2, Vec2), tan_half: f32, t: Vec2) -> Vec3 {
    let s = (lo + t * (hi - lo)) * tan_half;
    normalize(Vec3::new(s.x, s.y, 1.0))
}

impl LightKind for ProjectionLight {
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
        ProjectionLight::sample_li(self, ctx)
    }

    fn power(&self) -> f32 {
        ProjectionLight::power(self)
    }

    /// Bounded by its total power over the whole sphere of directions (coarser than
    /// pbrt-v4's cone, but never zero where it shines, so the choice stays unbiased).
    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        LightBounds::point(self.p, ProjectionLight::power(self)).extent()
    }

    fn constant_colour(&self) -> Option<Rgb> {
        None
    }

    /// pbrt-v4's: a point of the screen chosen by the image (density p(t) over t ∈ [0, 1]²),
    /// its direction's density per solid angle p(t) / (A · cos³θ), A the screen's area on
    /// the plane z = 1.
    fn sample_le(
        &self,
        u1: Vec2,
        _: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        let (t, pdf) = self.distribution.sample(u1);
        let wl = screen_direction(self.window, self.tan_half, t);
        let l = self.intensity(wl);
        let w = self.world_from_light.vector(wl).normalize_or_zero();
        let pdf_dir = pdf / (self.screen_area() * wl.z * wl.z * wl.z);
        let ok = l != Rgb::ZERO && w != Vec3::ZERO && pdf_dir > 0.0 && pdf_dir.is_finite();
        ok.then_some(LightLeSample {
            l,
            factor: 1.0,
            p: self.p,
            p_error: Vec3::ZERO,
            w,
            n: Vec3::ZERO,
            pdf_pos: 1.0,
            pdf_dir,
        })
    }

    fn pdf_le(&self, _: Vec3, _: Vec3, w: Vec3) -> LightLePdf {
        let wl = self.light_from_world.vector(w).normalize_or_zero();
        let dir = match self.screen_point(wl) {
            Some(t) => self.distribution.pdf(t) / (self.screen_area() * wl.z * wl.z * wl.z),
            None => 0.0,
        };
        LightLePdf { pos: 0.0, dir }
    }

    fn image(&self) -> Option<&Arc<Image>> {
        Some(&self.image)
    }

    fn heap_bytes(&self) -> usize {
        size_of_val(self) + self.distribution.memory_bytes()
    }
}

/// A · mean over the texels of `weight(colour) · cos³θ`, with θ the angle of the texel
/// centre's direction to the axis: the integral of `weight(I(ω))` over the projector's
/// directions for scale 1. pbrt-v4's `power` divides by this with the luminance as weight.
pub fn projected_sum(image: &Image, tan_half: f32, weight: impl Fn(Rgb) -> f32) -> f32 {
    let aspect = image.width as f32 / image.height as f32;
    let (lo, hi) = if aspect > 1.0 {
        (Vec2::new(-aspect, -1.0), Vec2::new(aspect, 1.0))
    } else {
        (Vec2::new(-1.0, -1.0 / aspect), Vec2::new(1.0, 1.0 / aspect))
    };
    let area = 4.0 * tan_half * tan_half * aspect.max(1.0 / aspect);
    let (w, h) = (image.width, image.height);
    let mut sum = 0.0f64;
    for y in 0..h {
        for x in 0..w {
            let t = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let s = (lo + t * (hi - lo)) * tan_half;
            let cos = 1.0 / (1.0 + s.length_squared()).sqrt();
            let c = Rgb::from(image.texels[(y * w + x) as usize]).max(Rgb::ZERO);
            sum += (weight(c) * cos * cos * cos) as f64;
        }
    }
    (area as f64 * sum / (w as f64 * h as f64)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{PI, PackedRgb};

    fn ctx(p: Vec3) -> LightSampleContext {
        LightSampleContext::in_medium(p)
    }

    #[test]
    fn a_slide_lands_upright_and_inside_its_field_of_view() {
        // 2×2 slide: top row red, bottom row blue; fov 90 (tan = 1), at the origin looking
        // down +z. On the plane z = 1 the window is [−1, 1]²; pbrt-v4 flips y, so the top
        // row lands at +y.
        let texels = vec![
            PackedRgb::new(1.0, 0.0, 0.0),
            PackedRgb::new(1.0, 0.0, 0.0),
            PackedRgb::new(0.0, 0.0, 1.0),
            PackedRgb::new(0.0, 0.0, 1.0),
        ];
        let image = Arc::new(Image::new(2, 2, texels).unwrap());
        let light = ProjectionLight::new(Transform::IDENTITY, image, 2.0, 90.0).unwrap();
        let up = light.sample_li(&ctx(Vec3::new(0.3, 0.5, 1.0))).unwrap();
        let r2 = 0.09 + 0.25 + 1.0;
        assert!(
            (up.l - Rgb::new(2.0 / r2, 0.0, 0.0)).abs().max_element() < 1e-6,
            "{}",
            up.l
        );
        let down = light.sample_li(&ctx(Vec3::new(0.3, -0.5, 1.0))).unwrap();
        assert!(down.l.z > 0.0 && down.l.x == 0.0);
        // Outside the 90° field, and behind the projector: nothing.
        assert!(light.sample_li(&ctx(Vec3::new(1.2, 0.0, 1.0))).is_none());
        assert!(light.sample_li(&ctx(Vec3::new(0.0, 0.0, -1.0))).is_none());
    }

    #[test]
    fn power_is_the_integral_of_intensity_over_the_field() {
        // A white slide of fov 90 over a square: the solid angle of a square of half-angle
        // 45° is 4 asin(1/2) = 2π/3, so Φ = scale · 2π/3.
        let n = 64;
        let image = Image::new(n, n, vec![PackedRgb::ONE; (n * n) as usize]).unwrap();
        let light = ProjectionLight::new(Transform::IDENTITY, Arc::new(image), 3.0, 90.0).unwrap();
        let want = 3.0 * 2.0 * PI / 3.0;
        assert!(
            (light.power() - want).abs() < 1e-3 * want,
            "{}",
            light.power()
        );
    }

    #[test]
    fn emitted_rays_carry_the_power() {
        use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};
        let texels = (0..48)
            .map(|i| PackedRgb::new(((i * 37) % 11) as f32 / 5.0, 0.5, (i % 3) as f32))
            .collect();
        let image = Arc::new(Image::new(8, 6, texels).unwrap());
        let at = Transform::translate(Vec3::new(1.0, 2.0, 3.0))
            * Transform::rotate(40.0, Vec3::new(1.0, 1.0, 0.0)).unwrap();
        let light = ProjectionLight::new(at, image, 1.5, 70.0).unwrap();
        let phi = le_power(&light, &[], &[], 1 << 14);
        let want = ProjectionLight::power(&light);
        assert!((phi - want).abs() < 0.01 * want, "{phi} vs {want}");
        le_pdfs_agree(&light, &[], &[], 256, 1e-3);
        let total = le_dir_integral(&light, light.p, Vec3::ZERO, 1 << 18);
        assert!((total - 1.0).abs() < 0.03, "{total}");
    }
}
