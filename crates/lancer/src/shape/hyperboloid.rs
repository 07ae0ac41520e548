//! The hyperboloid: the surface swept by the segment p₁p₂ turning about the z axis, up to
//! `phimax`.

use super::hit::{ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind};
use super::mesh::{RuleError, TriangleMesh};
use super::placement::{LocalHit, Placement, quadric_error, quadric_hit, quadric_t};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Vec2, Vec3, solve_quadratic};
use crate::ray::Ray;
use glam::{DVec2, DVec3};

/// pbrt's `hyperboloid` as a scene gives it: the segment `p1`–`p2` swept about the z axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HyperboloidDesc {
    /// Start of the segment.
    pub p1: Vec3,
    /// End of the segment (at a different height from `p1`).
    pub p2: Vec3,
    /// Sweep, degrees.
    pub phi_max: f32,
}

impl GeometryKind for HyperboloidDesc {
    type Prim = Box<Hyperboloid>;

    fn pbrt_name(&self) -> &'static str {
        "hyperboloid"
    }

    /// The ends finite and at different heights.
    fn validate(&self) -> Result<(), RuleError> {
        let (p1, p2) = (self.p1, self.p2);
        if p1.z != p2.z && p1.is_finite() && p2.is_finite() {
            Ok(())
        } else {
            Err(RuleError::on(
                &["p1", "p2"],
                format!(
                    "the hyperboloid's \"p1\" {p1} and \"p2\" {p2} must be finite and at \
                     different heights (at one height the swept segment is a flat \
                     annulus: use a disk)"
                ),
            ))
        }
    }

    fn build(
        &self,
        at: &mut Placing<'_>,
        out: &mut impl Extend<Box<Hyperboloid>>,
    ) -> Result<(), String> {
        let s = Hyperboloid::new(at.placement(), self.p1, self.p2, self.phi_max)
            .expect("validated: finite ends at different heights");
        out.extend([Box::new(s)]);
        Ok(())
    }
}

/// pbrt's hyperboloid: the segment from `p1` (v = 0) to `p2` (v = 1) swept about the
/// object-space z axis through φ ∈ [0, φmax].
///
/// The point of the segment at height z is p₁ + s(p₂ − p₁) with s = (z − z₁)/(z₂ − z₁), so
/// the surface is x² + y² = R²(s) with R²(s) = |q + s·e|² (q = p₁ and e = p₂ − p₁ in xy): a
/// one-sheet hyperboloid of revolution, a cone when the segment's line meets the axis, a
/// cylinder when it is parallel to it. This is the exact surface for any segment; pbrt-v3's
/// fit `a(x² + y²) − c·z² = 1` is the special case of a line nearest the axis at z = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Hyperboloid {
    /// The start of the segment (v = 0).
    pub p1: Vec3,
    /// The end of the segment (v = 1).
    pub p2: Vec3,
    /// Sweep angle, radians.
    pub phi_max: f32,
    /// Placement in the world.
    pub placement: Placement,
    /// Surface area, object space.
    area: f64,
}

impl Hyperboloid {
    /// pbrt's hyperboloid (`p1`, `p2`, `phimax` in degrees); `None` when p₁ and p₂ are at the
    /// same height (the sweep would be a flat annulus) or not finite.
    pub fn new(placement: Placement, p1: Vec3, p2: Vec3, phi_max_deg: f32) -> Option<Hyperboloid> {
        if p1.z == p2.z || !p1.is_finite() || !p2.is_finite() {
            return None;
        }
        let mut h = Hyperboloid {
            p1,
            p2,
            phi_max: phi_max_deg.clamp(0.0, 360.0).to_radians(),
            placement,
            area: 0.0,
        };
        h.area = h.phi_max as f64 * (h.area_cdf(1.0) - h.area_cdf(0.0));
        Some(h)
    }

