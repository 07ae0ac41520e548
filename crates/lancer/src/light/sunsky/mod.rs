//! `LightSource "sunsky"`, a lancer extension (pbrt-v4 has none): the Hosek–Wilkie sky and sun
//! as Mitsuba 3's `sunsky` emitter computes them ([`model`]), spectral in spectral mode and
//! from the model's RGB tables in RGB mode.
//!
//! The light's space has its zenith at +z (as the environment maps of pbrt-v4's `imgtool
//! makesky`); below its horizon the light is black, and so is all of it when the sun is below
//! the horizon (as Mitsuba). The sun is a disk of half-angle 0.2679° whose radiance is uniform,
//! its irradiance over its solid angle Ω = 2π(1 − cos θ_max) with cos θ_max rounded to f32 as
//! Mitsuba's; whether a direction meets it is decided by |w × s|² ≤ sin²θ_max (in f64). The
//! cross product is what keeps the rim in place: it misjudges a few 10⁻⁶ of the disk (in f32
//! as well), where w·s ≥ cos θ_max in f32 (cos θ_max = 1 − 1.1·10⁻⁵, 180 ulps from 1) would
//! misjudge 0.3 %.
//!
//! Sampling picks the sun or the sky in proportion to their luminous power (∫ Y dω): the sun
//! uniformly over its cone, the sky from a piecewise-constant table of its luminance over
//! (φ/2π, 1 − cos θ) — cells of equal solid angle, so p(ω) = p(u, v)/2π.

pub mod model;

use super::bounds::LightExtent;
use super::distant::{disk_pdf, disk_point, has_disk};
use super::kind::{
    LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere, point_error,
};
use super::sample::{LightLiSample, LightSampleContext};
use crate::math::{PI, Rgb, SampledSpectrum, Transform, Vec2, Vec3, luminance};
use crate::sampling::PiecewiseConstant2D;
use crate::shape::{Shape, TriangleMesh};
use crate::spectrum::sampled::SampledWavelengths;
use glam::DVec3;
use model::{Basis, SPECTRAL_CHANNELS, SkyChannel};

/// Azimuth × cos θ cells of the sky's sampling table.
const TABLE_PHI: usize = 128;
const TABLE_Z: usize = 64;

/// A `sunsky` light as a scene describes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunskyDesc {
    /// Light space (zenith +z) → world space.
    pub light_to_world: Transform,
    /// The sun's direction, turbidity, albedo and scales.
    pub params: SunskyParams,
}

impl LightDescKind for SunskyDesc {
    type Light = SunskyLight;

    fn pbrt_name(&self) -> &'static str {
        "sunsky"
    }

    /// Counted with the environment lights, as `infinite`.
    fn count_name(&self) -> &'static str {
        "infinite"
    }

    /// [`SunskyParams::check`].
    fn validate(&self) -> Result<(), String> {
        self.params.check().map_or(Ok(()), Err)
    }

    fn build(&self, scene: &SceneSphere) -> Result<SunskyLight, String> {
        Ok(SunskyLight::new(self.light_to_world, &self.params, *scene))
    }
}

/// What a `sunsky` light is made of (the scene description's parameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SunskyParams {
    /// Direction towards the sun, light space (+z the zenith); need not be unit.
    pub sun_direction: Vec3,
    /// Atmospheric turbidity, in [1, 10].
    pub turbidity: f32,
    /// Ground albedo, in [0, 1].
    pub albedo: f32,
    /// Multiplies the sun.
    pub sun_scale: f32,
    /// Multiplies the sky.
    pub sky_scale: f32,
    /// Multiplies both.
    pub scale: f32,
}

impl SunskyParams {
    /// Mitsuba's defaults (turbidity 3, albedo 0.3, scales 1) with the sun towards `sun`.
    pub fn new(sun: Vec3) -> SunskyParams {
        SunskyParams {
            sun_direction: sun,
            turbidity: 3.0,
            albedo: 0.3,
            sun_scale: 1.0,
            sky_scale: 1.0,
            scale: 1.0,
        }
    }

