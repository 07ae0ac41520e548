//! An environment light whose radiance comes from an image: pbrt-v4's `ImageInfiniteLight`.
//!
//! The image covers the sphere of directions in light space (z up, as pbrt-v4). pbrt-v4 reads
//! square images in its equal-area octahedral layout ([`EnvMapping::EqualArea`]); lancer also
//! accepts 2:1 latitude–longitude images ([`EnvMapping::LatLong`], pbrt-v3's layout), which
//! pbrt-v4 refuses: u = φ/2π with φ = atan2(y, x), v = θ/π with θ from +z, row 0 at the top.
//!
//! Radiance is the nearest texel times `scale` (as pbrt-v4's `ImageLe`), so it is constant over
//! each texel, exactly like the sampling density: directions are chosen by a
//! [`PiecewiseConstant2D`] over the texels weighted by their channel average (times sin θ for
//! lat-long, whose texels near the poles cover less solid angle), and
//! p(ω) = p(u, v) / |dω/d(u, v)| with |dω/d(u, v)| = 4π (equal-area) or 2π² sin θ (lat-long).

use super::bounds::LightExtent;
use super::distant::{disk_pdf, disk_point, has_disk};
use super::kind::{
    LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere, point_error,
};
use super::sample::{LightLiSample, LightSampleContext};
use crate::image::Image;
use crate::math::{PI, Rgb, Transform, Vec2, Vec3, luminance};
use crate::sampling::{
    PiecewiseConstant2D, equal_area_sphere_to_square, equal_area_square_to_sphere,
};
use crate::shape::{Shape, TriangleMesh};
use std::sync::Arc;

/// An image environment as a scene describes it (pbrt-v4's `infinite` light with
/// `filename`).
#[derive(Clone, Debug, PartialEq)]
pub struct ImageInfiniteDesc {
    /// Light space → world space.
    pub light_to_world: Transform,
    /// Multiplies the image.
    pub l: Rgb,
    /// Environment map, equal-area octahedral (square) or lat-long (2:1).
    pub image: Arc<Image>,
}

impl LightDescKind for ImageInfiniteDesc {
    type Light = ImageInfiniteLight;

    fn pbrt_name(&self) -> &'static str {
        "infinite"
    }

    fn count_name(&self) -> &'static str {
        "infinite (image)"
    }

    /// An image of a known layout with finite values ([`environment_mapping`]).
    fn validate(&self) -> Result<(), String> {
        environment_mapping(&self.image).map(|_| ())
    }

    fn build(&self, scene: &SceneSphere) -> Result<ImageInfiniteLight, String> {
        ImageInfiniteLight::new(self.light_to_world, self.image.clone(), self.l, *scene)
    }
}

/// How an environment image covers the sphere.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvMapping {
    /// pbrt-v4's equal-area octahedral square.
    EqualArea,
    /// Latitude–longitude, twice as wide as high (a lancer extension).
    LatLong,
}

impl EnvMapping {
    /// The layout an image of `width × height` texels has: square → equal-area, 2:1 → lat-long.
    pub fn of_size(width: u32, height: u32) -> Option<EnvMapping> {
        if width == height {
            Some(EnvMapping::EqualArea)
        } else if width as u64 == 2 * height as u64 {
            Some(EnvMapping::LatLong)
        } else {
            None
        }
    }

    /// Image coordinates in [0, 1]² (row 0 at v = 0) of a unit direction in light space.
    #[inline]
    pub fn dir_to_uv(self, w: Vec3) -> Vec2 {
        match self {
            EnvMapping::EqualArea => equal_area_sphere_to_square(w),
            EnvMapping::LatLong => {
                let theta = w.z.clamp(-1.0, 1.0).acos();
                let mut phi = w.y.atan2(w.x);
                if phi < 0.0 {
                    phi += 2.0 * PI;
                }
                Vec2::new(phi / (2.0 * PI), theta / PI)
            }
        }
    }

    /// The light-space direction of image coordinates `uv`, and the Jacobian |dω/d(u, v)|.
    #[inline]
    pub fn uv_to_dir(self, uv: Vec2) -> (Vec3, f32) {
        match self {
            EnvMapping::EqualArea => (equal_area_square_to_sphere(uv), 4.0 * PI),
            EnvMapping::LatLong => {
                let (phi, theta) = (2.0 * PI * uv.x, PI * uv.y);
                let (st, ct) = theta.sin_cos();
                (
                    Vec3::new(st * phi.cos(), st * phi.sin(), ct),
                    2.0 * PI * PI * st,
                )
            }
        }
    }