    /// World-space bounds: the radius along the segment is largest at an end (R² is convex).
    pub fn bounds(&self) -> Bounds3 {
        let r = self.p1.truncate().length().max(self.p2.truncate().length());
        let b = Bounds3::new(
            Vec3::new(-r, -r, self.p1.z.min(self.p2.z)),
            Vec3::new(r, r, self.p1.z.max(self.p2.z)),
        );
        self.placement.to_world.bounds(&b)
    }

    /// (q, e, Δz): the segment's start and xy step, and its rise, in double precision.
    #[inline]
    fn segment(&self) -> (DVec2, DVec2, f64) {
        let (p1, p2) = (self.p1.as_dvec3(), self.p2.as_dvec3());
        (p1.truncate(), (p2 - p1).truncate(), p2.z - p1.z)
    }

    /// The segment parameter s = (z − z₁)/(z₂ − z₁) at height z.
    #[inline]
    fn s_of(&self, z: f64) -> f64 {
        let (_, _, dz) = self.segment();
        (z - self.p1.z as f64) / dz
    }

    /// The sweep angle of p: the angle turning the segment's point at p's height onto p,
    /// atan2(pr × p, pr · p), in [0, 2π).
    #[inline]
    fn phi_at(&self, p: DVec3, s: f64) -> f64 {
        let (q, e, _) = self.segment();
        let pr = q + s * e;
        let phi = (pr.x * p.y - pr.y * p.x).atan2(pr.x * p.x + pr.y * p.y);
        if phi < 0.0 {
            phi + 2.0 * std::f64::consts::PI
        } else {
            phi
        }
    }

