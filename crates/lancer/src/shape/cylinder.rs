//! The cylinder: x² + y² = r² between `zmin` and `zmax`, swept to `phimax` (open ends).

use super::hit::{ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind, positive};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::{LocalHit, Placement, phi_of};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Vec2, Vec3, gamma};
use crate::ray::Ray;

/// pbrt's `cylinder` as a scene gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CylinderDesc {
    /// Radius.
    pub radius: f32,
    /// Bottom.
    pub z_min: f32,
    /// Top.
    pub z_max: f32,
    /// Sweep, degrees.
    pub phi_max: f32,
}

impl GeometryKind for CylinderDesc {
    type Prim = Box<Cylinder>;

    fn pbrt_name(&self) -> &'static str {
        "cylinder"
    }

    /// The radius positive.
    fn validate(&self) -> Result<(), RuleError> {
        positive(self.radius, &["radius"], "radius")
    }

    fn build(
        &self,
        at: &mut Placing<'_>,
        out: &mut impl Extend<Box<Cylinder>>,
    ) -> Result<(), String> {
        let s = Cylinder::new(
            at.placement(),
            self.radius,
            self.z_min,
            self.z_max,
            self.phi_max,
        );
        out.extend([Box::new(s)]);
        Ok(())
    }
}

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

    /// The object-space hit: u = φ/φmax, v = (z − zmin)/(zmax − zmin),
    /// ∂p/∂u = (−φmax·y, φmax·x, 0), ∂p/∂v = (0, 0, zmax − zmin).
    #[inline(always)]
    fn local(&self, ray: &Ray, hit: &ShapeHit) -> LocalHit {
        let (o, d) = self.placement.object_ray(ray);
        let mut p = o + hit.t as f64 * d;
        let hit_rad = (p.x * p.x + p.y * p.y).sqrt();
        p.x *= self.radius as f64 / hit_rad;
        p.y *= self.radius as f64 / hit_rad;
        let phi = phi_of(p) as f32;
        let p = p.as_vec3a();
        let u = phi / self.phi_max;
        let v = (p.z - self.z_min) / (self.z_max - self.z_min);
        LocalHit {
            p,
            p_error: gamma(3) * Vec3::new(p.x, p.y, 0.0).abs(),
            uv: Vec2::new(u, v),
            dpdu: Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0),
            dpdv: Vec3::new(0.0, 0.0, self.z_max - self.z_min),
        }
    }

    /// Full interaction: the object-space hit ((u, v), ∂p/∂u, ∂p/∂v as `local` has them)
    /// placed in the world.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        self.placement.interaction(self.local(ray, hit), ray, hit.t)
    }

    /// ∂n/∂u, ∂n/∂v at the hit, object space, by the Weingarten equations
    /// ([`LocalHit::swept_normal_derivatives`])
    /// with ∂²p/∂u² = −φmax²·(x, y, 0) and ∂²p/∂u∂v = ∂²p/∂v² = 0 (pbrt-v4's `Cylinder`).
    pub(crate) fn normal_derivatives(&self, ray: &Ray, hit: &ShapeHit) -> (Vec3, Vec3) {
        self.local(ray, hit)
            .swept_normal_derivatives(self.phi_max, Vec3::ZERO, Vec3::ZERO)
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

impl ShapeKind for Cylinder {
    fn bounds(&self) -> Bounds3 {
        Cylinder::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Cylinder::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Cylinder::interaction(self, ray, hit)
    }

    fn shading_derivatives(
        &self,
        ray: &Ray,
        hit: &ShapeHit,
        _: &[TriangleMesh],
        si: &SurfaceInteraction,
    ) -> ShadingDerivatives {
        self.placement
            .derivatives(si, self.normal_derivatives(ray, hit))
    }

    /// The object-space area scaled by the placement.
    fn area(&self) -> f32 {
        self.object_area() * self.placement.area_scale()
    }

    /// A point sampled in object space, then placed.
    fn sample_area(&self, u: Vec2, _: &[TriangleMesh]) -> Option<ShapeSample> {
        let (p, n) = self.sample_object(u);
        Some(self.placement.place(p, n))
    }

    /// The object-space area, as pbrt-v4's quadrics.
    fn emission_area(&self) -> f32 {
        self.object_area()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::testing::{assert_near, assert_rel, identity};
    use std::f64::consts::PI;

    /// Radius 1 between z = −1 and z = 1, swept to `phi_max` degrees.
    fn tube(phi_max: f32) -> Cylinder {
        Cylinder::new(identity(), 1.0, -1.0, 1.0, phi_max)
    }

    #[test]
    fn hit_from_outside_and_from_inside() {
        // From (5, 0, 0.5) along −x: x = 1 at t = 4, n = +x; u = 0, v = (0.5 + 1)/2 = 0.75.
        // ∂p/∂u = (0, 2π, 0) × ∂p/∂v = (0, 0, 2) = (4π, 0, 0): outward.
        let c = tube(360.0);
        let ray = Ray::new(Vec3::new(5.0, 0.0, 0.5), -Vec3::X);
        let h = c.intersect(&ray).unwrap();
        assert_eq!(h.t, 4.0);
        let si = c.interaction(&ray, &h);
        assert_near(si.p, Vec3::new(1.0, 0.0, 0.5), 1e-6);
        assert_near(si.n, Vec3::X, 1e-6);
        assert!(si.uv.x.abs() < 1e-6 && (si.uv.y - 0.75).abs() < 1e-6);
        // From the axis along +y: (0, 1, 0) at t = 1, φ = 90° (u = ¼), normal still outward.
        let inside = Ray::new(Vec3::ZERO, Vec3::Y);
        let h = c.intersect(&inside).unwrap();
        assert_eq!(h.t, 1.0);
        let si = c.interaction(&inside, &h);
        assert_near(si.n, Vec3::Y, 1e-6);
        assert!((si.uv.x - 0.25).abs() < 1e-6);
    }

    #[test]
    fn open_ends_and_cuts() {
        let c = tube(360.0);
        // Above the top: the infinite cylinder is crossed at z = 1.5, outside [−1, 1].
        assert!(
            c.intersect(&Ray::new(Vec3::new(5.0, 0.0, 1.5), -Vec3::X))
                .is_none()
        );
        // Down the axis: never meets the wall (a = dx² + dy² = 0).
        assert!(
            c.intersect(&Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z))
                .is_none()
        );
        // In through the open top, (0, 0, 3) + t(1, 0, −3): the wall x = 1 at t = 1, z = 0.
        let slant = Ray::new(Vec3::new(0.0, 0.0, 3.0), Vec3::new(1.0, 0.0, -3.0));
        let h = c.intersect(&slant).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert_near(c.interaction(&slant, &h).p, Vec3::new(1.0, 0.0, 0.0), 1e-6);
        // φmax = 180°: along +y from (0, −5, 0) the near wall (φ = 270°) is cut, the far one
        // (φ = 90°) is hit at t = 6 with its outward normal +y.
        let half = tube(180.0);
        let ray = Ray::new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y);
        let h = half.intersect(&ray).unwrap();
        assert_eq!(h.t, 6.0);
        assert_near(half.interaction(&ray, &h).n, Vec3::Y, 1e-6);
    }

    #[test]
    fn areas_full_and_partial() {
        // (zmax − zmin)·r·φmax: 2·1·2π = 4π; half a cylinder r = 0.5, 0 ≤ z ≤ 2: 2·0.5·π = π.
        assert_rel(tube(360.0).object_area(), 4.0 * PI, 1e-6);
        assert_rel(
            Cylinder::new(identity(), 0.5, 0.0, 2.0, 180.0).object_area(),
            PI,
            1e-6,
        );
    }

    #[test]
    fn samples_lie_on_the_wall() {
        // u = (¼, ½): z = −1 + ¼·2 = −0.5, φ = π: (−1, 0, −0.5), normal −x.
        let (p, n) = tube(360.0).sample_object(Vec2::new(0.25, 0.5));
        assert_near(p, Vec3::new(-1.0, 0.0, -0.5), 1e-6);
        assert_near(n, -Vec3::X, 1e-6);
    }
}
