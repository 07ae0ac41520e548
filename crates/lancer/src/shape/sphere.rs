//! The sphere: x² + y² + z² = r², optionally cut by `zmin`/`zmax` and swept to `phimax`.

use super::hit::{ShapeHit, SurfaceInteraction};
use super::placement::{Placement, phi_of};
use crate::math::{Bounds3, Vec2, Vec3, gamma, normalize};
use crate::ray::Ray;
use glam::DVec3;

/// A sphere of radius `r` centred at the object-space origin, keeping the part with
/// `z_min ≤ z ≤ z_max` and `0 ≤ φ ≤ φ_max`.
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    /// Radius.
    pub radius: f32,
    /// Lowest z kept.
    pub z_min: f32,
    /// Highest z kept.
    pub z_max: f32,
    /// θ at `z_min` (θ = acos(z/r)).
    theta_z_min: f32,
    /// θ at `z_max`.
    theta_z_max: f32,
    /// Sweep angle, radians.
    pub phi_max: f32,
    /// Placement in the world.
    pub placement: Placement,
}

impl Sphere {
    /// pbrt's sphere (`radius`, `zmin`, `zmax`, `phimax` in degrees).
    pub fn new(
        placement: Placement,
        radius: f32,
        z_min: f32,
        z_max: f32,
        phi_max_deg: f32,
    ) -> Sphere {
        let (lo, hi) = (z_min.min(z_max), z_min.max(z_max));
        let z_min = lo.clamp(-radius, radius);
        let z_max = hi.clamp(-radius, radius);
        Sphere {
            radius,
            z_min,
            z_max,
            theta_z_min: (z_min / radius).clamp(-1.0, 1.0).acos(),
            theta_z_max: (z_max / radius).clamp(-1.0, 1.0).acos(),
            phi_max: phi_max_deg.clamp(0.0, 360.0).to_radians(),
            placement,
        }
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        let b = Bounds3::new(
            Vec3::new(-self.radius, -self.radius, self.z_min),
            Vec3::new(self.radius, self.radius, self.z_max),
        );
        self.placement.to_world.bounds(&b)
    }

    /// The object-space point at `t` projected back onto the sphere, and its φ.
    #[inline]
    fn point_at(&self, o: DVec3, d: DVec3, t: f64) -> (DVec3, f64) {
        let mut p = o + t * d;
        p *= self.radius as f64 / p.length();
        if p.x == 0.0 && p.y == 0.0 {
            p.x = 1e-5 * self.radius as f64;
        }
        (p, phi_of(p))
    }

    #[inline]
    fn inside_cut(&self, p: DVec3, phi: f64) -> bool {
        let r = self.radius;
        !((self.z_min > -r && (p.z as f32) < self.z_min)
            || (self.z_max < r && (p.z as f32) > self.z_max)
            || phi > self.phi_max as f64)
    }

    /// Nearest hit: the roots of (d·d)t² + 2(d·o)t + o·o − r² = 0 in object space (the course's
    /// sphere equation with the centre at the origin), in double precision. The discriminant
    /// is computed as 4a(r + |v|)(r − |v|) with v = o − (b/2a)d, the foot of the perpendicular
    /// from the centre, which avoids cancellation for distant rays (PBRT-v4 §6.8.5).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        let r = self.radius as f64;
        let a = d.length_squared();
        let b = 2.0 * d.dot(o);
        let c = o.length_squared() - r * r;
        let v = o - (b / (2.0 * a)) * d;
        let len = v.length();
        let discrim = 4.0 * a * (r + len) * (r - len);
        if discrim < 0.0 || a == 0.0 {
            return None;
        }
        let root = discrim.sqrt();
        let q = if b < 0.0 {
            -0.5 * (b - root)
        } else {
            -0.5 * (b + root)
        };
        let (mut t0, mut t1) = (q / a, c / q);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let t_max = ray.t_max as f64;
        if t0 >= t_max || t1 <= 0.0 {
            return None;
        }
        for t in [t0, t1] {
            if t <= 0.0 || t >= t_max {
                continue;
            }
            let (p, phi) = self.point_at(o, d, t);
            if self.inside_cut(p, phi) {
                return Some(ShapeHit {
                    t: t as f32,
                    u: 0.0,
                    v: 0.0,
                });
            }
        }
        None
    }

    /// Full interaction: u = φ/φmax, v = (θ − θ_zmin)/(θ_zmax − θ_zmin),
    /// ∂p/∂u = (−φmax·y, φmax·x, 0), ∂p/∂v = (θ_zmax − θ_zmin)(z cos φ, z sin φ, −r sin θ).
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (o, d) = self.placement.object_ray(ray);
        let (p, phi) = self.point_at(o, d, hit.t as f64);
        let p = p.as_vec3a();
        let phi = phi as f32;
        let u = phi / self.phi_max;
        let cos_theta = (p.z / self.radius).clamp(-1.0, 1.0);
        let theta = cos_theta.acos();
        let v = (theta - self.theta_z_min) / (self.theta_z_max - self.theta_z_min);
        let z_radius = (p.x * p.x + p.y * p.y).sqrt();
        let (cos_phi, sin_phi) = (p.x / z_radius, p.y / z_radius);
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let dpdv = (self.theta_z_max - self.theta_z_min)
            * Vec3::new(p.z * cos_phi, p.z * sin_phi, -self.radius * sin_theta);
        let p_err = gamma(5) * p.abs();
        SurfaceInteraction::from_object(
            &self.placement.to_world,
            p,
            p_err,
            Vec2::new(u, v),
            dpdu,
            dpdv,
            self.placement.flip_normal,
            -normalize(ray.d),
            hit.t,
        )
    }

    /// Surface area, object space: a sphere zone's area depends only on its height,
    /// A = φmax·r·(zmax − zmin) (Archimedes).
    pub fn object_area(&self) -> f32 {
        self.phi_max * self.radius * (self.z_max - self.z_min)
    }

    /// A point uniform by area and its outward normal p/r, object space: z uniform in
    /// [zmin, zmax] and φ = u₁·φmax are uniform by area on a sphere zone (Archimedes again).
    pub fn sample_object(&self, u: Vec2) -> (Vec3, Vec3) {
        let z = self.z_min + u.x * (self.z_max - self.z_min);
        let phi = u.y * self.phi_max;
        let rho = (self.radius * self.radius - z * z).max(0.0).sqrt();
        let p = Vec3::new(rho * phi.cos(), rho * phi.sin(), z);
        (p, p / self.radius)
    }
}