    /// The first parameter out of its range, as a message; `None` when all are valid.
    pub fn check(&self) -> Option<String> {
        let d = self.sun_direction;
        if !d.is_finite() || d.length_squared() == 0.0 {
            return Some(format!(
                "the sun's direction must be a non-zero vector, not {d}"
            ));
        }
        if !(1.0..=10.0).contains(&self.turbidity) {
            return Some(format!("turbidity {} is outside [1, 10]", self.turbidity));
        }
        if !(0.0..=1.0).contains(&self.albedo) {
            return Some(format!("albedo {} is outside [0, 1]", self.albedo));
        }
        for (name, v) in [
            ("sunscale", self.sun_scale),
            ("skyscale", self.sky_scale),
            ("scale", self.scale),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Some(format!("{name} must be finite and not negative, not {v}"));
            }
        }
        None
    }
}

/// The sun and sky light.
#[derive(Clone, Debug, PartialEq)]
pub struct SunskyLight {
    /// Light space → world space.
    light_to_world: Transform,
    /// World space → light space.
    world_to_light: Transform,
    /// Unit direction towards the sun's centre, light space (f32 and f64).
    sun: Vec3,
    sun_d: DVec3,
    /// Two unit vectors perpendicular to the sun and each other (the cone's frame).
    sun_x: DVec3,
    sun_y: DVec3,
    /// cos θ_max of the disk (f32 as Mitsuba's), sin²θ_max, and Ω = 2π(1 − cos θ_max).
    cos_max: f64,
    sin2_max: f64,
    sun_solid_angle: f64,
    /// The sky per RGB channel and per wavelength of the model.
    sky_rgb: [SkyChannel; 3],
    sky_spectral: [SkyChannel; SPECTRAL_CHANNELS],
    /// `scale · sky_scale`.
    sky_scale: f32,
    /// The sun's radiance (irradiance / Ω, times `scale · sun_scale`), RGB and per wavelength.
    sun_rgb: Rgb,
    sun_spectral: [f32; SPECTRAL_CHANNELS],
    /// False when the sun is below the horizon: the light is black.
    lit: bool,
    /// The sky's luminance over (φ/2π, 1 − cos θ).
    sky_table: PiecewiseConstant2D,
    /// Probability of sampling the sun rather than the sky.
    p_sun: f32,
    /// ∫ L dω over sky and sun, averaged over the RGB channels (for the power).
    radiance_integral: f32,
    /// The scene's bounding sphere.
    scene: SceneSphere,
}

impl SunskyLight {
    /// The light; `params` must pass [`SunskyParams::check`].
    pub fn new(
        light_to_world: Transform,
        params: &SunskyParams,
        scene: SceneSphere,
    ) -> SunskyLight {
        let sun_d = DVec3::new(
            params.sun_direction.x as f64,
            params.sun_direction.y as f64,
            params.sun_direction.z as f64,
        )
        .normalize();
        let sun = Vec3::new(sun_d.x as f32, sun_d.y as f32, sun_d.z as f32);
        let (sun_x, sun_y) = sun_d.any_orthonormal_pair();
        // Elevation η = π/2 − θ_sun.
        let eta = std::f32::consts::FRAC_PI_2 - sun.z.clamp(-1.0, 1.0).acos();
        let lit = sun.z >= 0.0;
        let (t, a) = (params.turbidity, params.albedo);
        let sky_rgb = std::array::from_fn(|c| model::sky_channel(Basis::Rgb, c, t, a, eta));
        let sky_spectral =
            std::array::from_fn(|c| model::sky_channel(Basis::Spectral, c, t, a, eta));
        let cos_max = (model::SUN_HALF_APERTURE as f32).cos() as f64;
        let sun_solid_angle = 2.0 * std::f64::consts::PI * (1.0 - cos_max);
        let e = model::sun_irradiance(t, eta);
        let sun_k = (params.scale * params.sun_scale) as f64 / sun_solid_angle;
        let sun_rgb = model::sun_rgb(&e) * sun_k as f32;
        let sun_spectral = e.map(|e| (e as f64 * sun_k) as f32);
        let mut light = SunskyLight {
            world_to_light: light_to_world.inverse(),
            light_to_world,
            sun,
            sun_d,
            sun_x,
            sun_y,
            cos_max,
            sin2_max: (1.0 - cos_max) * (1.0 + cos_max),
            sun_solid_angle,
            sky_rgb,
            sky_spectral,
            sky_scale: params.scale * params.sky_scale,
            sun_rgb,
            sun_spectral,
            lit,
            sky_table: PiecewiseConstant2D::new(&[1.0], 1, 1).expect("one cell"),
            p_sun: 0.0,
            radiance_integral: 0.0,
            scene,
        };
        light.build_sampling();
        light
    }

