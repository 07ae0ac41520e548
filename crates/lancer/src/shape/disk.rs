//! The disk: the plane z = h inside radius r (and outside `innerradius`), swept to `phimax`.

use super::hit::{ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind, positive};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::{Placement, phi_of};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Vec2, Vec3, cross, normalize};
use crate::ray::Ray;

/// pbrt's `disk` as a scene gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiskDesc {
    /// Height (z) of the disk.
    pub height: f32,
    /// Outer radius.
    pub radius: f32,
    /// Inner radius.
    pub inner_radius: f32,
    /// Sweep, degrees.
    pub phi_max: f32,
}

impl GeometryKind for DiskDesc {
    type Prim = Box<Disk>;

    fn pbrt_name(&self) -> &'static str {
        "disk"
    }

    /// The radius positive.
    fn validate(&self) -> Result<(), RuleError> {
        positive(self.radius, &["radius"], "radius")
    }

    fn build(&self, at: &mut Placing<'_>, out: &mut impl Extend<Box<Disk>>) -> Result<(), String> {
        let s = Disk::new(
            at.placement(),
            self.height,
            self.radius,
            self.inner_radius,
            self.phi_max,
        );
        out.extend([Box::new(s)]);
        Ok(())
    }
}

/// A disk (or annulus) at height `height` in object space, normal +z.
#[derive(Clone, Debug, PartialEq)]
pub struct Disk {
    /// z of the disk's plane.
    pub height: f32,
    /// Outer radius.
    pub radius: f32,
    /// Inner radius (a hole when > 0).
    pub inner_radius: f32,
    /// Sweep angle, radians.
    pub phi_max: f32,
    /// Placement in the world.
    pub placement: Placement,
}

impl Disk {
    /// pbrt's disk (`height`, `radius`, `innerradius`, `phimax` in degrees).
    pub fn new(
        placement: Placement,
        height: f32,
        radius: f32,
        inner_radius: f32,
        phi_max_deg: f32,
    ) -> Disk {
        Disk {
            height,
            radius,
            inner_radius: inner_radius.clamp(0.0, radius),
            phi_max: phi_max_deg.clamp(0.0, 360.0).to_radians(),
            placement,
        }
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Bounds3 {
        let b = Bounds3::new(
            Vec3::new(-self.radius, -self.radius, self.height),
            Vec3::new(self.radius, self.radius, self.height),
        );
        self.placement.to_world.bounds(&b)
    }

    /// Nearest hit: the plane z = h at t = (h − o_z)/d_z, kept if r_i² ≤ x² + y² ≤ r² and
    /// φ ≤ φmax.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        if d.z == 0.0 {
            return None;
        }
        let t = (self.height as f64 - o.z) / d.z;
        if t <= 0.0 || t >= ray.t_max as f64 {
            return None;
        }
        let p = o + t * d;
        let dist2 = p.x * p.x + p.y * p.y;
        let (r, ri) = (self.radius as f64, self.inner_radius as f64);
        if dist2 > r * r || dist2 < ri * ri {
            return None;
        }
        if self.phi_max < 2.0 * std::f32::consts::PI && phi_of(p) > self.phi_max as f64 {
            return None;
        }
        Some(ShapeHit {
            t: t as f32,
            u: 0.0,
            v: 0.0,
        })
    }

    /// Full interaction: u = φ/φmax, v = (r − r_hit)/(r − r_i), ∂p/∂u = (−φmax·y, φmax·x, 0),
    /// ∂p/∂v = (x, y, 0)(r_i − r)/r_hit. The point lies exactly on the plane (no error in z).
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (o, d) = self.placement.object_ray(ray);
        let mut p = (o + hit.t as f64 * d).as_vec3a();
        p.z = self.height;
        let dist = (p.x * p.x + p.y * p.y).sqrt();
        let u = phi_of(p.as_dvec3()) as f32 / self.phi_max;
        let v = (self.radius - dist) / (self.radius - self.inner_radius);
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        let dpdv = if dist > 0.0 {
            Vec3::new(p.x, p.y, 0.0) * (self.inner_radius - self.radius) / dist
        } else {
            Vec3::new(self.inner_radius - self.radius, 0.0, 0.0)
        };
        // At the centre ∂p/∂u vanishes; keep a tangent so the normal stays +z.
        let dpdu = if dpdu.length_squared() == 0.0 {
            Vec3::new(0.0, 1.0, 0.0) * self.phi_max
        } else {
            dpdu
        };
        let dpdv = if cross(dpdu, dpdv).length_squared() == 0.0 {
            Vec3::new(-1.0, 0.0, 0.0)
        } else {
            dpdv
        };
        SurfaceInteraction::from_object(
            &self.placement.to_world,
            p,
            Vec3::ZERO,
            Vec2::new(u, v),
            dpdu,
            dpdv,
            self.placement.flip_normal,
            -normalize(ray.d),
            hit.t,
        )
    }

    /// Surface area, object space: A = φmax/2 · (r² − rᵢ²).
    pub fn object_area(&self) -> f32 {
        0.5 * self.phi_max * (self.radius * self.radius - self.inner_radius * self.inner_radius)
    }

    /// A point uniform by area and its normal +z, object space: ρ² uniform between rᵢ² and r²
    /// is uniform by area on the annulus, φ = u₁·φmax.
    pub fn sample_object(&self, u: Vec2) -> (Vec3, Vec3) {
        let (ri2, r2) = (
            self.inner_radius * self.inner_radius,
            self.radius * self.radius,
        );
        let r = (ri2 + u.x * (r2 - ri2)).sqrt();
        let phi = u.y * self.phi_max;
        let p = Vec3::new(r * phi.cos(), r * phi.sin(), self.height);
        (p, Vec3::Z)
    }
}