    /// |dω/d(u, v)| at the unit direction `w` (light space).
    #[inline]
    fn jacobian_at(self, w: Vec3) -> f32 {
        match self {
            EnvMapping::EqualArea => 4.0 * PI,
            EnvMapping::LatLong => 2.0 * PI * PI * (1.0 - w.z * w.z).max(0.0).sqrt(),
        }
    }

    /// Solid angle of texel row `y` of `height` (all texels of a row have the same):
    /// 4π/(w·h) equal-area, (2π/w)·(cos θ₀ − cos θ₁) lat-long.
    fn texel_solid_angle(self, y: u32, width: u32, height: u32) -> f32 {
        match self {
            EnvMapping::EqualArea => 4.0 * PI / (width as f32 * height as f32),
            EnvMapping::LatLong => {
                let t0 = PI * y as f32 / height as f32;
                let t1 = PI * (y + 1) as f32 / height as f32;
                2.0 * PI / width as f32 * (t0.cos() - t1.cos())
            }
        }
    }

    /// The illuminance pbrt-v4 attributes to `image` (unscaled) for its `illuminance`
    /// parameter: on an upward (+z) patch, from the texels whose centre is above the horizon,
    /// E = 2π/(w·h) · Σ Y(texel)·cos θ for equal-area images — exactly pbrt-v4's sum, which
    /// is half the true ∫ L cos θ dω (its 2π where 4π is each texel's share of the sphere).
    /// Lat-long images use the same convention, half their ∫ L cos θ dω, so that one
    /// environment gets the same scale in either layout.
    pub fn pbrt_illuminance(self, image: &Image) -> f32 {
        let (w, h) = (image.width, image.height);
        let mut sum = 0.0f64;
        for y in 0..h {
            let domega = self.texel_solid_angle(y, w, h) as f64;
            for x in 0..w {
                let uv = Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
                let (dir, _) = self.uv_to_dir(uv);
                if dir.z <= 0.0 {
                    continue;
                }
                let c = Rgb::from(image.texels[(y * w + x) as usize]);
                sum += (luminance(c) * dir.z) as f64 * domega;
            }
        }
        (0.5 * sum) as f32
    }
}

/// The layout of an environment image, or the rule it breaks: it must be square (equal-area
/// octahedral) or twice as wide as high (latitude-longitude), and hold finite values only.
/// The one place these rules are checked (scene descriptions, the build, the light).
pub fn environment_mapping(image: &Image) -> Result<EnvMapping, String> {
    let (w, h) = (image.width, image.height);
    let mapping = EnvMapping::of_size(w, h).ok_or_else(|| {
        format!(
            "an environment image must be square (equal-area octahedral) or twice as wide as high (latitude-longitude), not {w}×{h}"
        )
    })?;
    if image.texels.iter().any(|c| !c.is_finite()) {
        return Err(
            "the environment image holds infinite or NaN values and cannot be a light".into(),
        );
    }
    Ok(mapping)
}

/// An environment light of radiance `scale · image(direction)`.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageInfiniteLight {
    /// The image (linear RGB).
    image: Arc<Image>,
    /// Its layout.
    mapping: EnvMapping,
    /// Multiplies every texel.
    scale: Rgb,
    /// Light space → world space.
    light_to_world: Transform,
    /// World space → light space.
    world_to_light: Transform,
    /// Over the texels, in proportion to their channel average (× sin θ for lat-long).
    distribution: PiecewiseConstant2D,
    /// The scene's bounding sphere.
    scene: SceneSphere,
    /// ∫ L dω over the sphere, averaged over the channels (for the power).
    radiance_integral: f32,
}

impl ImageInfiniteLight {
    /// The light; an error (from [`environment_mapping`]) when the image is neither square
    /// nor 2:1, or holds values that are not finite.
    pub fn new(
        light_to_world: Transform,
        image: Arc<Image>,
        scale: Rgb,
        scene: SceneSphere,
    ) -> Result<ImageInfiniteLight, String> {
        let (w, h) = (image.width, image.height);
        let mapping = environment_mapping(&image)?;
        let mut weights = Vec::with_capacity(image.texels.len());
        let mut integral = 0.0f64;
        for y in 0..h {
            let domega = mapping.texel_solid_angle(y, w, h);
            let sin_theta = match mapping {
                EnvMapping::EqualArea => 1.0,
                EnvMapping::LatLong => (PI * (y as f32 + 0.5) / h as f32).sin(),
            };
            for x in 0..w {
                let c = Rgb::from(image.texels[(y * w + x) as usize]);
                // pbrt-v4 weighs each texel by its channel average.
                weights.push((c.x + c.y + c.z) / 3.0 * sin_theta);
                let l = (c.max(Rgb::ZERO) * scale).max(Rgb::ZERO);
                integral += ((l.x + l.y + l.z) / 3.0 * domega) as f64;
            }
        }
        let distribution = PiecewiseConstant2D::new(&weights, w as usize, h as usize)
            .expect("one weight per texel");
        Ok(ImageInfiniteLight {
            image,
            mapping,
            scale,
            world_to_light: light_to_world.inverse(),
            light_to_world,
            distribution,
            scene,
            radiance_integral: integral as f32,
        })
    }

