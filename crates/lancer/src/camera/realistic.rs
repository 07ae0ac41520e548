//! pbrt-v4's `realistic` camera: rays from the film traced through a system of spherical lens
//! interfaces and an aperture stop, so that depth of field, vignetting and distortion come from
//! the lens itself.
//!
//! Camera space has the film at z = 0 and the lens in front of it (+z). The lens file lists the
//! interfaces from the scene side to the film side; "lens space" is camera space with z
//! negated, where the rear interface is at z = −thickness of the last row and each row's
//! thickness steps further towards −z. The last thickness (rear element to film) is replaced by
//! the one that focuses the system at `focusdistance`, from a thick-lens approximation.
//!
//! A camera ray starts at the film point, aims at a point sampled uniformly in a bound of the
//! exit pupil (precomputed for 64 rings of film radius, rotated to the film point's angle),
//! and carries the weight cos⁴θ / (p(pupil point) · z_rear²) (pbrt-v4's approximation of the
//! irradiance at the film, with z_rear the distance from the film to the rear element).

use super::aperture::ApertureMask;
use super::lens::LensDesc;
use crate::material::refract;
use crate::math::{Vec2, Vec3, normalize, solve_quadratic};
use rayon::prelude::*;

/// Film radii at which the exit pupil is bounded (pbrt-v4's 64).
const PUPIL_RINGS: usize = 64;

/// Points tried per ring when bounding the exit pupil: 256², where pbrt-v4 tries 1024² (some
/// 6 s of work at every load). The bound grows by pbrt-v4's margin for that spacing, twice the
/// square's diagonal over √n, so it still holds the whole pupil; being a little wider, it only
/// wastes a few percent more camera samples. The camera's estimate is unbiased either way.
pub const PUPIL_SAMPLES: usize = 1 << 16;

/// One interface of the system, lengths in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Interface {
    /// Radius of curvature; 0 for the aperture stop.
    curvature_radius: f32,
    /// Distance to the next interface towards the film.
    thickness: f32,
    /// Index of refraction behind the interface (towards the film).
    eta: f32,
    /// Radius of the clear aperture.
    aperture_radius: f32,
}

impl Interface {
    fn is_stop(&self) -> bool {
        self.curvature_radius == 0.0
    }
}

/// An axis-aligned rectangle on the rear element's plane; empty when `min > max`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Rect {
    min: Vec2,
    max: Vec2,
}

impl Rect {
    const EMPTY: Rect = Rect {
        min: Vec2::splat(f32::MAX),
        max: Vec2::splat(-f32::MAX),
    };

    fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y
    }

    fn contains(&self, p: Vec2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    fn lerp(&self, t: Vec2) -> Vec2 {
        self.min + t * (self.max - self.min)
    }

    fn area(&self) -> f32 {
        let d = self.max - self.min;
        d.x * d.y
    }
}

/// A ray in camera or lens space (directions not necessarily normalised).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensRay {
    /// Origin.
    pub o: Vec3,
    /// Direction.
    pub d: Vec3,
}

impl LensRay {
    fn at(&self, t: f32) -> Vec3 {
        self.o + t * self.d
    }

    /// The same ray with z negated (camera space ↔ lens space).
    fn flip_z(&self) -> LensRay {
        LensRay {
            o: self.o * Vec3::new(1.0, 1.0, -1.0),
            d: self.d * Vec3::new(1.0, 1.0, -1.0),
        }
    }
}

/// A sampled camera ray: camera-space ray and its weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LensSample {
    /// The ray leaving the front element, camera space, unit direction.
    pub ray: LensRay,
    /// cos⁴θ / (p · z_rear²) times the aperture's transmission.
    pub weight: f32,
}

/// The lens system, focused, with its exit-pupil bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct RealisticCamera {
    interfaces: Vec<Interface>,
    aperture: Option<ApertureMask>,
    /// The film's physical extent (metres), centred on the axis.
    extent: Rect,
    /// The film's diagonal in metres.
    diagonal: f32,
    /// The image's resolution in pixels.
    resolution: Vec2,
    /// Bounds of the exit pupil for film points at radius in [i, i+1)·(diagonal/2)/64, for a
    /// film point on +x (rotated for the others).
    pupil_bounds: Vec<Rect>,
}

/// ⌊the radical inverse of `a` in `base`⌋: its digits mirrored about the point (pbrt-v4's
/// `RadicalInverse`, here only for bases 2 and 3).
fn radical_inverse(base: u64, mut a: u64) -> f32 {
    let inv_base = 1.0 / base as f64;
    let (mut reversed, mut inv_bn) = (0u64, 1.0f64);
    while a > 0 {
        let next = a / base;
        reversed = reversed * base + (a - next * base);
        inv_bn *= inv_base;
        a = next;
    }
    ((reversed as f64 * inv_bn) as f32).min(1.0 - f32::EPSILON / 2.0)
}

