//! An image environment seen through a window: pbrt-v4's `PortalImageInfiniteLight`.
//!
//! The portal is a rectangle (four world-space corners p0…p3). Its frame has x along p3 − p0,
//! y along p1 − p0 and z = x × y, the side the light comes from. A direction ω with local
//! coordinates (x, y, z), z > 0, maps to the "rectified" image coordinates
//! u = (atan2(x, z) + π/2)/π, v = (atan2(y, z) + π/2)/π, whose inverse is
//! ω = normalize(tan α, tan β, 1) with α = π(u − ½), β = π(v − ½), and whose Jacobian is
//! |dω/d(u, v)| = π² (1 − x²)(1 − y²)/z.
//!
//! Seen from a point p, the portal covers the axis-aligned (u, v) rectangle spanned by the
//! images of p0 − p and p2 − p (the mapping keeps the portal's edges on lines of constant u
//! or v). Light sampling picks (u, v) inside that window from a piecewise-constant density
//! over a grid of the environment's resolution, each cell weighted by its radiance (channel
//! average) times |dω/d(u, v)| at its centre; the window is cut out of the grid with a
//! summed-area table (pbrt-v4's `WindowedPiecewiseConstant2D`), so
//! p(ω) = f(u, v) / ∫_window f · 1/|dω/d(u, v)|.
//!
//! Radiance is the environment's own ([`ImageInfiniteLight::le`]) for directions in front of
//! the portal's plane and zero behind it, where pbrt-v4's map is undefined. pbrt-v4 also
//! returns zero for rays that leave beside the portal; lancer's `Le` does not see the ray's
//! origin, so it keeps the environment there (and [`PortalInfiniteLight::pdf_li`] is zero
//! for them, which keeps MIS unbiased). In a room closed but for the window the two agree.

use super::bounds::LightExtent;
use super::distant::{disk_pdf, disk_point, has_disk};
use super::image_infinite::{ImageInfiniteLight, environment_mapping};
use super::kind::{
    LightDescKind, LightKind, LightLePdf, LightLeSample, LightType, SceneSphere, point_error,
};
use super::sample::{LightLiSample, LightSampleContext};
use crate::image::Image;
use crate::math::{Frame, PI, Rgb, Transform, Vec2, Vec3, cross, normalize};
use crate::shape::{Shape, TriangleMesh};
use std::sync::Arc;

/// An environment seen through a portal as a scene describes it (pbrt-v4's `infinite` light
/// with `portal`).
#[derive(Clone, Debug, PartialEq)]
pub struct PortalInfiniteDesc {
    /// Light space → world space.
    pub light_to_world: Transform,
    /// Multiplies the image.
    pub l: Rgb,
    /// Environment map, equal-area octahedral (square) or lat-long (2:1).
    pub image: Arc<Image>,
    /// The portal's corners, world space, in order around the rectangle.
    pub portal: [Vec3; 4],
}

impl LightDescKind for PortalInfiniteDesc {
    type Light = PortalInfiniteLight;

    fn pbrt_name(&self) -> &'static str {
        "infinite"
    }

    /// An image of a known layout with finite values ([`environment_mapping`]); the
    /// portal's shape is checked as the light is made ([`portal_frame`]).
    fn validate(&self) -> Result<(), String> {
        environment_mapping(&self.image).map(|_| ())
    }

    fn build(&self, scene: &SceneSphere) -> Result<PortalInfiniteLight, String> {
        PortalInfiniteLight::new(
            self.light_to_world,
            self.image.clone(),
            self.l,
            self.portal,
            *scene,
        )
    }
}

/// An image environment light that only lets light in through a rectangular portal.
#[derive(Clone, Debug, PartialEq)]
pub struct PortalInfiniteLight {
    /// The environment (its radiance, image and transform).
    env: ImageInfiniteLight,
    /// The portal's corners, world space.
    portal: [Vec3; 4],
    /// x along p3 − p0, y along p1 − p0, z = x × y.
    frame: Frame,
    /// Grid resolution (the environment image's).
    nx: usize,
    /// Grid rows.
    ny: usize,
    /// Sampling weight of each grid cell, row-major.
    func: Vec<f32>,
    /// Summed-area table of `func`: `sat[y·nx + x]` = Σ over cells (≤ x, ≤ y).
    sat: Vec<f64>,
    /// The scene's bounding sphere.
    scene: SceneSphere,
    /// pbrt-v4's Φ for a portal light, channel average.
    power: f32,
}