    /// The sky's sampling table, the sun's share of the samples and the power: each cell of
    /// the table weighted by the sky's luminance averaged over 2×2 points in it.
    fn build_sampling(&mut self) {
        let mut weights = Vec::with_capacity(TABLE_PHI * TABLE_Z);
        let mut avg_integral = 0.0f64;
        let cell = 2.0 * std::f64::consts::PI / (TABLE_PHI * TABLE_Z) as f64;
        for iz in 0..TABLE_Z {
            for ip in 0..TABLE_PHI {
                let mut c = Rgb::ZERO;
                for (dp, dz) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
                    let uv = Vec2::new(
                        (ip as f32 + dp) / TABLE_PHI as f32,
                        (iz as f32 + dz) / TABLE_Z as f32,
                    );
                    c += self.sky_rgb_at(uv_to_dir(uv)).max(Rgb::ZERO) * 0.25;
                }
                weights.push(luminance(c));
                avg_integral += ((c.x + c.y + c.z) / 3.0) as f64 * cell;
            }
        }
        self.sky_table =
            PiecewiseConstant2D::new(&weights, TABLE_PHI, TABLE_Z).expect("one weight per cell");
        let sky_power = 2.0 * PI * self.sky_table.integral() * self.sky_scale;
        let sun_power = luminance(self.sun_rgb.max(Rgb::ZERO)) * self.sun_solid_angle as f32;
        self.p_sun = if !self.lit || sun_power + sky_power <= 0.0 {
            0.0
        } else {
            sun_power / (sun_power + sky_power)
        };
        let sun_avg = (self.sun_rgb.x + self.sun_rgb.y + self.sun_rgb.z) / 3.0;
        self.radiance_integral = if self.lit {
            avg_integral as f32 * self.sky_scale + sun_avg * self.sun_solid_angle as f32
        } else {
            0.0
        };
    }

    /// True when the light emits nothing anywhere (sun below the horizon, or scales of 0).
    pub fn is_black(&self) -> bool {
        self.radiance_integral <= 0.0
    }

    /// The unit light-space direction of a world direction (zero if `d` is).
    #[inline]
    fn to_light(&self, d: Vec3) -> Vec3 {
        self.world_to_light.vector(d).normalize_or_zero()
    }

    /// True when unit light-space direction `w` meets the sun's disk: w·s > 0 and
    /// |w × s|² ≤ sin²θ_max, in f64.
    #[inline]
    fn in_sun(&self, w: Vec3) -> bool {
        let wd = DVec3::new(w.x as f64, w.y as f64, w.z as f64);
        wd.dot(self.sun_d) > 0.0
            && wd.cross(self.sun_d).length_squared() <= self.sin2_max * wd.length_squared()
    }

    /// The angle γ between unit `w` and the sun, robust near 0 and π (Mitsuba's `unit_angle`):
    /// 2 asin(|w − s|/2), or π − 2 asin(|w + s|/2) when w·s < 0.
    #[inline]
    fn sun_angle(&self, w: Vec3) -> f32 {
        if w.dot(self.sun) < 0.0 {
            PI - 2.0 * ((w + self.sun).length() * 0.5).min(1.0).asin()
        } else {
            2.0 * ((w - self.sun).length() * 0.5).min(1.0).asin()
        }
    }

    /// The sky's RGB radiance towards unit light-space `w` (without `sky_scale`).
    fn sky_rgb_at(&self, w: Vec3) -> Rgb {
        if !self.lit || w.z < 0.0 {
            return Rgb::ZERO;
        }
        let gamma = self.sun_angle(w);
        let cos_gamma = gamma.cos();
        let [r, g, b] = &self.sky_rgb;
        Rgb::new(
            model::sky_radiance(r, w.z, gamma, cos_gamma),
            model::sky_radiance(g, w.z, gamma, cos_gamma),
            model::sky_radiance(b, w.z, gamma, cos_gamma),
        )
    }

    /// RGB radiance towards unit light-space `w`: sky and, inside its disk, sun.
    #[inline]
    fn radiance_rgb(&self, w: Vec3) -> Rgb {
        if !self.lit || w.z < 0.0 {
            return Rgb::ZERO;
        }
        let sky = self.sky_rgb_at(w) * self.sky_scale;
        if self.in_sun(w) {
            sky + self.sun_rgb
        } else {
            sky
        }
    }

    /// Radiance (RGB mode) arriving along a ray leaving the scene in world direction `d`.
    #[inline]
    pub fn le(&self, d: Vec3) -> Rgb {
        self.radiance_rgb(self.to_light(d))
    }

    /// Spectral radiance at the path's wavelengths arriving along world direction `d`: at each
    /// λ the model's two channels around it, interpolated linearly (zero outside 320–720 nm).
    pub fn le_spectral(&self, d: Vec3, lambda: &SampledWavelengths) -> SampledSpectrum {
        let w = self.to_light(d);
        if !self.lit || w.z < 0.0 {
            return SampledSpectrum::ZERO;
        }
        let gamma = self.sun_angle(w);
        let cos_gamma = gamma.cos();
        let sun = self.in_sun(w);
        let mut sky = [f32::NAN; SPECTRAL_CHANNELS];
        let mut channel = |i: usize| {
            if sky[i].is_nan() {
                sky[i] = model::sky_radiance(&self.sky_spectral[i], w.z, gamma, cos_gamma);
            }
            sky[i]
        };
        let l = lambda.lambda.to_array().map(|l| {
            let Some((i, j, t)) = model::spectral_channels(l) else {
                return 0.0;
            };
            let sky = (1.0 - t) * channel(i) + t * channel(j);
            let mut v = self.sky_scale * sky;
            if sun {
                v += (1.0 - t) * self.sun_spectral[i] + t * self.sun_spectral[j];
            }
            v
        });
        SampledSpectrum::from_array(l)
    }

    /// Density of the sky's table at unit light-space `w` per solid angle.
    #[inline]
    fn sky_pdf(&self, w: Vec3) -> f32 {
        if w.z < 0.0 {
            return 0.0;
        }
        self.sky_table.pdf(dir_to_uv(w)) / (2.0 * PI)
    }

    /// The mixture's density at unit light-space `w`.
    #[inline]
    fn pdf_light(&self, w: Vec3) -> f32 {
        if !self.lit || w.z < 0.0 {
            return 0.0;
        }
        let sun = if self.p_sun > 0.0 && self.in_sun(w) {
            self.p_sun / self.sun_solid_angle as f32
        } else {
            0.0
        };
        sun + (1.0 - self.p_sun) * self.sky_pdf(w)
    }

    /// A direction towards the sun (probability `p_sun`, uniform over its disk) or the sky (by
    /// its luminance), with the radiance from there and the mixture's density.
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LightLiSample> {
        let (wi, wl, pdf) = self.sample_direction(u)?;
        Some(LightLiSample {
            l: self.radiance_rgb(wl),
            factor: 1.0,
            wi,
            pdf,
            p_light: ctx.p + wi * (2.0 * self.scene.radius.max(1e-3)),
        })
    }

    /// A world direction towards the sun (probability `p_sun`, uniform over its disk) or the
    /// sky (by its luminance) from `u`, with its light-space twin (as `le` and `pdf_li` will
    /// see it) and the mixture's density there; `None` when the light is black or the
    /// density is not positive and finite.
    fn sample_direction(&self, u: Vec2) -> Option<(Vec3, Vec3, f32)> {
        if self.is_black() {
            return None;
        }
        let w = if u.x < self.p_sun {
            // Uniform in the cone: cos θ = 1 − u·(1 − cos θ_max), φ = 2πu'.
            let u0 = (u.x / self.p_sun).min(1.0) as f64;
            let cos_t = 1.0 - u0 * (1.0 - self.cos_max);
            let sin_t = ((1.0 - cos_t) * (1.0 + cos_t)).max(0.0).sqrt();
            let phi = 2.0 * std::f64::consts::PI * u.y as f64;
            let d = self.sun_d * cos_t + (self.sun_x * phi.cos() + self.sun_y * phi.sin()) * sin_t;
            Vec3::new(d.x as f32, d.y as f32, d.z as f32)
        } else {
            let ux = ((u.x - self.p_sun) / (1.0 - self.p_sun)).min(1.0 - f32::EPSILON / 2.0);
            let (uv, table_pdf) = self.sky_table.sample(Vec2::new(ux, u.y));
            if table_pdf == 0.0 {
                return None;
            }
            uv_to_dir(uv)
        };
        let wi = self.light_to_world.vector(w).normalize_or_zero();
        if wi == Vec3::ZERO {
            return None;
        }
        // Evaluated at the world direction as `le` and `pdf_li` will be.
        let wl = self.to_light(wi);
        let pdf = self.pdf_light(wl);
        (pdf > 0.0 && pdf.is_finite()).then_some((wi, wl, pdf))
    }

    /// Density with which [`SunskyLight::sample_li`] picks world direction `wi`.
    #[inline]
    pub fn pdf_li(&self, wi: Vec3) -> f32 {
        self.pdf_light(self.to_light(wi))
    }

    /// Φ = π r² ∫ L dω, averaged over the RGB channels.
    pub fn power(&self) -> f32 {
        PI * self.scene.radius * self.scene.radius * self.radiance_integral
    }

    /// Bytes of the sampling table.
    pub fn table_bytes(&self) -> usize {
        self.sky_table.memory_bytes()
    }
}

