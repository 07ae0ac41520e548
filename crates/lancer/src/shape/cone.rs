//! The cone: x² + y² = (r/h)²·(z − h)² for 0 ≤ z ≤ h (apex at z = h), swept to `phimax`.

use super::hit::{ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind, positive};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::{LocalHit, Placement, phi_of, quadric_error, quadric_hit, quadric_t};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Vec2, Vec3, normalize, solve_quadratic};
use crate::ray::Ray;

/// pbrt's `cone` as a scene gives it: base radius at z = 0, apex at z = `height`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeDesc {
    /// Radius of the base.
    pub radius: f32,
    /// Height of the apex.
    pub height: f32,
    /// Sweep, degrees.
    pub phi_max: f32,
}

impl GeometryKind for ConeDesc {
    type Prim = Box<Cone>;

    fn pbrt_name(&self) -> &'static str {
        "cone"
    }

    /// The radius and the height positive.
    fn validate(&self) -> Result<(), RuleError> {
        positive(self.radius, &["radius"], "radius")?;
        positive(self.height, &["height"], "height")
    }

    fn build(&self, at: &mut Placing<'_>, out: &mut impl Extend<Box<Cone>>) -> Result<(), String> {
        let c = Cone::new(at.placement(), self.radius, self.height, self.phi_max);
        out.extend([Box::new(c)]);
        Ok(())
    }
}

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

    /// The object-space hit: u = φ/φmax, v = z/h, ∂p/∂u = (−φmax·y, φmax·x, 0),
    /// ∂p/∂v = (−x/(1 − v), −y/(1 − v), h); the normal ∂p/∂u × ∂p/∂v points away from the axis.
    #[inline(always)]
    fn local(&self, ray: &Ray, hit: &ShapeHit) -> LocalHit {
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
    /// with pbrt-v3's `Cone`: ∂²p/∂u² = −φmax²·(x, y, 0), ∂²p/∂u∂v = φmax/(1 − v)·(y, −x, 0),
    /// ∂²p/∂v² = 0 (zero at the apex, where ∂p/∂v is not that of the parameterisation).
    pub(crate) fn normal_derivatives(&self, ray: &Ray, hit: &ShapeHit) -> (Vec3, Vec3) {
        let l = self.local(ray, hit);
        let (p, uv) = (l.p, l.uv);
        let d2pduv = if uv.y < 1.0 - 1e-6 {
            self.phi_max / (1.0 - uv.y) * Vec3::new(p.y, -p.x, 0.0)
        } else {
            Vec3::ZERO
        };
        l.swept_normal_derivatives(self.phi_max, d2pduv, Vec3::ZERO)
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

impl ShapeKind for Cone {
    /// The two distances added in double precision ([`quadric_t`]).
    fn hit_after(&self, first: &ShapeHit, next: &ShapeHit) -> ShapeHit {
        quadric_hit(quadric_t(first) + quadric_t(next))
    }

    fn bounds(&self) -> Bounds3 {
        Cone::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Cone::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Cone::interaction(self, ray, hit)
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

    #[test]
    fn hit_point_normal_and_uv() {
        // r = 1, h = 2: ρ = (2 − z)/2. Along −x at z = 1 (k = ¼): t² − 10t + 24.75 = 0,
        // t = 4.5 (x = ½) or 5.5. ∂p/∂u = (0, π, 0), ∂p/∂v = (−x/(1 − v), 0, h) = (−1, 0, 2):
        // n ∝ (2π, 0, π), i.e. (2, 0, 1)/√5 (away from the axis, tilted up); uv = (0, ½).
        let c = Cone::new(identity(), 1.0, 2.0, 360.0);
        let ray = Ray::new(Vec3::new(5.0, 0.0, 1.0), -Vec3::X);
        let h = c.intersect(&ray).unwrap();
        assert!((h.t - 4.5).abs() < 1e-6);
        let si = c.interaction(&ray, &h);
        assert_near(si.p, Vec3::new(0.5, 0.0, 1.0), 1e-6);
        assert_near(si.n, Vec3::new(2.0, 0.0, 1.0) / 5f32.sqrt(), 1e-6);
        assert!(si.uv.x.abs() < 1e-6 && (si.uv.y - 0.5).abs() < 1e-6);
    }

    #[test]
    fn rays_outside_the_cuts_miss() {
        // Points of x² + y² = k(z − h)² (here k = 1, h = 1) beyond a cut, approached along
        // the gradient ∇F = (2x, 2y, −2k(z − h)).
        let grad = |p: DVec3| DVec3::new(2.0 * p.x, 2.0 * p.y, -2.0 * (p.z - 1.0));
        let cases = [
            // Below the base (z < 0), φmax = 270°.
            (270.0, DVec3::new(1.2, 0.0, -0.2)),
            // At φ = −5° = 355°, beyond the sweep.
            (
                270.0,
                DVec3::new(
                    0.5 * 5f64.to_radians().cos(),
                    -0.5 * 5f64.to_radians().sin(),
                    0.5,
                ),
            ),
            // The upper nappe, above the apex.
            (360.0, DVec3::new(0.3, 0.0, 1.3)),
        ];
        for (phi_max, p) in cases {
            let f = p.x * p.x + p.y * p.y - (p.z - 1.0).powi(2);
            assert!(f.abs() < 1e-9, "{p} is not on the implicit cone");
            let c = Cone::new(identity(), 1.0, 1.0, phi_max);
            assert_cut_away(p, grad(p), |r| {
                c.intersect(r).map(|h| c.interaction(r, &h).p)
            });
        }
    }

    #[test]
    fn closed_form_areas() {
        // Full cone: π·r·√(h² + r²) (the lateral surface, slant √(h² + r²)).
        let c = Cone::new(identity(), 1.2, 1.5, 360.0);
        assert_rel(c.object_area(), PI * 1.2 * 1.5f64.hypot(1.2), 1e-6);
        // A sector of it, φmax = 250°: 250/360 of the lateral surface r = 0.8, h = 2.
        let c = Cone::new(identity(), 0.8, 2.0, 250.0);
        assert_rel(
            c.object_area(),
            250.0 / 360.0 * PI * 0.8 * 2f64.hypot(0.8),
            1e-6,
        );
    }

    #[test]
    fn samples_lie_on_the_cone_with_the_intersection_normal() {
        // u₀ = ¼: √u₀ = ½, ρ = ½, z = h(1 − ½) = 1; φ = 0: the point hit above, same normal.
        let c = Cone::new(identity(), 1.0, 2.0, 360.0);
        let (p, n) = c.sample_object(Vec2::new(0.25, 0.0));
        assert_near(p, Vec3::new(0.5, 0.0, 1.0), 1e-6);
        assert_near(n, Vec3::new(2.0, 0.0, 1.0) / 5f32.sqrt(), 1e-6);
    }
}