/// Local direction of rectified image coordinates `uv` and |dω/d(u, v)| there.
fn rectified_to_local(uv: Vec2) -> (Vec3, f32) {
    let alpha = -PI / 2.0 + uv.x * PI;
    let beta = -PI / 2.0 + uv.y * PI;
    let w = normalize(Vec3::new(alpha.tan(), beta.tan(), 1.0));
    (w, rectified_jacobian(w))
}

/// |dω/d(u, v)| = π² (1 − x²)(1 − y²)/z at the unit local direction `w` (z > 0).
fn rectified_jacobian(w: Vec3) -> f32 {
    PI * PI * (1.0 - w.x * w.x) * (1.0 - w.y * w.y) / w.z
}

/// Rectified image coordinates of a unit local direction, `None` behind the portal's plane.
fn local_to_rectified(w: Vec3) -> Option<Vec2> {
    if w.z <= 0.0 {
        return None;
    }
    let u = (w.x.atan2(w.z) + PI / 2.0) / PI;
    let v = (w.y.atan2(w.z) + PI / 2.0) / PI;
    Some(Vec2::new(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)))
}

/// The portal's frame: x along p3 − p0, y along p1 − p0, z = x × y; an error when the four
/// corners do not form a rectangle in order (pbrt-v4's tolerance: unit edge directions within
/// 0.001 of parallel and perpendicular).
pub fn portal_frame(portal: &[Vec3; 4]) -> Result<Frame, String> {
    let dir = |a: Vec3, b: Vec3| (b - a).try_normalize();
    let (Some(p01), Some(p12), Some(p32), Some(p03)) = (
        dir(portal[0], portal[1]),
        dir(portal[1], portal[2]),
        dir(portal[3], portal[2]),
        dir(portal[0], portal[3]),
    ) else {
        return Err("an infinite light's portal has coincident corners".into());
    };
    let parallel = (p01.dot(p32) - 1.0).abs() <= 1e-3 && (p12.dot(p03) - 1.0).abs() <= 1e-3;
    let square = [p01.dot(p12), p12.dot(p32), p32.dot(p03), p03.dot(p01)]
        .iter()
        .all(|d| d.abs() <= 1e-3);
    if !parallel || !square {
        return Err("an infinite light's portal must be a rectangle, its corners in order".into());
    }
    Ok(Frame {
        x: p03,
        y: p01,
        z: normalize(cross(p03, p01)),
    })
}

/// The (u, v) rectangle, as (min, max).
type Window = (Vec2, Vec2);

impl PortalInfiniteLight {
    /// The light; an error when the image is not a valid environment, or the four corners do
    /// not form a rectangle (pbrt-v4's tolerance: unit edge directions within 0.001).
    pub fn new(
        light_to_world: Transform,
        image: Arc<Image>,
        scale: Rgb,
        portal: [Vec3; 4],
        scene: SceneSphere,
    ) -> Result<PortalInfiniteLight, String> {
        let env = ImageInfiniteLight::new(light_to_world, image, scale, scene)?;
        let frame = portal_frame(&portal)?;
        let (nx, ny) = (env.image().width as usize, env.image().height as usize);
        let area = (portal[1] - portal[0]).length() * (portal[3] - portal[0]).length();
        // Cell weights: radiance (channel average) × |dω/d(u, v)| at the cell centre.
        let mut func = Vec::with_capacity(nx * ny);
        let mut phi = 0.0f64;
        for y in 0..ny {
            for x in 0..nx {
                let uv = Vec2::new((x as f32 + 0.5) / nx as f32, (y as f32 + 0.5) / ny as f32);
                let (local, jacobian) = rectified_to_local(uv);
                let l = env.le(frame.from_local(local));
                let avg = (l.x + l.y + l.z) / 3.0;
                let f = avg * jacobian;
                func.push(if f.is_finite() { f.max(0.0) } else { 0.0 });
                // pbrt-v4's Φ: area · mean over cells of L / |dω/d(u, v)|.
                if jacobian > 0.0 {
                    phi += (avg.max(0.0) / jacobian) as f64;
                }
            }
        }
        let mut sat = vec![0.0f64; nx * ny];
        for y in 0..ny {
            let mut row = 0.0f64;
            for x in 0..nx {
                row += func[y * nx + x] as f64;
                sat[y * nx + x] = row + if y > 0 { sat[(y - 1) * nx + x] } else { 0.0 };
            }
        }
        Ok(PortalInfiniteLight {
            env,
            portal,
            frame,
            nx,
            ny,
            func,
            sat,
            scene,
            power: (area as f64 * phi / (nx * ny) as f64) as f32,
        })
    }

