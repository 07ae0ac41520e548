//! The cone: x² + y² = (r/h)²·(z − h)² for 0 ≤ z ≤ h (apex at z = h), swept to `phimax`.

use super::hit::{ShapeHit, SurfaceInteraction};
use super::placement::{Placement, phi_of, quadric_error, quadric_hit, quadric_t};
use crate::math::{Bounds3, Vec2, Vec3, normalize, solve_quadratic};
use crate::ray::Ray;

/// pbrt's cone around the object-space z axis: base circle of radius `r` at z = 0, apex at
/// z = `h`, open at the base.
#[derive(Clone, Debug, PartialEq)]
pub struct Cone {
    /// Radius of the base.
    pub radius: f32,
    /// Height of the apex.
    pub height: f32,
    /// Sweep angle, radians.
    pub phi_max: f32,
    /// Placement in the world.
    pub placement: Placement,
}

impl Cone {
    /// pbrt's cone (`radius`, `height`, `phimax` in degrees).
    pub fn new(placement: Placement, radius: f32, height: f32, phi_max_deg: f32) -> Cone {
        Cone {
            radius,
            height,
            phi_max: phi_max_deg.clamp(0.0, 360.0).to_radians(),
            placement,
        }
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        let b = Bounds3::new(
            Vec3::new(-self.radius, -self.radius, 0.0),
            Vec3::new(self.radius, self.radius, self.height),
        );
        self.placement.to_world.bounds(&b)
    }

    /// Nearest hit: with k = (r/h)², the roots of
    /// (dx² + dy² − k·dz²)t² + 2(dx·ox + dy·oy − k·dz·(oz − h))t + ox² + oy² − k(oz − h)² = 0
    /// (pbrt-v3 §3.9.1), kept when 0 ≤ z ≤ h and φ ≤ φmax.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        let (r, h) = (self.radius as f64, self.height as f64);
        let k = (r / h) * (r / h);
        let oz = o.z - h;
        let a = d.x * d.x + d.y * d.y - k * d.z * d.z;
        let b = 2.0 * (d.x * o.x + d.y * o.y - k * d.z * oz);
        let c = o.x * o.x + o.y * o.y - k * oz * oz;
        let (t0, t1) = solve_quadratic(a, b, c)?;
        let t_max = ray.t_max as f64;
        for t in [t0, t1] {
            if t <= 0.0 || t >= t_max {
                continue;
            }
            let p = o + t * d;
            if p.z < 0.0 || p.z > h || phi_of(p) > self.phi_max as f64 {
                continue;
            }
            return Some(quadric_hit(t));
        }
        None
    }

    /// Full interaction: u = φ/φmax, v = z/h, ∂p/∂u = (−φmax·y, φmax·x, 0),
    /// ∂p/∂v = (−x/(1 − v), −y/(1 − v), h); the normal ∂p/∂u × ∂p/∂v points away from the axis.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (o, d) = self.placement.object_ray(ray);
        let t = quadric_t(hit);
        let p64 = o + t * d;
        let phi = phi_of(p64) as f32;
        let p = p64.as_vec3a();
        let u = phi / self.phi_max;
        let v = (p.z / self.height).clamp(0.0, 1.0);
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        // At the apex (v = 1) ∂p/∂v is undefined; use the generator through φ instead.
        let dpdv = if v < 1.0 - 1e-6 {
            Vec3::new(-p.x / (1.0 - v), -p.y / (1.0 - v), self.height)
        } else {
            Vec3::new(
                -self.radius * phi.cos(),
                -self.radius * phi.sin(),
                self.height,
            )
        };
        SurfaceInteraction::from_object(
            &self.placement.to_world,
            p,
            quadric_error(o, d, t, p),
            Vec2::new(u, v),
            dpdu,
            dpdv,
            self.placement.flip_normal,
            -normalize(ray.d),
            hit.t,
        )
    }

    /// Surface area A = φmax/2 · r·√(h² + r²) (a sector of the unrolled cone), object space.
    pub fn object_area(&self) -> f32 {
        0.5 * self.phi_max * self.radius * self.height.hypot(self.radius)
    }

    /// A point uniform by area and its outward normal, object space. The area element is
    /// proportional to the distance from the apex, so ρ = r·√u₀ (v = 1 − √u₀) and φ = u₁·φmax;
    /// the normal (h·cos φ, h·sin φ, r)/√(h² + r²) is ∂p/∂u × ∂p/∂v normalised.
    pub fn sample_object(&self, u: Vec2) -> (Vec3, Vec3) {
        let s = u.x.sqrt();
        let rho = self.radius * s;
        let z = self.height * (1.0 - s);
        let phi = u.y * self.phi_max;
        let (sin, cos) = phi.sin_cos();
        let p = Vec3::new(rho * cos, rho * sin, z);
        let n = normalize(Vec3::new(self.height * cos, self.height * sin, self.radius));
        (p, n)
    }
}