/// Where a ray meets the spherical interface of `radius` centred on the axis at `z_center`
/// (lens space), and the unit normal there facing the ray's origin. Of the two roots, the one
/// on the interface's vertex side: the nearer one when the ray travels towards +z and the
/// surface is convex towards −z (radius > 0), or towards −z and radius < 0.
fn intersect_spherical(radius: f32, z_center: f32, r: &LensRay) -> Option<(f32, Vec3)> {
    let o = r.o - Vec3::new(0.0, 0.0, z_center);
    let (a, b, c) = (
        r.d.dot(r.d) as f64,
        2.0 * r.d.dot(o) as f64,
        (o.dot(o) - radius * radius) as f64,
    );
    let (t0, t1) = solve_quadratic(a, b, c)?;
    let closer = (r.d.z > 0.0) ^ (radius < 0.0);
    let t = if closer { t0.min(t1) } else { t0.max(t1) } as f32;
    if t < 0.0 || t.is_nan() {
        return None;
    }
    let n = normalize(o + t * r.d);
    Some((t, if n.dot(-r.d) < 0.0 { -n } else { n }))
}

impl RealisticCamera {
    /// The camera for a film of diagonal `diagonal_mm` and `xres × yres` pixels, bounding the
    /// exit pupil with `pupil_samples` points per ring ([`PUPIL_SAMPLES`] as pbrt-v4). Errors
    /// when the system cannot be focused at the focus distance, or no ray traverses it.
    pub fn new(
        desc: &LensDesc,
        diagonal_mm: f32,
        xres: u32,
        yres: u32,
        pupil_samples: usize,
    ) -> Result<RealisticCamera, String> {
        if desc.interfaces.is_empty() {
            return Err("the lens system has no interfaces".into());
        }
        let diagonal = diagonal_mm / 1000.0;
        // The film's size: diagonal² = x² + y² with y/x the image's aspect.
        let aspect = yres as f32 / xres as f32;
        let x = (diagonal * diagonal / (1.0 + aspect * aspect)).sqrt();
        let y = aspect * x;
        let extent = Rect {
            min: Vec2::new(-x / 2.0, -y / 2.0),
            max: Vec2::new(x / 2.0, y / 2.0),
        };
        let interfaces = desc
            .interfaces
            .iter()
            .map(|l| {
                let mut diameter = l.aperture_diameter;
                if l.curvature_radius == 0.0 && desc.aperture_diameter <= diameter {
                    // The stop opens to `aperturediameter`, never wider than the file allows.
                    diameter = desc.aperture_diameter;
                }
                Interface {
                    curvature_radius: l.curvature_radius / 1000.0,
                    thickness: l.thickness / 1000.0,
                    eta: l.eta,
                    aperture_radius: diameter / 2000.0,
                }
            })
            .collect();
        let mut camera = RealisticCamera {
            interfaces,
            aperture: ApertureMask::new(&desc.aperture)?,
            extent,
            diagonal,
            resolution: Vec2::new(xres as f32, yres as f32),
            pupil_bounds: Vec::new(),
        };
        let film_distance = camera.focus_thick_lens(desc.focus_distance)?;
        camera.interfaces.last_mut().expect("not empty").thickness = film_distance;
        camera.pupil_bounds = (0..PUPIL_RINGS)
            .into_par_iter()
            .map(|i| {
                let r0 = i as f32 / PUPIL_RINGS as f32 * diagonal / 2.0;
                let r1 = (i + 1) as f32 / PUPIL_RINGS as f32 * diagonal / 2.0;
                camera.bound_exit_pupil(r0, r1, pupil_samples)
            })
            .collect();
        if camera.pupil_bounds.iter().all(Rect::is_empty) {
            return Err("no ray from the film gets through the lens system".into());
        }
        Ok(camera)
    }

    /// Distance from the film to the rear element.
    fn rear_z(&self) -> f32 {
        self.interfaces.last().map_or(0.0, |e| e.thickness)
    }

    /// Distance from the film to the front element.
    fn front_z(&self) -> f32 {
        self.interfaces.iter().map(|e| e.thickness).sum()
    }