    /// The environment image.
    pub fn image(&self) -> &Arc<Image> {
        &self.image
    }

    /// Bytes of the sampling tables (the image not included).
    pub fn table_bytes(&self) -> usize {
        self.distribution.memory_bytes()
    }

    /// The image's layout.
    pub fn mapping(&self) -> EnvMapping {
        self.mapping
    }

    /// Radiance of the texel holding `uv` (nearest, as pbrt-v4), clamped at 0, times scale.
    #[inline]
    fn image_le(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.image.width, self.image.height);
        let x = ((uv.x * w as f32) as u32).min(w - 1);
        let y = ((uv.y * h as f32) as u32).min(h - 1);
        Rgb::from(self.image.texels[(y * w + x) as usize]).max(Rgb::ZERO) * self.scale
    }

    /// The unit light-space direction of a world direction (zero if `d` is).
    #[inline]
    fn to_light(&self, d: Vec3) -> Vec3 {
        self.world_to_light.vector(d).normalize_or_zero()
    }

    /// Radiance arriving along a ray leaving the scene in world direction `d`.
    #[inline]
    pub fn le(&self, d: Vec3) -> Rgb {
        let w = self.to_light(d);
        if w == Vec3::ZERO {
            return Rgb::ZERO;
        }
        self.image_le(self.mapping.dir_to_uv(w))
    }

    /// A direction chosen by the image's brightness, with its density per solid angle.
    #[inline]
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LightLiSample> {
        let (uv, map_pdf) = self.distribution.sample(u);
        if map_pdf == 0.0 {
            return None;
        }
        let (wl, jacobian) = self.mapping.uv_to_dir(uv);
        if jacobian <= 0.0 {
            return None;
        }
        let wi = self.light_to_world.vector(wl).normalize_or_zero();
        if wi == Vec3::ZERO {
            return None;
        }
        let pdf = map_pdf / jacobian;
        pdf.is_finite().then(|| LightLiSample {
            factor: 1.0,
            l: self.image_le(uv),
            wi,
            pdf,
            p_light: ctx.p + wi * (2.0 * self.scene.radius.max(1e-3)),
        })
    }

    /// Density with which [`ImageInfiniteLight::sample_li`] picks world direction `wi`.
    #[inline]
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        self.pdf_towards(wi)
    }

    /// Φ = π r² ∫ L dω (pbrt-v4: 4π²r²·scale·mean(L) for an equal-area image), averaged over
    /// the channels.
    pub fn power(&self) -> f32 {
        PI * self.scene.radius * self.scene.radius * self.radiance_integral
    }

    /// Density per solid angle with which the image's distribution picks the world direction
    /// `d` (towards the light).
    fn pdf_towards(&self, d: Vec3) -> f32 {
        let w = self.to_light(d);
        let jacobian = self.mapping.jacobian_at(w);
        if w == Vec3::ZERO || jacobian <= 0.0 {
            return 0.0;
        }
        self.distribution.pdf(self.mapping.dir_to_uv(w)) / jacobian
    }
}

impl LightKind for ImageInfiniteLight {
    fn light_type(&self) -> LightType {
        LightType::Infinite
    }