    /// Nearest hit: with s(t) = s₀ + s₁t (s₀ = (oz − z₁)/Δz, s₁ = dz/Δz), the roots of
    /// (ox + t·dx)² + (oy + t·dy)² − |q + s(t)·e|² = 0, i.e.
    /// a = dx² + dy² − s₁²|e|², b = 2(ox·dx + oy·dy − s₁·q·e − s₀s₁|e|²),
    /// c = ox² + oy² − |q|² − 2s₀·q·e − s₀²|e|², kept when 0 ≤ s ≤ 1 and φ ≤ φmax.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let (o, d) = self.placement.object_ray(ray);
        let (q, e, dz) = self.segment();
        let (qq, qe, ee) = (q.dot(q), q.dot(e), e.dot(e));
        let s0 = (o.z - self.p1.z as f64) / dz;
        let s1 = d.z / dz;
        let a = d.x * d.x + d.y * d.y - s1 * s1 * ee;
        let b = 2.0 * (o.x * d.x + o.y * d.y - s1 * qe - s0 * s1 * ee);
        let c = o.x * o.x + o.y * o.y - qq - 2.0 * s0 * qe - s0 * s0 * ee;
        let (t0, t1) = solve_quadratic(a, b, c)?;
        let t_max = ray.t_max as f64;
        for t in [t0, t1] {
            if t <= 0.0 || t >= t_max {
                continue;
            }
            let p = o + t * d;
            let s = self.s_of(p.z);
            if !(0.0..=1.0).contains(&s) || self.phi_at(p, s) > self.phi_max as f64 {
                continue;
            }
            return Some(quadric_hit(t));
        }
        None
    }

    /// The object-space hit (pbrt-v3): u = φ/φmax, v = s, ∂p/∂u = (−φmax·y, φmax·x, 0),
    /// ∂p/∂v = R_z(φ)·(p₂ − p₁) = (Δx cos φ − Δy sin φ, Δx sin φ + Δy cos φ, Δz).
    #[inline(always)]
    fn local(&self, ray: &Ray, hit: &ShapeHit) -> LocalHit {
        let (o, d) = self.placement.object_ray(ray);
        let t = quadric_t(hit);
        let p64 = o + t * d;
        let s = self.s_of(p64.z).clamp(0.0, 1.0);
        let phi = self.phi_at(p64, s);
        let (sin, cos) = phi.sin_cos();
        let (_, e, dz) = self.segment();
        let p = p64.as_vec3a();
        LocalHit {
            p,
            p_error: quadric_error(o, d, t, p),
            uv: Vec2::new(phi as f32 / self.phi_max, s as f32),
            dpdu: Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0),
            dpdv: DVec3::new(e.x * cos - e.y * sin, e.x * sin + e.y * cos, dz).as_vec3a(),
        }
    }

    /// Full interaction: the object-space hit ((u, v), ∂p/∂u, ∂p/∂v as `local` has them)
    /// placed in the world.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        self.placement.interaction(self.local(ray, hit), ray, hit.t)
    }

    /// ∂n/∂u, ∂n/∂v at the hit, object space, by the Weingarten equations
    /// ([`LocalHit::swept_normal_derivatives`])
    /// with pbrt-v3's `Hyperboloid`: ∂²p/∂u² = −φmax²·(x, y, 0),
    /// ∂²p/∂u∂v = φmax·(−∂p/∂v_y, ∂p/∂v_x, 0), ∂²p/∂v² = 0 (the generator is a line).
    pub(crate) fn normal_derivatives(&self, ray: &Ray, hit: &ShapeHit) -> (Vec3, Vec3) {
        let l = self.local(ray, hit);
        let d2pduv = self.phi_max * Vec3::new(-l.dpdv.y, l.dpdv.x, 0.0);
        l.swept_normal_derivatives(self.phi_max, d2pduv, Vec3::ZERO)
    }

    /// Coefficients (α, β, γ) of |∂p/∂φ × ∂p/∂s|² = α·s² + β·s + γ. With (x′, y′) = q + s·e,
    /// ∂p/∂φ × ∂p/∂s = R_z(φ)·(x′Δz, y′Δz, −(x′, y′)·e), whose squared length is
    /// Δz²·|q + s·e|² + ((q + s·e)·e)², independent of φ.
    #[inline]
    fn area_density(&self) -> (f64, f64, f64) {
        let (q, e, dz) = self.segment();
        let (qq, qe, ee) = (q.dot(q), q.dot(e), e.dot(e));
        let dz2 = dz * dz;
        (
            dz2 * ee + ee * ee,
            2.0 * (dz2 * qe + qe * ee),
            dz2 * qq + qe * qe,
        )
    }

    /// G(s) = ∫ √(α·s² + β·s + γ) ds (up to a constant): with w = s + β/(2α) and
    /// κ = γ/α − β²/(4α²) ≥ 0, G = √α/2 · (w·√(w² + κ) + κ·asinh(w/√κ)); √γ·s when α = 0.
    fn area_cdf(&self, s: f64) -> f64 {
        let (alpha, beta, gamma) = self.area_density();
        if alpha <= 0.0 {
            return gamma.sqrt() * s;
        }
        let w = s + beta / (2.0 * alpha);
        let kappa = (gamma / alpha - beta * beta / (4.0 * alpha * alpha)).max(0.0);
        let log_term = if kappa > 0.0 {
            kappa * (w / kappa.sqrt()).asinh()
        } else {
            0.0
        };
        0.5 * alpha.sqrt() * (w * (w * w + kappa).sqrt() + log_term)
    }

    /// Surface area, object space: A = φmax·∫₀¹ √(α·s² + β·s + γ) ds, in closed form.
    pub fn object_area(&self) -> f32 {
        self.area as f32
    }

    /// A point uniform by area and its normal (∂p/∂u × ∂p/∂v normalised), object space:
    /// φ = u₁·φmax, and s solves G(s) = G(0) + u₀·(G(1) − G(0)) (Newton's method kept inside
    /// a shrinking bracket).
    pub fn sample_object(&self, u: Vec2) -> (Vec3, Vec3) {
        let (alpha, beta, gamma) = self.area_density();
        let (g0, g1) = (self.area_cdf(0.0), self.area_cdf(1.0));
        let target = g0 + u.x as f64 * (g1 - g0);
        let (mut lo, mut hi, mut s) = (0.0f64, 1.0f64, u.x as f64);
        for _ in 0..60 {
            let f = self.area_cdf(s) - target;
            if f > 0.0 {
                hi = s;
            } else {
                lo = s;
            }
            let density = (alpha * s * s + beta * s + gamma).max(0.0).sqrt();
            let next = if density > 0.0 { s - f / density } else { -1.0 };
            let next = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
            if (next - s).abs() < 1e-13 {
                s = next;
                break;
            }
            s = next;
        }
        let (q, e, dz) = self.segment();
        let r = q + s * e;
        let phi = u.y as f64 * self.phi_max as f64;
        let (sin, cos) = phi.sin_cos();
        let rot = |v: DVec3| DVec3::new(v.x * cos - v.y * sin, v.x * sin + v.y * cos, v.z);
        let p = rot(DVec3::new(r.x, r.y, self.p1.z as f64 + s * dz));
        let n = rot(DVec3::new(r.x * dz, r.y * dz, -r.dot(e))).normalize_or_zero();
        (p.as_vec3a(), n.as_vec3a())
    }
}