    /// The environment image.
    pub fn image(&self) -> &Arc<Image> {
        self.env.image()
    }

    /// Bytes of the sampling tables (the image not included).
    pub fn table_bytes(&self) -> usize {
        self.env.table_bytes()
            + self.func.capacity() * std::mem::size_of::<f32>()
            + self.sat.capacity() * std::mem::size_of::<f64>()
    }

    /// Radiance arriving along a ray leaving the scene in world direction `d`: the
    /// environment's in front of the portal's plane, zero behind it.
    #[inline]
    pub fn le(&self, d: Vec3) -> Rgb {
        if self.frame.to_local(d).z <= 0.0 {
            return Rgb::ZERO;
        }
        self.env.le(d)
    }

    /// Rectified coordinates of a world direction (`None` behind the portal).
    fn rectified(&self, d: Vec3) -> Option<(Vec2, f32)> {
        let w = self.frame.to_local(d).normalize_or_zero();
        let uv = local_to_rectified(w)?;
        Some((uv, rectified_jacobian(w)))
    }

    /// The (u, v) window the portal covers seen from `p`; `None` if `p` is not behind it.
    fn window(&self, p: Vec3) -> Option<Window> {
        let (a, _) = self.rectified(self.portal[0] - p)?;
        let (b, _) = self.rectified(self.portal[2] - p)?;
        Some((a.min(b), a.max(b)))
    }

    /// Σ of the weights in cells (< x, < y) of integer corner (x, y), clamped to the grid.
    #[inline]
    fn sat_at(&self, x: usize, y: usize) -> f64 {
        if x == 0 || y == 0 {
            return 0.0;
        }
        let (x, y) = ((x - 1).min(self.nx - 1), (y - 1).min(self.ny - 1));
        self.sat[y * self.nx + x]
    }

    /// ∫₀^u ∫₀^v f: the table interpolated bilinearly, exact for a piecewise-constant f.
    fn cumulative(&self, u: f32, v: f32) -> f64 {
        let (x, y) = (u as f64 * self.nx as f64, v as f64 * self.ny as f64);
        let (x0, y0) = (x as usize, y as usize);
        let (dx, dy) = (x - x0 as f64, y - y0 as f64);
        (1.0 - dx) * (1.0 - dy) * self.sat_at(x0, y0)
            + (1.0 - dx) * dy * self.sat_at(x0, y0 + 1)
            + dx * (1.0 - dy) * self.sat_at(x0 + 1, y0)
            + dx * dy * self.sat_at(x0 + 1, y0 + 1)
    }

    /// ∫ f over a window, in units where the whole grid has area 1.
    fn integral(&self, (lo, hi): Window) -> f64 {
        let s = self.cumulative(hi.x, hi.y) - self.cumulative(lo.x, hi.y)
            + (self.cumulative(lo.x, lo.y) - self.cumulative(hi.x, lo.y));
        (s / (self.nx * self.ny) as f64).max(0.0)
    }

    /// The weight of the cell holding `uv`.
    fn eval(&self, uv: Vec2) -> f32 {
        let x = ((uv.x * self.nx as f32) as usize).min(self.nx - 1);
        let y = ((uv.y * self.ny as f32) as usize).min(self.ny - 1);
        self.func[y * self.nx + x]
    }

    /// Inverts the monotone cumulative `cdf` on [min, max] for `u`: bisection down to one
    /// cell of `n`, then linear interpolation (exact, the cumulative being linear in a cell).
    fn invert(cdf: impl Fn(f32) -> f64, u: f32, mut min: f32, mut max: f32, n: usize) -> f32 {
        let n = n as f32;
        let u = u as f64;
        while (n * max).ceil() - (n * min).floor() > 1.0 {
            let mid = 0.5 * (min + max);
            if mid <= min || mid >= max {
                break;
            }
            if cdf(mid) > u {
                max = mid;
            } else {
                min = mid;
            }
        }
        let (c0, c1) = (cdf(min), cdf(max));
        let t = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        (min + (t as f32) * (max - min)).clamp(min, max)
    }