impl LightKind for SunskyLight {
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
        SunskyLight::sample_li(self, ctx, u)
    }

    fn pdf_li(&self, _: &LightSampleContext, wi: Vec3, _: Option<(Vec3, Vec3)>) -> f32 {
        SunskyLight::pdf_li(self, wi)
    }

    fn power(&self) -> f32 {
        SunskyLight::power(self)
    }

    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        LightExtent::Unbounded
    }

    fn constant_colour(&self) -> Option<Rgb> {
        None
    }

    fn le(&self, d: Vec3) -> Rgb {
        SunskyLight::le(self, d)
    }

    /// The sun and sky are spectral by nature: the model's spectrum along `wi`.
    fn le_spectral(&self, wi: Vec3, lambda: &SampledWavelengths) -> Option<SampledSpectrum> {
        Some(SunskyLight::le_spectral(self, wi, lambda))
    }

    /// As the image environment's: the direction the light comes from chosen from `u1` as
    /// [`SunskyLight::sample_li`] chooses it (p_dir its density), the ray travelling opposite
    /// it from a point uniform on the scene's disk (p_pos = 1/(π r²)).
    fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        if !has_disk(&self.scene) {
            return None;
        }
        let (from, wl, pdf_dir) = self.sample_direction(u1)?;
        let p = disk_point(&self.scene, from, u2);
        Some(LightLeSample {
            l: self.radiance_rgb(wl),
            factor: 1.0,
            p,
            p_error: point_error(p),
            w: -from,
            n: Vec3::ZERO,
            pdf_pos: disk_pdf(&self.scene),
            pdf_dir,
        })
    }

    /// The sun's disk: light travelling along `w` came from it.
    fn caustic_source(&self, w: Vec3) -> bool {
        self.p_sun > 0.0 && self.in_sun(self.to_light(-w))
    }

    fn pdf_le(&self, _: Vec3, _: Vec3, w: Vec3) -> LightLePdf {
        LightLePdf {
            pos: disk_pdf(&self.scene),
            dir: SunskyLight::pdf_li(self, -w),
        }
    }

    fn heap_bytes(&self) -> usize {
        size_of_val(self) + self.table_bytes()
    }
}

/// The upper-hemisphere direction of table coordinates (u, v): φ = 2πu, cos θ = 1 − v.
#[inline]
fn uv_to_dir(uv: Vec2) -> Vec3 {
    let z = 1.0 - uv.y;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * uv.x;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Table coordinates of a unit upper-hemisphere direction (the inverse of [`uv_to_dir`]).
#[inline]
fn dir_to_uv(w: Vec3) -> Vec2 {
    let mut phi = w.y.atan2(w.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    Vec2::new((phi / (2.0 * PI)).min(1.0), (1.0 - w.z).clamp(0.0, 1.0))
}

#[cfg(test)]
mod tests;
