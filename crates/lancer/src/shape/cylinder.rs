//! The cylinder: x² + y² = r² between `zmin` and `zmax`, swept to `phimax` (open ends).

use super::hit::{ShapeHit, SurfaceInteraction};
use super::placement::{Placement, phi_of};
use crate::math::{Bounds3, Vec2, Vec3, gamma, normalize};
use crate::ray::Ray;

/// An open cylinder around the object-space z axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    /// Radius.
    pub radius: f32,
    /// Bottom.
    pub z_min: f32,
    /// Top.
    pub z_max: f32,
    /// Sweep angle, radians.
    pub phi_max: f32,
    /// Placement in the world.
    pub placement: Placement,
}

impl Cylinder {
    /// pbrt's cylinder (`radius`, `zmin`, `zmax`, `phimax` in degrees).
    pub fn new(
        placement: Placement,
        radius: f32,
        z_min: f32,
        z_max: f32,
        phi_max_deg: f32,
    ) -> Cylinder {
        Cylinder {
            radius,
            z_min: z_min.min(z_max),
            z_max: z_min.max(z_max),
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

    /// Nearest hit: roots of (dx² + dy²)t² + 2(dx·ox + dy·oy)t + ox² + oy² − r² = 0, with the
    /// discriminant in the cancellation-free form 4a(r + |v|)(r − |v|) as for the sphere.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        let r = self.radius as f64;
        let a = d.x * d.x + d.y * d.y;
        if a == 0.0 {
            return None;
        }
        let b = 2.0 * (d.x * o.x + d.y * o.y);
        let c = o.x * o.x + o.y * o.y - r * r;
        let f = b / (2.0 * a);
        let (vx, vy) = (o.x - f * d.x, o.y - f * d.y);
        let len = (vx * vx + vy * vy).sqrt();
        let discrim = 4.0 * a * (r + len) * (r - len);
        if discrim < 0.0 {
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
        for t in [t0, t1] {
            if t <= 0.0 || t >= t_max {
                continue;
            }
            let p = o + t * d;
            if p.z < self.z_min as f64 || p.z > self.z_max as f64 {
                continue;
            }
            if phi_of(p) > self.phi_max as f64 {
                continue;
            }
            return Some(ShapeHit {
                t: t as f32,
                u: 0.0,
                v: 0.0,
            });
        }
        None
    }

    /// Full interaction: u = φ/φmax, v = (z − zmin)/(zmax − zmin), ∂p/∂u = (−φmax·y, φmax·x, 0),
    /// ∂p/∂v = (0, 0, zmax − zmin).
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (o, d) = self.placement.object_ray(ray);
        let mut p = o + hit.t as f64 * d;
        let hit_rad = (p.x * p.x + p.y * p.y).sqrt();
        p.x *= self.radius as f64 / hit_rad;
        p.y *= self.radius as f64 / hit_rad;
        let phi = phi_of(p) as f32;
        let p = p.as_vec3a();
        let u = phi / self.phi_max;
        let v = (p.z - self.z_min) / (self.z_max - self.z_min);
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        let dpdv = Vec3::new(0.0, 0.0, self.z_max - self.z_min);
        let p_err = gamma(3) * Vec3::new(p.x, p.y, 0.0).abs();
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

    /// Surface area, object space: A = (zmax − zmin)·r·φmax.
    pub fn object_area(&self) -> f32 {
        (self.z_max - self.z_min) * self.radius * self.phi_max
    }

    /// A point uniform by area and its outward normal (x, y, 0)/r, object space: z uniform in
    /// [zmin, zmax], φ = u₁·φmax.
    pub fn sample_object(&self, u: Vec2) -> (Vec3, Vec3) {
        let z = self.z_min + u.x * (self.z_max - self.z_min);
        let phi = u.y * self.phi_max;
        let (x, y) = (self.radius * phi.cos(), self.radius * phi.sin());
        (Vec3::new(x, y, z), Vec3::new(x, y, 0.0) / self.radius)
    }
}