    /// A point of `window` with density f / ∫_window f, and that density.
    fn sample_window(&self, u: Vec2, w: Window) -> Option<(Vec2, f32)> {
        let total = self.integral(w);
        if total <= 0.0 {
            return None;
        }
        let (lo, hi) = w;
        // Marginal in u.
        let x = Self::invert(
            |x| self.integral((lo, Vec2::new(x, hi.y))) / total,
            u.x,
            lo.x,
            hi.x,
            self.nx,
        );
        // Conditional in v, within the grid column holding x.
        let nxf = self.nx as f32;
        let mut c_lo = Vec2::new((x * nxf).floor() / nxf, lo.y);
        let mut c_hi = Vec2::new((x * nxf).ceil() / nxf, hi.y);
        if c_lo.x == c_hi.x {
            c_hi.x += 1.0 / nxf;
        }
        c_lo.x = c_lo.x.min(1.0);
        c_hi.x = c_hi.x.min(1.0);
        let cond = self.integral((c_lo, c_hi));
        if cond <= 0.0 {
            return None;
        }
        let y = Self::invert(
            |y| self.integral((c_lo, Vec2::new(c_hi.x, y))) / cond,
            u.y,
            lo.y,
            hi.y,
            self.ny,
        );
        let p = Vec2::new(x, y);
        Some((p, (self.eval(p) as f64 / total) as f32))
    }

    /// A direction through the portal chosen by the environment's brightness there, with its
    /// density per solid angle.
    pub fn sample_li(&self, ctx: &LightSampleContext, u: Vec2) -> Option<LightLiSample> {
        let window = self.window(ctx.p)?;
        let (uv, map_pdf) = self.sample_window(u, window)?;
        let (local, jacobian) = rectified_to_local(uv);
        if map_pdf <= 0.0 || jacobian <= 0.0 {
            return None;
        }
        let wi = self.frame.from_local(local);
        let pdf = map_pdf / jacobian;
        pdf.is_finite().then(|| LightLiSample {
            factor: 1.0,
            l: self.env.le(wi),
            wi,
            pdf,
            p_light: ctx.p + wi * (2.0 * self.scene.radius.max(1e-3)),
        })
    }

    /// Density with which [`PortalInfiniteLight::sample_li`] picks world direction `wi` at
    /// `p`: zero for directions that miss the portal.
    pub fn pdf_li(&self, p: Vec3, wi: Vec3) -> f32 {
        let Some((uv, jacobian)) = self.rectified(wi) else {
            return 0.0;
        };
        let Some((lo, hi)) = self.window(p) else {
            return 0.0;
        };
        if jacobian <= 0.0 || uv.x < lo.x || uv.y < lo.y || uv.x > hi.x || uv.y > hi.y {
            return 0.0;
        }
        let total = self.integral((lo, hi));
        if total <= 0.0 {
            return 0.0;
        }
        (self.eval(uv) as f64 / total) as f32 / jacobian
    }

    /// pbrt-v4's Φ for a portal light: area · mean over the grid of L/|dω/d(u, v)|, channel
    /// average.
    pub fn power(&self) -> f32 {
        self.power
    }
}

/// The whole grid of rectified coordinates: where light arrives from through the portal
/// from anywhere.
const WHOLE: Window = (Vec2::ZERO, Vec2::ONE);

impl LightKind for PortalInfiniteLight {
    fn light_type(&self) -> LightType {
        LightType::Infinite
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        PortalInfiniteLight::sample_li(self, ctx, u)
    }

    fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, _: Option<(Vec3, Vec3)>) -> f32 {
        PortalInfiniteLight::pdf_li(self, ctx.p, wi)
    }

    fn power(&self) -> f32 {
        self.power
    }

    fn extent(&self, _: &[Shape], _: &[TriangleMesh]) -> LightExtent {
        LightExtent::Unbounded
    }

    fn constant_colour(&self) -> Option<Rgb> {
        None
    }

    fn le(&self, d: Vec3) -> Rgb {
        PortalInfiniteLight::le(self, d)
    }

    /// pbrt-v4's: the direction the light comes from chosen over the whole rectified grid by
    /// `u1` (p_dir = f(u, v)/∫f / |dω/d(u, v)|), the ray travelling opposite it from a point
    /// uniform on the scene's disk (p_pos = 1/(π r²)); pbrt-v4 leaves sampling the portal's
    /// own area aside, as it does not suit bidirectional methods.
    fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        _: &[Shape],
        _: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        let (uv, map_pdf) = self.sample_window(u1, WHOLE)?;
        let (local, jacobian) = rectified_to_local(uv);
        if map_pdf <= 0.0 || jacobian <= 0.0 || !has_disk(&self.scene) {
            return None;
        }
        let from = self.frame.from_local(local);
        let pdf_dir = map_pdf / jacobian;
        let p = disk_point(&self.scene, from, u2);
        pdf_dir.is_finite().then(|| LightLeSample {
            l: self.env.le(from),
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
        let dir = match self.rectified(-w) {
            Some((uv, jacobian)) if jacobian > 0.0 => {
                let total = self.integral(WHOLE);
                if total > 0.0 {
                    (self.eval(uv) as f64 / total) as f32 / jacobian
                } else {
                    0.0
                }
            }
            _ => 0.0,
        };
        LightLePdf {
            pos: disk_pdf(&self.scene),
            dir,
        }
    }

    fn image(&self) -> Option<&Arc<Image>> {
        Some(PortalInfiniteLight::image(self))
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

    /// The scene's bounding sphere in these tests.
    const SCENE: SceneSphere = SceneSphere {
        centre: Vec3::ZERO,
        radius: 10.0,
    };

    /// A 16×16 equal-area sky of uneven texels, rotated, behind a 2×1.5 window in the plane
    /// x = 1 (corners in the order pbrt-v4 expects: z = (p3 − p0) × (p1 − p0) = +x).
    fn light() -> (PortalInfiniteLight, ImageInfiniteLight) {
        let texels = (0..256)
            .map(|i| {
                let u = rand2(i, 7);
                PackedRgb::new(0.1 + 4.0 * u.x * u.x, 0.5 * u.y, 1.0)
            })
            .collect();
        let image = Arc::new(Image::new(16, 16, texels).unwrap());
        let to_world = Transform::rotate(30.0, Vec3::new(0.2, 1.0, 0.3)).unwrap();
        let portal = [
            Vec3::new(1.0, -0.5, -1.0),
            Vec3::new(1.0, -0.5, 1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(1.0, 1.0, -1.0),
        ];
        let scale = Rgb::splat(2.0);
        (
            PortalInfiniteLight::new(to_world, image.clone(), scale, portal, SCENE).unwrap(),
            ImageInfiniteLight::new(to_world, image, scale, SCENE).unwrap(),
        )
    }

    fn ctx(p: Vec3) -> LightSampleContext {
        LightSampleContext {
            p,
            n: Vec3::X,
            ns: Vec3::X,
        }
    }

    /// Where the ray p + t·w meets the plane x = 1, if it does (t > 0).
    fn through_window(p: Vec3, w: Vec3) -> Option<Vec3> {
        (w.x > 0.0).then(|| p + w * ((1.0 - p.x) / w.x))
    }

    #[test]
    fn the_frame_faces_out_of_the_window() {
        let (l, _) = light();
        assert!((l.frame.z - Vec3::X).length() < 1e-6, "{:?}", l.frame.z);
        // The rectified map and its inverse agree, and the Jacobian is π² at the centre.
        let (w, j) = rectified_to_local(Vec2::splat(0.5));
        assert!((w - Vec3::Z).length() < 1e-6 && (j - PI * PI).abs() < 1e-4);
        for i in 0..100 {
            let uv = rand2(i, 1) * 0.98 + Vec2::splat(0.01);
            let (w, _) = rectified_to_local(uv);
            assert!((local_to_rectified(w).unwrap() - uv).length() < 1e-4);
        }
        assert_eq!(local_to_rectified(Vec3::new(0.0, 0.6, -0.8)), None);
    }

    #[test]
    fn samples_pass_through_the_portal_with_the_pdf_of_pdf_li() {
        let (l, _) = light();
        for (k, p) in [
            Vec3::ZERO,
            Vec3::new(0.3, 0.8, -0.9),
            Vec3::new(-2.0, 0.1, 0.4),
        ]
        .into_iter()
        .enumerate()
        {
            let mut n = 0;
            for i in 0..5000 {
                let Some(s) = l.sample_li(&ctx(p), rand2(i, 10 + k as u64)) else {
                    continue;
                };
                n += 1;
                let q = through_window(p, s.wi).expect("towards the window");
                assert!(
                    q.y >= -0.5 - 1e-3 && q.y <= 1.0 + 1e-3 && q.z.abs() <= 1.0 + 1e-3,
                    "{q:?}"
                );
                let pdf = l.pdf_li(p, s.wi);
                assert!((pdf - s.pdf).abs() <= 2e-3 * s.pdf, "{pdf} vs {}", s.pdf);
                assert_eq!(s.l, l.le(s.wi));
            }
            assert!(n > 4900, "{n}");
        }
        // Directions that miss the window have density zero.
        assert_eq!(
            l.pdf_li(Vec3::ZERO, normalize(Vec3::new(1.0, 0.0, 3.0))),
            0.0
        );
        assert_eq!(l.pdf_li(Vec3::ZERO, -Vec3::X), 0.0);
    }

    #[test]
    fn the_pdf_integrates_to_one() {
        // ∫ p dω over the sphere = E[p(ω)/p_u(ω)] with ω uniform on the hemisphere facing the
        // window (p_u = 1/2π); the density is zero behind the portal's plane.
        let (l, _) = light();
        for p in [Vec3::new(0.5, 0.2, 0.1), Vec3::new(-1.0, 0.3, -0.6)] {
            let n = 400_000u64;
            let mut sum = 0.0f64;
            for i in 0..n {
                let w = crate::sampling::sample_uniform_hemisphere(rand2(i, 99));
                let wi = Vec3::new(w.z, w.x, w.y);
                sum += l.pdf_li(p, wi) as f64 * 2.0 * PI as f64;
            }
            let integral = sum / n as f64;
            assert!((integral - 1.0).abs() < 0.02, "{p:?}: {integral}");
            assert_eq!(l.pdf_li(p, normalize(Vec3::new(-0.5, 0.1, 0.2))), 0.0);
        }
    }

    #[test]
    fn radiance_is_the_environments_in_front_of_the_portal() {
        let (l, env) = light();
        for i in 0..200 {
            let d = crate::sampling::sample_uniform_sphere(rand2(i, 5));
            let want = if d.x > 0.0 { env.le(d) } else { Rgb::ZERO };
            assert_eq!(l.le(d), want, "{d:?}");
        }
        // A sample's radiance is the environment's along its direction.
        let s = l.sample_li(&ctx(Vec3::ZERO), Vec2::new(0.3, 0.7)).unwrap();
        assert_eq!(s.l, env.le(s.wi));
    }

    #[test]
    fn non_rectangles_are_refused() {
        let square = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        let f = portal_frame(&square).unwrap();
        // x = p3 − p0 = +y, y = p1 − p0 = +x, z = x × y = −z.
        assert!((f.z + Vec3::Z).length() < 1e-6);
        let skew = [Vec3::ZERO, Vec3::X, Vec3::new(2.0, 1.0, 0.0), Vec3::Y];
        assert!(portal_frame(&skew).unwrap_err().contains("rectangle"));
        let point = [Vec3::ZERO; 4];
        assert!(portal_frame(&point).unwrap_err().contains("coincident"));
    }

    #[test]
    fn emitted_rays_carry_what_crosses_the_disk_from_the_portals_side() {
        use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};
        let (light, _) = light();
        let phi = le_power(&light, &[], &[], 1 << 14);
        // π r² ∫ L dω over the directions in front of the portal, by uniform directions.
        let n = 1 << 16;
        let mut sum = 0.0f64;
        for i in 0..n {
            let l = light.le(crate::sampling::sample_uniform_sphere(rand2(i, 11)));
            sum += ((l.x + l.y + l.z) / 3.0) as f64;
        }
        let want = (PI * 100.0) as f64 * 4.0 * PI as f64 * sum / n as f64;
        assert!((phi as f64 - want).abs() < 0.02 * want, "{phi} vs {want}");
        le_pdfs_agree(&light, &[], &[], 256, 1e-2);
        let total = le_dir_integral(&light, Vec3::ZERO, Vec3::ZERO, 1 << 16);
        assert!((total - 1.0).abs() < 0.03, "{total}");
    }
}