    /// Traces a camera-space ray from the film side through the system, rear to front: the
    /// camera-space ray leaving the front element and the aperture's transmission, or `None`
    /// when an interface's rim or the stop blocks it or it reflects totally. At each interface
    /// Snell's law bends it from the index behind the interface to the one in front (1 for air,
    /// written 0 or 1).
    pub fn trace_from_film(&self, r: &LensRay) -> Option<(LensRay, f32)> {
        let mut z = 0.0;
        let mut weight = 1.0;
        let mut ray = r.flip_z();
        for i in (0..self.interfaces.len()).rev() {
            let e = &self.interfaces[i];
            z -= e.thickness;
            let (t, n) = if e.is_stop() {
                // The stop's plane.
                let t = (z - ray.o.z) / ray.d.z;
                if t < 0.0 || t.is_nan() {
                    return None;
                }
                (t, Vec3::ZERO)
            } else {
                intersect_spherical(e.curvature_radius, z + e.curvature_radius, &ray)?
            };
            let p = ray.at(t);
            match (&self.aperture, e.is_stop()) {
                (Some(mask), true) => {
                    let uv = Vec2::new(
                        (p.x / e.aperture_radius + 1.0) / 2.0,
                        (p.y / e.aperture_radius + 1.0) / 2.0,
                    );
                    weight = mask.bilerp(uv);
                    if weight == 0.0 {
                        return None;
                    }
                }
                _ => {
                    if p.x * p.x + p.y * p.y > e.aperture_radius * e.aperture_radius {
                        return None;
                    }
                }
            }
            ray.o = p;
            if !e.is_stop() {
                let eta_i = if e.eta != 0.0 { e.eta } else { 1.0 };
                let eta_t = match i {
                    0 => 1.0,
                    _ if self.interfaces[i - 1].eta == 0.0 => 1.0,
                    _ => self.interfaces[i - 1].eta,
                };
                ray.d = refract(normalize(-ray.d), n, eta_t / eta_i)?.0;
            }
        }
        Some((ray.flip_z(), weight))
    }

    /// Traces a camera-space ray from the scene side through the system, front to rear (the
    /// aperture's shape not considered, as pbrt-v4): the ray leaving the rear element.
    pub fn trace_from_scene(&self, r: &LensRay) -> Option<LensRay> {
        let mut z = -self.front_z();
        let mut ray = r.flip_z();
        for (i, e) in self.interfaces.iter().enumerate() {
            let (t, n) = if e.is_stop() {
                let t = (z - ray.o.z) / ray.d.z;
                if t < 0.0 || t.is_nan() {
                    return None;
                }
                (t, Vec3::ZERO)
            } else {
                intersect_spherical(e.curvature_radius, z + e.curvature_radius, &ray)?
            };
            let p = ray.at(t);
            if p.x * p.x + p.y * p.y > e.aperture_radius * e.aperture_radius {
                return None;
            }
            ray.o = p;
            if !e.is_stop() {
                let eta_i = match i {
                    0 => 1.0,
                    _ if self.interfaces[i - 1].eta == 0.0 => 1.0,
                    _ => self.interfaces[i - 1].eta,
                };
                let eta_t = if e.eta != 0.0 { e.eta } else { 1.0 };
                ray.d = refract(normalize(-ray.d), n, eta_t / eta_i)?.0;
            }
            z += e.thickness;
        }
        Some(ray.flip_z())
    }

    /// The principal plane's and focal point's z (camera space) on the side `out` leaves to,
    /// from a ray `r_in` parallel to the axis and `out`, what the system made of it: the focal
    /// point is where `out` crosses the axis, the principal plane where it reaches `r_in`'s
    /// height.
    fn cardinal_points(r_in: &LensRay, out: &LensRay) -> (f32, f32) {
        let tf = -out.o.x / out.d.x;
        let tp = (r_in.o.x - out.o.x) / out.d.x;
        (out.at(tp).z, out.at(tf).z)
    }

    /// The thick-lens approximation: (principal plane, focal point) z on the film side, then
    /// on the scene side, from rays parallel to the axis at a thousandth of the film's
    /// diagonal.
    fn thick_lens(&self) -> Result<[(f32, f32); 2], String> {
        let x = 0.001 * self.diagonal;
        let stop = "a ray near the axis does not get through the lens system (is the aperture \
                    stop extremely small?)";
        let from_scene = LensRay {
            o: Vec3::new(x, 0.0, self.front_z() + 1.0),
            d: -Vec3::Z,
        };
        let to_film = self.trace_from_scene(&from_scene).ok_or(stop)?;
        let from_film = LensRay {
            o: Vec3::new(x, 0.0, self.rear_z() - 1.0),
            d: Vec3::Z,
        };
        let (to_scene, _) = self.trace_from_film(&from_film).ok_or(stop)?;
        Ok([
            Self::cardinal_points(&from_scene, &to_film),
            Self::cardinal_points(&from_film, &to_scene),
        ])
    }

