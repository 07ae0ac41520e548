//! The sphere: x² + y² + z² = r², optionally cut by `zmin`/`zmax` and swept to `phimax`.

use super::hit::{ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind, positive};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::{LocalHit, Placement, phi_of};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, PackedVec3, Vec2, Vec3, gamma};
use crate::ray::Ray;
use glam::DVec3;

/// pbrt's `sphere` as a scene gives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereDesc {
    /// Radius.
    pub radius: f32,
    /// Lowest z kept.
    pub z_min: f32,
    /// Highest z kept.
    pub z_max: f32,
    /// Sweep, degrees.
    pub phi_max: f32,
}

impl GeometryKind for SphereDesc {
    type Prim = Box<Sphere>;

    fn pbrt_name(&self) -> &'static str {
        "sphere"
    }

    /// The radius positive.
    fn validate(&self) -> Result<(), RuleError> {
        positive(self.radius, &["radius"], "radius")
    }

    fn build(
        &self,
        at: &mut Placing<'_>,
        out: &mut impl Extend<Box<Sphere>>,
    ) -> Result<(), String> {
        let s = Sphere::new(
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

    /// True when nothing is cut away: the full z range and the full sweep.
    #[inline]
    pub fn is_whole(&self) -> bool {
        self.z_min <= -self.radius
            && self.z_max >= self.radius
            && self.phi_max >= 2.0 * std::f32::consts::PI
    }

    /// Whether the cuts keep the point at `t` along the object-space ray (`o`, `d`).
    #[inline]
    fn keeps(&self, o: DVec3, d: DVec3, t: f64) -> bool {
        let (p, phi) = self.point_at(o, d, t);
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
        // A clear miss needs no square roots: |v|² beyond r² by more than any rounding of
        // |v| = √(v·v) could undo means |v| > r, a negative discriminant. (Only misses are
        // turned away here; every other ray takes the same steps as before.)
        let len2 = v.length_squared();
        if len2 > r * r * (1.0 + 1e-12) {
            return None;
        }
        let len = len2.sqrt();
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
        // A whole sphere cuts nothing away: the nearer root in range is the hit, and the
        // point and its φ (an f64 atan2) are left for the interaction.
        let whole = self.is_whole();
        for t in [t0, t1] {
            if t <= 0.0 || t >= t_max {
                continue;
            }
            if whole || self.keeps(o, d, t) {
                return Some(ShapeHit {
                    t: t as f32,
                    u: 0.0,
                    v: 0.0,
                });
            }
        }
        None
    }

    /// The object-space hit: u = φ/φmax, v = (θ − θ_zmin)/(θ_zmax − θ_zmin),
    /// ∂p/∂u = (−φmax·y, φmax·x, 0), ∂p/∂v = (θ_zmax − θ_zmin)(z cos φ, z sin φ, −r sin θ).
    #[inline(always)]
    fn local(&self, ray: &Ray, hit: &ShapeHit) -> LocalHit {
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
        LocalHit {
            p,
            p_error: gamma(5) * p.abs(),
            uv: Vec2::new(u, v),
            dpdu,
            dpdv,
        }
    }

    /// Full interaction: the object-space hit ((u, v), ∂p/∂u, ∂p/∂v as `local` has them)
    /// placed in the world.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        self.placement.interaction(self.local(ray, hit), ray, hit.t)
    }

    /// ∂n/∂u, ∂n/∂v at the hit, object space, by the Weingarten equations
    /// ([`LocalHit::swept_normal_derivatives`])
    /// with ∂²p/∂u² = −φmax²·(x, y, 0), ∂²p/∂u∂v = Δθ·z·φmax·(−sin φ, cos φ, 0) and
    /// ∂²p/∂v² = −Δθ²·p, Δθ = θ_zmax − θ_zmin (pbrt-v4's `Sphere`).
    pub(crate) fn normal_derivatives(&self, ray: &Ray, hit: &ShapeHit) -> (Vec3, Vec3) {
        let l = self.local(ray, hit);
        let p = l.p;
        let z_radius = (p.x * p.x + p.y * p.y).sqrt();
        let (cos_phi, sin_phi) = (p.x / z_radius, p.y / z_radius);
        let dtheta = self.theta_z_max - self.theta_z_min;
        let d2pduv = dtheta * p.z * self.phi_max * Vec3::new(-sin_phi, cos_phi, 0.0);
        let d2pdvv = -dtheta * dtheta * p;
        l.swept_normal_derivatives(self.phi_max, d2pduv, d2pdvv)
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

impl ShapeKind for Sphere {
    fn bounds(&self) -> Bounds3 {
        Sphere::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Sphere::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Sphere::interaction(self, ray, hit)
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

    /// Its world centre and radius when nothing is cut away (the radius scaled by the cube root
    /// of the placement's |det|).
    fn whole_sphere(&self) -> Option<(PackedVec3, f32)> {
        let t = &self.placement.to_world;
        let scale = glam::Mat3::from_mat4(t.m).determinant().abs().cbrt();
        self.is_whole()
            .then(|| (t.point(Vec3::ZERO).into(), self.radius * scale))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Transform;
    use crate::shape::testing::{assert_near, assert_rel, identity};
    use std::f64::consts::PI;

    fn full(radius: f32) -> Sphere {
        Sphere::new(identity(), radius, -radius, radius, 360.0)
    }

    /// The hit and interaction of `ray` on `s`, which must exist.
    fn hit(s: &Sphere, ray: &Ray) -> (ShapeHit, SurfaceInteraction) {
        let h = s.intersect(ray).expect("a hit");
        (h, s.interaction(ray, &h))
    }

    #[test]
    fn ray_down_the_axis_hits_the_pole() {
        // |(0, 0, 5 − t)| = 2 at t = 3 and t = 7: the nearer root, the pole (0, 0, 2),
        // normal +z.
        let s = full(2.0);
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z);
        let (h, si) = hit(&s, &ray);
        assert_eq!(h.t, 3.0);
        assert_near(si.p, Vec3::new(0.0, 0.0, 2.0), 1e-4);
        assert_near(si.n, Vec3::Z, 1e-6);
        assert_near(si.wo, Vec3::Z, 0.0);
        // Shortened before the sphere: no hit.
        assert!(s.intersect(&Ray { t_max: 2.9, ..ray }).is_none());
        // Passing beside it (distance 3 > r): no hit.
        assert!(
            s.intersect(&Ray::new(Vec3::new(3.0, 0.0, 5.0), -Vec3::Z))
                .is_none()
        );
    }

    #[test]
    fn off_axis_hit_point_normal_and_uv() {
        // x = 1: z = √(4 − 1) = √3, t = 5 − √3 = 3.26795; n = p/r = (1/2, 0, √3/2).
        // u = φ/φmax = 0; θ = acos(√3/2) = π/6, v = (θ − π)/(0 − π) = 5/6.
        let s = full(2.0);
        let ray = Ray::new(Vec3::new(1.0, 0.0, 5.0), -Vec3::Z);
        let (h, si) = hit(&s, &ray);
        let r3 = 3f32.sqrt();
        assert!((h.t - (5.0 - r3)).abs() < 1e-6, "t {}", h.t);
        assert_near(si.p, Vec3::new(1.0, 0.0, r3), 1e-6);
        assert_near(si.n, Vec3::new(0.5, 0.0, 0.5 * r3), 1e-6);
        assert!((si.uv.x - 0.0).abs() < 1e-6 && (si.uv.y - 5.0 / 6.0).abs() < 1e-5);
        // ∂p/∂u = φmax·(−y, x, 0) = (0, 2π, 0).
        assert_near(
            si.dpdu,
            Vec3::new(0.0, 2.0 * std::f32::consts::PI, 0.0),
            1e-5,
        );
    }

    #[test]
    fn cuts_in_z_and_phi_let_the_far_side_show() {
        // z ≤ 0.5 cuts the north pole away: the ray down the axis goes on to the south pole,
        // t = 5 + 1 = 6, outward normal −z.
        let s = Sphere::new(identity(), 1.0, -1.0, 0.5, 360.0);
        let (h, si) = hit(&s, &Ray::new(Vec3::new(0.0, 0.0, 5.0), -Vec3::Z));
        assert_eq!(h.t, 6.0);
        assert_near(si.n, -Vec3::Z, 1e-6);
        // φmax = 90°: along −x at y = 0.5 the near hit (√0.75, 0.5, 0) is at φ = 30°,
        // t = 5 − √0.75 = 4.13397, u = 30/90; at y = −0.5 both roots (φ = 330°, 210°) are cut.
        let q = Sphere::new(identity(), 1.0, -1.0, 1.0, 90.0);
        let c = 0.75f32.sqrt();
        let (h, si) = hit(&q, &Ray::new(Vec3::new(5.0, 0.5, 0.0), -Vec3::X));
        assert!((h.t - (5.0 - c)).abs() < 1e-6);
        assert!((si.uv.x - 1.0 / 3.0).abs() < 1e-5, "u {}", si.uv.x);
        assert!(
            q.intersect(&Ray::new(Vec3::new(5.0, -0.5, 0.0), -Vec3::X))
                .is_none()
        );
        // Along +x at y = 0.5 the near root (φ = 150°) is cut: the far one, seen from inside,
        // t = 5 + √0.75, keeps the outward normal (√0.75, 0.5, 0).
        let (h, si) = hit(&q, &Ray::new(Vec3::new(-5.0, 0.5, 0.0), Vec3::X));
        assert!((h.t - (5.0 + c)).abs() < 1e-5);
        assert_near(si.n, Vec3::new(c, 0.5, 0.0), 1e-5);
    }

    #[test]
    fn placement_moves_the_sphere_and_reverse_orientation_flips_the_normal() {
        // Radius 1 scaled by 2 about (1, 2, 3): the top is at z = 5, t = 10 − 5 = 5.
        let xf = Transform::translate(Vec3::new(1.0, 2.0, 3.0))
            * Transform::scale(Vec3::splat(2.0)).unwrap();
        let ray = Ray::new(Vec3::new(1.0, 2.0, 10.0), -Vec3::Z);
        for (reverse, n) in [(false, Vec3::Z), (true, -Vec3::Z)] {
            let s = Sphere::new(Placement::new(xf, reverse), 1.0, -1.0, 1.0, 360.0);
            let (h, si) = hit(&s, &ray);
            assert!((h.t - 5.0).abs() < 1e-5);
            // The pole is nudged off the axis by 10⁻⁵·r in object space (φ is undefined there).
            assert_near(si.p, Vec3::new(1.0, 2.0, 5.0), 3e-5);
            assert_near(si.n, n, 1e-5);
        }
    }

    #[test]
    fn areas_full_and_partial() {
        // Full sphere of radius 2: 4π·r² = 16π = φmax·r·(zmax − zmin) = 2π·2·4.
        assert_rel(full(2.0).object_area(), 16.0 * PI, 1e-6);
        // A zone −1 ≤ z ≤ 1 of a quarter sweep: (π/2)·2·2 = 2π.
        assert_rel(
            Sphere::new(identity(), 2.0, -1.0, 1.0, 90.0).object_area(),
            2.0 * PI,
            1e-6,
        );
        // z limits beyond the sphere are clamped to ±r: a hemisphere, 2π·r² = 2π.
        assert_rel(
            Sphere::new(identity(), 1.0, 0.0, 7.0, 360.0).object_area(),
            2.0 * PI,
            1e-6,
        );
    }

    #[test]
    fn samples_lie_on_the_zone_with_outward_normals() {
        // u = (½, ½) on the full sphere of radius 2: z = −2 + ½·4 = 0, φ = π: (−2, 0, 0).
        let s = full(2.0);
        let (p, n) = s.sample_object(Vec2::new(0.5, 0.5));
        assert_near(p, Vec3::new(-2.0, 0.0, 0.0), 1e-5);
        assert_near(n, -Vec3::X, 1e-6);
        // Every sample of a cut sphere is on it, inside the cuts, with n = p/r.
        let q = Sphere::new(identity(), 1.5, -0.5, 1.0, 120.0);
        for i in 0..64 {
            let u = Vec2::new((i % 8) as f32 / 8.0 + 0.01, (i / 8) as f32 / 8.0 + 0.01);
            let (p, n) = q.sample_object(u);
            assert!((p.length() - 1.5).abs() < 1e-5, "{p}");
            assert!((-0.5..=1.0).contains(&p.z), "{p}");
            assert!(phi_of(p.as_dvec3()) <= 120f64.to_radians() + 1e-6, "{p}");
            assert_near(n, p / 1.5, 1e-6);
        }
    }
}
