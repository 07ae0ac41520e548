//! The paraboloid: z = zmax·(x² + y²)/r² between `zmin` and `zmax`, swept to `phimax`.

use super::hit::{ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind, positive};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::{LocalHit, Placement, phi_of, quadric_error, quadric_hit, quadric_t};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Vec2, Vec3, solve_quadratic};
use crate::ray::Ray;

/// pbrt's `paraboloid` as a scene gives it: z = zmax·(x² + y²)/radius², cut to [zmin, zmax].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParaboloidDesc {
    /// Radius at `z_max`.
    pub radius: f32,
    /// Bottom.
    pub z_min: f32,
    /// Top (positive).
    pub z_max: f32,
    /// Sweep, degrees.
    pub phi_max: f32,
}

impl GeometryKind for ParaboloidDesc {
    type Prim = Box<Paraboloid>;

    fn pbrt_name(&self) -> &'static str {
        "paraboloid"
    }

    /// The radius and the top positive.
    fn validate(&self) -> Result<(), RuleError> {
        positive(self.radius, &["radius"], "radius")?;
        positive(self.z_max, &["z_max"], "zmax")
    }

    fn build(
        &self,
        at: &mut Placing<'_>,
        out: &mut impl Extend<Box<Paraboloid>>,
    ) -> Result<(), String> {
        let s = Paraboloid::new(
            at.placement(),
            self.radius,
            self.z_min,
            self.z_min.max(self.z_max),
            self.phi_max,
        );
        out.extend([Box::new(s)]);
        Ok(())
    }
}

/// pbrt's paraboloid around the object-space z axis: its rim of radius `r` is at z = `zmax`,
/// its apex at the origin; the part with `zmin ≤ z ≤ zmax` is kept.
#[derive(Clone, Debug, PartialEq)]
pub struct Paraboloid {
    /// Radius at `z_max`.
    pub radius: f32,
    /// Lowest z kept (at least 0).
    pub z_min: f32,
    /// Highest z kept (positive).
    pub z_max: f32,
    /// Sweep angle, radians.
    pub phi_max: f32,
    /// Placement in the world.
    pub placement: Placement,
}