impl ShapeKind for Disk {
    fn bounds(&self) -> Bounds3 {
        Disk::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Disk::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Disk::interaction(self, ray, hit)
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

    /// An annulus 0.5 ≤ ρ ≤ 2 at height 1, swept to `phi_max` degrees.
    fn annulus(phi_max: f32) -> Disk {
        Disk::new(identity(), 1.0, 2.0, 0.5, phi_max)
    }

    fn down_at(x: f32, y: f32) -> Ray {
        Ray::new(Vec3::new(x, y, 5.0), -Vec3::Z)
    }

    #[test]
    fn hit_point_normal_and_uv() {
        // From (1, 0, 5) down to the plane z = 1: t = 4, p = (1, 0, 1).
        // ∂p/∂u = (0, 2π, 0), ∂p/∂v = (1, 0, 0)·(0.5 − 2)/1 = (−1.5, 0, 0): n = +z.
        // u = φ/φmax = 0, v = (r − ρ)/(r − rᵢ) = (2 − 1)/1.5 = 2/3.
        let d = annulus(360.0);
        let ray = down_at(1.0, 0.0);
        let h = d.intersect(&ray).unwrap();
        assert_eq!(h.t, 4.0);
        let si = d.interaction(&ray, &h);
        assert_near(si.p, Vec3::new(1.0, 0.0, 1.0), 1e-6);
        assert_eq!(si.p.z, 1.0, "the point is put exactly on the plane");
        assert_near(si.n, Vec3::Z, 1e-6);
        assert!(si.uv.x.abs() < 1e-6 && (si.uv.y - 2.0 / 3.0).abs() < 1e-6);
        // From below the normal is still +z (one-sided orientation, not facing the ray).
        let up = Ray::new(Vec3::new(1.0, 0.0, -1.0), Vec3::Z);
        let h = d.intersect(&up).unwrap();
        assert_eq!(h.t, 2.0);
        assert_near(d.interaction(&up, &h).n, Vec3::Z, 1e-6);
    }

    #[test]
    fn hole_rim_sweep_and_parallel_rays_miss() {
        let d = annulus(360.0);
        assert!(d.intersect(&down_at(0.25, 0.0)).is_none(), "in the hole");
        assert!(d.intersect(&down_at(2.5, 0.0)).is_none(), "beyond the rim");
        // In the plane itself: d_z = 0.
        assert!(
            d.intersect(&Ray::new(Vec3::new(-5.0, 0.0, 1.0), Vec3::X))
                .is_none()
        );
        // φmax = 90°: (0.6, 0.8) is at φ = 53.13°, u = 53.13/90; (−1, 0) at 180° is cut.
        let q = annulus(90.0);
        let ray = down_at(0.6, 0.8);
        let h = q.intersect(&ray).unwrap();
        let u = q.interaction(&ray, &h).uv.x;
        assert!(
            (u - 0.8f32.atan2(0.6).to_degrees() / 90.0).abs() < 1e-5,
            "u {u}"
        );
        assert!(q.intersect(&down_at(-1.0, 0.0)).is_none());
    }

    #[test]
    fn areas_full_and_partial() {
        // φmax/2·(r² − rᵢ²): π·(4 − 0.25) = 3.75π, a quarter of it for 90°.
        assert_rel(annulus(360.0).object_area(), 3.75 * PI, 1e-6);
        assert_rel(annulus(90.0).object_area(), 0.9375 * PI, 1e-6);
        // A plain disk of radius 1: π.
        assert_rel(
            Disk::new(identity(), 0.0, 1.0, 0.0, 360.0).object_area(),
            PI,
            1e-6,
        );
    }

    #[test]
    fn samples_lie_on_the_annulus() {
        // u = (½, ¼): ρ = √(0.25 + ½·(4 − 0.25)) = √2.125, φ = ¼·2π = π/2.
        let d = annulus(360.0);
        let (p, n) = d.sample_object(Vec2::new(0.5, 0.25));
        assert_near(p, Vec3::new(0.0, 2.125f32.sqrt(), 1.0), 1e-5);
        assert_eq!(n, Vec3::Z);
    }
}