impl ShapeKind for Hyperboloid {
    /// The two distances added in double precision ([`quadric_t`]).
    fn hit_after(&self, first: &ShapeHit, next: &ShapeHit) -> ShapeHit {
        quadric_hit(quadric_t(first) + quadric_t(next))
    }

    fn bounds(&self) -> Bounds3 {
        Hyperboloid::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Hyperboloid::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Hyperboloid::interaction(self, ray, hit)
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
    use std::f64::consts::PI;

    /// The segment (1, −1, 1) → (1, 1, −1) swept fully: x² + y² = 1 + z² for |z| ≤ 1 (the
    /// segment's point at height z is (1, −z, z)), its waist the unit circle at z = 0.
    fn classic() -> Hyperboloid {
        Hyperboloid::new(
            identity(),
            Vec3::new(1.0, -1.0, 1.0),
            Vec3::new(1.0, 1.0, -1.0),
            360.0,
        )
        .unwrap()
    }

    /// A segment parallel to the axis sweeps a cylinder of radius 1 between z = ±1.
    fn cylinder(phi_max: f32) -> Hyperboloid {
        Hyperboloid::new(
            identity(),
            Vec3::new(1.0, 0.0, -1.0),
            Vec3::new(1.0, 0.0, 1.0),
            phi_max,
        )
        .unwrap()
    }

    fn hit(h: &Hyperboloid, ray: &Ray) -> (ShapeHit, SurfaceInteraction) {
        let hit = h.intersect(ray).expect("a hit");
        (hit, h.interaction(ray, &hit))
    }

    #[test]
    fn a_segment_parallel_to_the_axis_is_a_cylinder() {
        // Along −x at z = 0: t = 4, p = (1, 0, 0); ∂p/∂u = (0, 2π, 0), ∂p/∂v = p₂ − p₁ =
        // (0, 0, 2): n ∝ (4π, 0, 0) = +x; u = 0, v = s = ½.
        let (h, si) = hit(
            &cylinder(360.0),
            &Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X),
        );
        assert!((h.t - 4.0).abs() < 1e-6);
        assert_near(si.p, Vec3::X, 1e-6);
        assert_near(si.n, Vec3::X, 1e-6);
        assert!(si.uv.x.abs() < 1e-6 && (si.uv.y - 0.5).abs() < 1e-6);
    }