impl Paraboloid {
    /// pbrt's paraboloid (`radius`, `zmin`, `zmax`, `phimax` in degrees); `z_max` must be
    /// positive, `z_min` is clamped to `[0, z_max]`.
    pub fn new(
        placement: Placement,
        radius: f32,
        z_min: f32,
        z_max: f32,
        phi_max_deg: f32,
    ) -> Paraboloid {
        let (lo, hi) = (z_min.min(z_max), z_min.max(z_max));
        Paraboloid {
            radius,
            z_min: lo.clamp(0.0, hi),
            z_max: hi,
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

    /// k = zmax/r², the paraboloid being z = k(x² + y²).
    #[inline]
    fn k(&self) -> f64 {
        self.z_max as f64 / (self.radius as f64 * self.radius as f64)
    }

    /// Nearest hit: with k = zmax/r², the roots of
    /// k(dx² + dy²)t² + (2k(dx·ox + dy·oy) − dz)t + k(ox² + oy²) − oz = 0 (pbrt-v3 §3.9.2),
    /// kept when zmin ≤ z ≤ zmax and φ ≤ φmax.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        let k = self.k();
        let a = k * (d.x * d.x + d.y * d.y);
        let b = 2.0 * k * (d.x * o.x + d.y * o.y) - d.z;
        let c = k * (o.x * o.x + o.y * o.y) - o.z;
        let (t0, t1) = solve_quadratic(a, b, c)?;
        let t_max = ray.t_max as f64;
        for t in [t0, t1] {
            if t <= 0.0 || t >= t_max {
                continue;
            }
            let p = o + t * d;
            if p.z < self.z_min as f64 || p.z > self.z_max as f64 || phi_of(p) > self.phi_max as f64
            {
                continue;
            }
            return Some(quadric_hit(t));
        }
        None
    }

    /// The object-space hit: u = φ/φmax, v = (z − zmin)/(zmax − zmin),
    /// ∂p/∂u = (−φmax·y, φmax·x, 0), ∂p/∂v = (zmax − zmin)·(x/2z, y/2z, 1); the normal
    /// ∂p/∂u × ∂p/∂v points away from the axis (out of the bowl).
    #[inline(always)]
    fn local(&self, ray: &Ray, hit: &ShapeHit) -> LocalHit {
        let (o, d) = self.placement.object_ray(ray);
        let t = quadric_t(hit);
        let p64 = o + t * d;
        let phi = phi_of(p64) as f32;
        let p = p64.as_vec3a();
        let u = phi / self.phi_max;
        let dz = self.z_max - self.z_min;
        let v = (p.z - self.z_min) / dz;
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        // (x, y)/(2z) with z = kρ² written as (x, y)/(2kρ²); at the apex itself (ρ = 0) the
        // derivative is undefined and ∂p/∂v is taken along z.
        let k = self.k() as f32;
        let rho2 = p.x * p.x + p.y * p.y;
        let dpdv = if rho2 > 0.0 {
            dz * Vec3::new(p.x / (2.0 * k * rho2), p.y / (2.0 * k * rho2), 1.0)
        } else {
            dz * Vec3::Z
        };
        LocalHit {
            p,
            p_error: quadric_error(o, d, t, p),
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
    /// with pbrt-v3's `Paraboloid`, Δz = zmax − zmin: ∂²p/∂u² = −φmax²·(x, y, 0),
    /// ∂²p/∂u∂v = Δz·φmax·(−y/2z, x/2z, 0), ∂²p/∂v² = −Δz²·(x/4z², y/4z², 0) (zero at the
    /// apex, where ∂p/∂v is taken along z).
    pub(crate) fn normal_derivatives(&self, ray: &Ray, hit: &ShapeHit) -> (Vec3, Vec3) {
        let l = self.local(ray, hit);
        let p = l.p;
        let dz = self.z_max - self.z_min;
        let (d2pduv, d2pdvv) = if p.x * p.x + p.y * p.y > 0.0 {
            (
                dz * self.phi_max * Vec3::new(-p.y / (2.0 * p.z), p.x / (2.0 * p.z), 0.0),
                -dz * dz * Vec3::new(p.x / (4.0 * p.z * p.z), p.y / (4.0 * p.z * p.z), 0.0),
            )
        } else {
            (Vec3::ZERO, Vec3::ZERO)
        };
        l.swept_normal_derivatives(self.phi_max, d2pduv, d2pdvv)
    }

    /// Surface area, object space: with z = kρ², dA = ρ·√(1 + 4k²ρ²) dρ dφ, so
    /// A = φmax/(12k²)·[(1 + 4k·zmax)^{3/2} − (1 + 4k·zmin)^{3/2}].
    pub fn object_area(&self) -> f32 {
        let k = self.k();
        let f = |z: f64| (1.0 + 4.0 * k * z).powf(1.5);
        (self.phi_max as f64 / (12.0 * k * k) * (f(self.z_max as f64) - f(self.z_min as f64)))
            as f32
    }

    /// A point uniform by area and its outward normal, object space. The area between the
    /// apex and height z is ∝ (1 + 4kz)^{3/2} − 1, so inverting the CDF gives
    /// 1 + 4kz = [(1 + 4k·zmin)^{3/2} + u₀·((1 + 4k·zmax)^{3/2} − (1 + 4k·zmin)^{3/2})]^{2/3};
    /// φ = u₁·φmax. The normal is ∂p/∂u × ∂p/∂v normalised: ∝ (x, y, −1/(2k)).
    pub fn sample_object(&self, u: Vec2) -> (Vec3, Vec3) {
        let k = self.k();
        let f = |z: f64| (1.0 + 4.0 * k * z).powf(1.5);
        let (f0, f1) = (f(self.z_min as f64), f(self.z_max as f64));
        let g = (f0 + u.x as f64 * (f1 - f0)).powf(2.0 / 3.0);
        let z = ((g - 1.0) / (4.0 * k)).clamp(self.z_min as f64, self.z_max as f64);
        let rho = (z / k).sqrt();
        let phi = u.y as f64 * self.phi_max as f64;
        let (sin, cos) = phi.sin_cos();
        let p = glam::DVec3::new(rho * cos, rho * sin, z);
        let n = glam::DVec3::new(p.x, p.y, -0.5 / k).normalize();
        (p.as_vec3a(), n.as_vec3a())
    }
}

impl ShapeKind for Paraboloid {
    /// The two distances added in double precision ([`quadric_t`]).
    fn hit_after(&self, first: &ShapeHit, next: &ShapeHit) -> ShapeHit {
        quadric_hit(quadric_t(first) + quadric_t(next))
    }

    fn bounds(&self) -> Bounds3 {
        Paraboloid::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Paraboloid::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Paraboloid::interaction(self, ray, hit)
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
    use crate::shape::testing::{assert_cut_away, assert_near, assert_rel, identity};
    use glam::DVec3;
    use std::f64::consts::PI;

    /// z = x² + y² for 0 ≤ z ≤ 1 (r = 1, k = zmax/r² = 1).
    fn bowl() -> Paraboloid {
        Paraboloid::new(identity(), 1.0, 0.0, 1.0, 360.0)
    }

    #[test]
    fn hits_points_normals_and_uv() {
        let q = bowl();
        // Down at x = ½: z = ¼, t = 5 − ¼ = 4.75 (a = 0, the linear root). The normal
        // ∂p/∂u × ∂p/∂v ∝ (x, y, −1/(2k)) = (½, 0, −½): out of the bowl.
        let ray = Ray::new(Vec3::new(0.5, 0.0, 5.0), -Vec3::Z);
        let h = q.intersect(&ray).unwrap();
        assert!((h.t - 4.75).abs() < 1e-6);
        let si = q.interaction(&ray, &h);
        assert_near(si.p, Vec3::new(0.5, 0.0, 0.25), 1e-6);
        assert_near(si.n, Vec3::new(1.0, 0.0, -1.0) / 2f32.sqrt(), 1e-6);
        assert!(si.uv.x.abs() < 1e-6 && (si.uv.y - 0.25).abs() < 1e-6);
        // Along +x at z = ¼: t² − 10t + 24.75 = 0, t = 4.5, p = (−½, 0, ¼), φ = π (u = ½).
        // ∂p/∂u = (0, −π, 0), ∂p/∂v = (x/(2kρ²), 0, 1) = (−1, 0, 1): n ∝ (−1, 0, −1).
        let ray = Ray::new(Vec3::new(-5.0, 0.0, 0.25), Vec3::X);
        let h = q.intersect(&ray).unwrap();
        assert!((h.t - 4.5).abs() < 1e-6);
        let si = q.interaction(&ray, &h);
        assert_near(si.p, Vec3::new(-0.5, 0.0, 0.25), 1e-6);
        assert_near(si.n, Vec3::new(-1.0, 0.0, -1.0) / 2f32.sqrt(), 1e-6);
        assert!((si.uv.x - 0.5).abs() < 1e-6 && (si.uv.y - 0.25).abs() < 1e-6);
    }

    #[test]
    fn rays_outside_the_cuts_miss() {
        // z = x² + y² cut to ¼ ≤ z ≤ 1; ∇F = (2kx, 2ky, −1) for F = k(x² + y²) − z.
        let q = Paraboloid::new(identity(), 1.0, 0.25, 1.0, 360.0);
        for p in [DVec3::new(1.2, 0.0, 1.44), DVec3::new(0.0, 0.3, 0.09)] {
            assert!(
                (p.x * p.x + p.y * p.y - p.z).abs() < 1e-9,
                "{p} is not on it"
            );
            let grad = DVec3::new(2.0 * p.x, 2.0 * p.y, -1.0);
            assert_cut_away(p, grad, |r| q.intersect(r).map(|h| q.interaction(r, &h).p));
        }
    }

    #[test]
    fn areas_in_closed_form_and_by_quadrature() {
        // z = ρ² up to z = 1: A = 2π∫₀¹ ρ√(1 + 4ρ²) dρ = π/6·(5√5 − 1).
        assert_rel(
            bowl().object_area(),
            PI / 6.0 * (5.0 * 5f64.sqrt() - 1.0),
            1e-6,
        );
        // A cut, partial one (r = 0.7, 0.3 ≤ z ≤ 1.4, 290°) against the midpoint rule on
        // A = φmax·∫ ρ√(1 + 4k²ρ²) dρ from ρ = √(zmin/k) to r.
        let q = Paraboloid::new(identity(), 0.7, 0.3, 1.4, 290.0);
        let k = 1.4 / 0.49;
        let (lo, hi, n) = ((0.3f64 / k).sqrt(), 0.7, 100_000);
        let step = (hi - lo) / n as f64;
        let integral: f64 = (0..n)
            .map(|i| {
                let rho = lo + (i as f64 + 0.5) * step;
                rho * (1.0 + 4.0 * k * k * rho * rho).sqrt() * step
            })
            .sum();
        assert_rel(q.object_area(), 290f64.to_radians() * integral, 1e-5);
    }

    #[test]
    fn samples_span_apex_to_rim() {
        // u₀ = 0 is the apex (normal −z, out of the bowl), u₀ = 1 the rim at φ = 0:
        // (1, 0, 1), n ∝ (1, 0, −½).
        let (p, n) = bowl().sample_object(Vec2::new(0.0, 0.0));
        assert_near(p, Vec3::ZERO, 1e-6);
        assert_near(n, -Vec3::Z, 1e-6);
        let (p, n) = bowl().sample_object(Vec2::new(1.0, 0.0));
        assert_near(p, Vec3::new(1.0, 0.0, 1.0), 1e-5);
        assert_near(n, Vec3::new(2.0, 0.0, -1.0) / 5f32.sqrt(), 1e-5);
    }
}
