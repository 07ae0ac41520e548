//! The hyperboloid: the surface swept by the segment p₁p₂ turning about the z axis, up to
//! `phimax`.

use super::hit::{ShapeHit, SurfaceInteraction};
use super::placement::{Placement, quadric_error, quadric_hit, quadric_t};
use crate::math::{Bounds3, Vec2, Vec3, normalize, solve_quadratic};
use crate::ray::Ray;
use glam::{DVec2, DVec3};

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

    /// Full interaction (pbrt-v3): u = φ/φmax, v = s, ∂p/∂u = (−φmax·y, φmax·x, 0),
    /// ∂p/∂v = R_z(φ)·(p₂ − p₁) = (Δx cos φ − Δy sin φ, Δx sin φ + Δy cos φ, Δz).
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let (o, d) = self.placement.object_ray(ray);
        let t = quadric_t(hit);
        let p64 = o + t * d;
        let s = self.s_of(p64.z).clamp(0.0, 1.0);
        let phi = self.phi_at(p64, s);
        let (sin, cos) = phi.sin_cos();
        let (_, e, dz) = self.segment();
        let p = p64.as_vec3a();
        let dpdu = Vec3::new(-self.phi_max * p.y, self.phi_max * p.x, 0.0);
        let dpdv = DVec3::new(e.x * cos - e.y * sin, e.x * sin + e.y * cos, dz).as_vec3a();
        SurfaceInteraction::from_object(
            &self.placement.to_world,
            p,
            quadric_error(o, d, t, p),
            Vec2::new(phi as f32 / self.phi_max, s as f32),
            dpdu,
            dpdv,
            self.placement.flip_normal,
            -normalize(ray.d),
            hit.t,
        )
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