    #[test]
    fn the_classic_hyperboloid_at_its_waist_and_rim() {
        let c = classic();
        // The waist (1, 0, 0) at t = 4: s = ½, ∂p/∂v = (0, 2, −2), and
        // ∂p/∂u × ∂p/∂v = (0, 2π, 0) × (0, 2, −2) = (−4π, 0, 0): the segment runs down, so
        // the natural normal points at the axis.
        let (h, si) = hit(&c, &Ray::new(Vec3::new(5.0, 0.0, 0.0), -Vec3::X));
        assert!((h.t - 4.0).abs() < 1e-6);
        assert_near(si.p, Vec3::X, 1e-6);
        assert_near(si.n, -Vec3::X, 1e-6);
        assert!(si.uv.x.abs() < 1e-6 && (si.uv.y - 0.5).abs() < 1e-6);
        // At z = 1: x² = 1 + 1, t = 5 − √2, s = 0; the segment's point there is (1, −1), which
        // turns onto (√2, 0) by φ = 45°: u = ⅛.
        let (h, si) = hit(&c, &Ray::new(Vec3::new(5.0, 0.0, 1.0), -Vec3::X));
        assert!((h.t - (5.0 - 2f32.sqrt())).abs() < 1e-5);
        assert!((si.uv.x - 0.125).abs() < 1e-5 && si.uv.y.abs() < 1e-5);
        // Beyond z = 1 on x² + y² = 1 + z²: (√3.25, 0, 1.5), ∇F = (2x, 2y, −2z).
        let p = DVec3::new(3.25f64.sqrt(), 0.0, 1.5);
        assert!((p.x * p.x + p.y * p.y - 1.0 - p.z * p.z).abs() < 1e-9);
        let grad = DVec3::new(2.0 * p.x, 2.0 * p.y, -2.0 * p.z);
        assert_cut_away(p, grad, |r| c.intersect(r).map(|h| c.interaction(r, &h).p));
    }

    #[test]
    fn flat_or_infinite_segments_are_refused() {
        let pl = identity();
        let (a, b) = (Vec3::new(1.0, 0.0, 0.5), Vec3::new(0.0, 1.0, 0.5));
        assert!(Hyperboloid::new(pl, a, b, 360.0).is_none(), "same height");
        let inf = Vec3::new(f32::INFINITY, 0.0, 1.0);
        assert!(Hyperboloid::new(pl, Vec3::ZERO, inf, 360.0).is_none());
    }

    #[test]
    fn closed_form_areas() {
        // Half a cylinder r = ½, height 2: φmax·r·h = π·½·2 = π.
        let half = Hyperboloid::new(
            identity(),
            Vec3::new(0.5, 0.0, -1.0),
            Vec3::new(0.5, 0.0, 1.0),
            180.0,
        )
        .unwrap();
        assert_rel(half.object_area(), PI, 1e-5);
        // A segment from the axis: a cone, π·r·slant with r = √2, slant = √3.
        let cone = Hyperboloid::new(identity(), Vec3::ZERO, Vec3::ONE, 360.0).unwrap();
        assert_rel(cone.object_area(), PI * 2f64.sqrt() * 3f64.sqrt(), 1e-5);
        // The classic one, ρ(z) = √(1 + z²): A = 2π∫₋₁¹ ρ√(1 + ρ′²) dz = 4π∫₀¹ √(1 + 2z²) dz
        // = 4π·(√3/2 + asinh(√2)/(2√2)).
        let want = 4.0 * PI * (3f64.sqrt() / 2.0 + 2f64.sqrt().asinh() / (2.0 * 2f64.sqrt()));
        assert_rel(classic().object_area(), want, 1e-5);
    }

    #[test]
    fn samples_lie_on_the_surface() {
        // On the cylinder the area is uniform in s: u = (½, ¼) gives s = ½, φ = π/2:
        // (0, 1, 0), normal +y.
        let (p, n) = cylinder(360.0).sample_object(Vec2::new(0.5, 0.25));
        assert_near(p, Vec3::Y, 1e-6);
        assert_near(n, Vec3::Y, 1e-6);
        // On the classic one every sample satisfies x² + y² = 1 + z², |z| ≤ 1, with the
        // natural normal along −∇F = −(2x, 2y, −2z).
        let c = classic();
        for i in 0..64 {
            let u = Vec2::new((i % 8) as f32 / 8.0 + 0.03, (i / 8) as f32 / 8.0 + 0.03);
            let (p, n) = c.sample_object(u);
            assert!(
                (p.x * p.x + p.y * p.y - 1.0 - p.z * p.z).abs() < 1e-5,
                "{p}"
            );
            assert!(p.z.abs() <= 1.0 + 1e-6, "{p}");
            assert_near(n, -crate::math::normalize(Vec3::new(p.x, p.y, -p.z)), 1e-5);
        }
    }
}