    /// The rear element's distance to the film that focuses the system at distance `focus` in
    /// front of the film (pbrt-v4's `FocusThickLens`). In lens space (scene towards −z), with
    /// p_f, f_f the film side's principal plane and focal point, p_s the scene side's principal
    /// plane and f = f_f − p_f: moving the lens by δ so that the thick-lens equation
    /// 1/z′ − 1/z = 1/f holds for the object at z = −focus and the film at 0 gives
    /// δ = ½ (p_s − z + p_f − √((p_s − z − p_f)(p_s − z − 4f − p_f))).
    fn focus_thick_lens(&self, focus: f32) -> Result<f32, String> {
        // Camera space → lens space: negate the z values.
        let [(pf, ff), (ps, _)] = self.thick_lens()?;
        let (pf, ff, ps) = (-pf, -ff, -ps);
        let f = ff - pf;
        let z = -focus;
        let c = (ps - z - pf) * (ps - z - 4.0 * f - pf);
        if c <= 0.0 || c.is_nan() {
            return Err(format!(
                "focusdistance {focus} is too short for this lens system (it cannot focus closer than about 4 focal lengths, {:.3})",
                4.0 * f.abs()
            ));
        }
        let delta = (ps - z + pf - c.sqrt()) / 2.0;
        Ok(self.rear_z() + delta)
    }

    /// A bound of the points of the rear element's plane through which rays from film points
    /// (x, 0) with x ∈ [x0, x1] get through the system: `n` points in the square 1.5 times the
    /// rear element's radius (Halton bases 2 and 3, the film point swept along the segment),
    /// each one outside the current bound traced; the bound grown by twice the sample spacing.
    fn bound_exit_pupil(&self, x0: f32, x1: f32, n: usize) -> Rect {
        let rear_radius = self.interfaces.last().map_or(0.0, |e| e.aperture_radius);
        let square = Rect {
            min: Vec2::splat(-1.5 * rear_radius),
            max: Vec2::splat(1.5 * rear_radius),
        };
        let rear_z = self.rear_z();
        let mut bound = Rect::EMPTY;
        for i in 0..n {
            let t = (i as f32 + 0.5) / n as f32;
            let film = Vec3::new(x0 + t * (x1 - x0), 0.0, 0.0);
            let u = Vec2::new(radical_inverse(2, i as u64), radical_inverse(3, i as u64));
            let rear = square.lerp(u);
            if bound.contains(rear) {
                continue;
            }
            let ray = LensRay {
                o: film,
                d: Vec3::new(rear.x, rear.y, rear_z) - film,
            };
            if self.trace_from_film(&ray).is_some() {
                bound = Rect {
                    min: bound.min.min(rear),
                    max: bound.max.max(rear),
                };
            }
        }
        if bound.is_empty() {
            return bound;
        }
        let grow = 2.0 * (square.max - square.min).length() / (n as f32).sqrt();
        Rect {
            min: bound.min - Vec2::splat(grow),
            max: bound.max + Vec2::splat(grow),
        }
    }

    /// A point of the exit pupil's bound for film point `p` (camera space), uniform in the
    /// bound of its ring rotated to `p`'s angle, and its density per unit area.
    fn sample_exit_pupil(&self, p: Vec2, u: Vec2) -> Option<(Vec3, f32)> {
        let r = p.length();
        let ring = ((r / (self.diagonal / 2.0) * PUPIL_RINGS as f32) as usize).min(PUPIL_RINGS - 1);
        let bound = self.pupil_bounds[ring];
        if bound.is_empty() {
            return None;
        }
        let q = bound.lerp(u);
        let (sin, cos) = if r != 0.0 {
            (p.y / r, p.x / r)
        } else {
            (0.0, 1.0)
        };
        Some((
            Vec3::new(cos * q.x - sin * q.y, sin * q.x + cos * q.y, self.rear_z()),
            1.0 / bound.area(),
        ))
    }

    /// The camera-space ray of raster point `p_raster` (pixels) through the lens, with `u`
    /// choosing the point of the exit pupil; `None` when the lens blocks it (vignetting).
    pub fn generate(&self, p_raster: Vec2, u: Vec2) -> Option<LensSample> {
        // Raster (0, 0) is the film's (−x, −y) corner, mirrored in x: the lens turns the image
        // over, so the picture comes out upright.
        let f = self.extent.lerp(p_raster / self.resolution);
        let film = Vec3::new(-f.x, f.y, 0.0);
        let (pupil, pdf) = self.sample_exit_pupil(Vec2::new(film.x, film.y), u)?;
        let r_film = LensRay {
            o: film,
            d: pupil - film,
        };
        let (mut ray, transmission) = self.trace_from_film(&r_film)?;
        ray.d = normalize(ray.d);
        let cos_theta = normalize(r_film.d).z;
        let rear = self.rear_z();
        let weight = transmission * cos_theta.powi(4) / (pdf * rear * rear);
        Some(LensSample { ray, weight })
    }
}

#[cfg(test)]
mod tests;