    #[inline]
    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        ImageInfiniteLight::sample_li(self, ctx, u)
    }

    fn pdf_li(&self, _: &LightSampleContext, wi: Vec3, _: Option<(Vec3, Vec3)>) -> f32 {
        ImageInfiniteLight::pdf_li(self, wi)
    }

    fn power(&self) -> f32 {
        ImageInfiniteLight::power(self)
    }

    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        LightExtent::Unbounded
    }

    fn constant_colour(&self) -> Option<Rgb> {
        None
    }

    fn le(&self, d: Vec3) -> Rgb {
        ImageInfiniteLight::le(self, d)
    }

    /// pbrt-v4's: the direction the light comes from chosen by the image's brightness from
    /// `u1` (p_dir = p(u, v)/|dω/d(u, v)|), the ray travelling opposite it from a point
    /// uniform on the scene's disk (p_pos = 1/(π r²)).
    fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        let (uv, map_pdf) = self.distribution.sample(u1);
        let (wl, jacobian) = self.mapping.uv_to_dir(uv);
        let from = self.light_to_world.vector(wl).normalize_or_zero();
        if map_pdf == 0.0 || jacobian <= 0.0 || from == Vec3::ZERO || !has_disk(&self.scene) {
            return None;
        }
        let pdf_dir = map_pdf / jacobian;
        let p = disk_point(&self.scene, from, u2);
        pdf_dir.is_finite().then(|| LightLeSample {
            l: self.image_le(uv),
            factor: 1.0,
            p,
            p_error: point_error(p),
            w: -from,
            n: Vec3::ZERO,
            pdf_pos: disk_pdf(&self.scene),
            pdf_dir,
        })
    }

    fn pdf_le(&self, _: Vec3, _: Vec3, w: Vec3) -> LightLePdf {
        LightLePdf {
            pos: disk_pdf(&self.scene),
            dir: self.pdf_towards(-w),
        }
    }

    fn image(&self) -> Option<&Arc<Image>> {
        Some(&self.image)
    }

    fn heap_bytes(&self) -> usize {
        size_of_val(self) + self.table_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::PackedRgb;
    use crate::sampling::{hash_u64, u32_to_unit_f32};

    fn rand2(i: u64, seed: u64) -> Vec2 {
        let h = hash_u64(&[i, seed]);
        Vec2::new(u32_to_unit_f32(h as u32), u32_to_unit_f32((h >> 32) as u32))
    }

    fn unit() -> SceneSphere {
        SceneSphere {
            centre: Vec3::ZERO,
            radius: 1.0,
        }
    }

    fn ctx() -> LightSampleContext {
        LightSampleContext {
            p: Vec3::ZERO,
            n: Vec3::Z,
            ns: Vec3::Z,
        }
    }

    fn rotated() -> Transform {
        Transform::rotate(35.0, Vec3::new(1.0, 2.0, 0.5)).unwrap()
    }

    /// Irradiance on a patch facing +z, by light sampling: E ≈ (1/n) Σ L cos θ / p.
    fn irradiance(light: &ImageInfiniteLight, n: u64) -> Rgb {
        let mut e = Rgb::ZERO;
        for i in 0..n {
            if let Some(s) = light.sample_li(&ctx(), rand2(i, 3)) {
                e += s.l * s.wi.z.max(0.0) / s.pdf;
            }
        }
        e / n as f32
    }

    #[test]
    fn a_constant_environment_gives_pi_l() {
        // Furnace: L constant ⇒ E = π·L on any patch, whatever the layout and rotation.
        let l = Rgb::new(0.5, 0.7, 0.9);
        let scale = Rgb::splat(2.0);
        for (w, h) in [(16, 16), (32, 16)] {
            let image = Arc::new(Image::new(w, h, vec![l.into(); (w * h) as usize]).unwrap());
            let light = ImageInfiniteLight::new(rotated(), image, scale, unit()).unwrap();
            let e = irradiance(&light, 100_000);
            let want = PI * l * scale;
            assert!(
                (e - want).abs().max_element() < 0.01 * want.max_element(),
                "{w}×{h}: {e} vs {want}"
            );
            // Radiance itself, seen from any direction.
            assert!(
                (light.le(Vec3::new(0.3, -0.2, 0.9)) - l * scale)
                    .abs()
                    .max_element()
                    < 1e-6
            );
            // Φ = π r² · 4π L (channel average).
            let avg = (l.x + l.y + l.z) / 3.0 * 2.0;
            assert!((light.power() - 4.0 * PI * PI * avg).abs() < 1e-3 * light.power());
            // pbrt-v4's illuminance convention: half the true π for L = 1 (up to the texel
            // centres' discretisation).
            let (w, h) = (4 * w, 4 * h);
            let one = Image::new(w, h, vec![PackedRgb::ONE; (w * h) as usize]).unwrap();
            let e_pbrt = light.mapping().pbrt_illuminance(&one);
            assert!((e_pbrt - PI / 2.0).abs() < 0.005 * PI, "{w}×{h}: {e_pbrt}");
        }
    }

    #[test]
    fn a_bright_upper_hemisphere_lights_up_and_not_down() {
        // Lat-long, top half 1 and bottom half 0: E(+z) = π exactly, and nothing from below.
        let (w, h) = (64u32, 32u32);
        let texels = (0..w * h)
            .map(|i| {
                if i / w < h / 2 {
                    PackedRgb::ONE
                } else {
                    PackedRgb::ZERO
                }
            })
            .collect();
        let image = Arc::new(Image::new(w, h, texels).unwrap());
        let light = ImageInfiniteLight::new(Transform::IDENTITY, image, Rgb::ONE, unit()).unwrap();
        let e = irradiance(&light, 100_000);
        assert!((e.x - PI).abs() < 0.01 * PI, "{e}");
        assert_eq!(light.le(Vec3::new(0.1, 0.2, 0.9)), Rgb::ONE);
        assert_eq!(light.le(Vec3::new(0.1, 0.2, -0.9)), Rgb::ZERO);
        assert_eq!(light.pdf_li(Vec3::new(0.0, 0.5, -0.5)), 0.0);
        // Turned upside down by its transform, the light comes from below.
        let flipped = ImageInfiniteLight::new(
            Transform::rotate(180.0, Vec3::X).unwrap(),
            light.image.clone(),
            Rgb::ONE,
            unit(),
        )
        .unwrap();
        assert_eq!(flipped.le(Vec3::new(0.1, 0.2, -0.9)), Rgb::ONE);
        assert_eq!(irradiance(&flipped, 1000), Rgb::ZERO);
    }

    #[test]
    fn equal_area_texels_are_where_pbrt_puts_them() {
        // A 4×4 equal-area image with one lit texel at column 2, row 1: pbrt-v4 reads texel
        // (x, y) = (⌊u·w⌋, ⌊v·h⌋) at (u, v) = EqualAreaSphereToSquare(ω), no flip.
        let mut texels = vec![PackedRgb::ZERO; 16];
        texels[4 + 2] = PackedRgb::ONE;
        let image = Arc::new(Image::new(4, 4, texels).unwrap());
        let light = ImageInfiniteLight::new(Transform::IDENTITY, image, Rgb::ONE, unit()).unwrap();
        let centre = equal_area_square_to_sphere(Vec2::new(2.5 / 4.0, 1.5 / 4.0));
        assert_eq!(light.le(centre), Rgb::ONE);
        // That texel is in the upper hemisphere, towards +x and −y.
        assert!(
            centre.z > 0.0 && centre.x > 0.0 && centre.y < 0.0,
            "{centre}"
        );
        for _ in 0..3 {
            let s = light.sample_li(&ctx(), Vec2::new(0.3, 0.6)).unwrap();
            assert_eq!(s.l, Rgb::ONE);
            // All the mass is in one of 16 texels of 4π/16 sr each.
            assert!((s.pdf - 4.0 / PI).abs() < 1e-4, "{}", s.pdf);
        }
    }

    #[test]
    fn bad_images_are_refused() {
        let image = |w: u32, h: u32, v: f32| {
            Arc::new(Image::new(w, h, vec![PackedRgb::splat(v); (w * h) as usize]).unwrap())
        };
        assert!(
            ImageInfiniteLight::new(Transform::IDENTITY, image(3, 2, 1.0), Rgb::ONE, unit())
                .is_err()
        );
        assert!(
            ImageInfiniteLight::new(Transform::IDENTITY, image(2, 2, f32::NAN), Rgb::ONE, unit())
                .unwrap_err()
                .contains("NaN")
        );
    }

    #[test]
    fn emitted_rays_carry_the_power_in_either_layout() {
        use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};
        for (w, h) in [(8, 8), (16, 8)] {
            let texels = (0..w * h)
                .map(|i| {
                    let u = ((i * 7919) % 97) as f32 / 97.0;
                    PackedRgb::new(0.2 + 3.0 * u * u, 0.5 * u, 1.0 - u)
                })
                .collect();
            let image = Arc::new(Image::new(w, h, texels).unwrap());
            let scene = SceneSphere {
                centre: Vec3::new(0.5, 0.0, -1.0),
                radius: 2.0,
            };
            let light = ImageInfiniteLight::new(rotated(), image, Rgb::splat(1.5), scene).unwrap();
            let phi = le_power(&light, &[], &[], 1 << 14);
            let want = light.power();
            assert!((phi - want).abs() < 0.01 * want, "{w}x{h}: {phi} vs {want}");
            le_pdfs_agree(&light, &[], &[], 256, 1e-3);
            let total = le_dir_integral(&light, Vec3::ZERO, Vec3::ZERO, 1 << 16);
            assert!((total - 1.0).abs() < 0.03, "{w}x{h}: {total}");
        }
    }
}
