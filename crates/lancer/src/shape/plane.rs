//! The infinite plane of the course (a lancer extension to pbrt's shapes).

use super::hit::{Shading, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, Placing, ShapeKind};
use super::mesh::{RuleError, TriangleMesh};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, Frame, Vec2, Vec3, gamma, normalize};
use crate::ray::Ray;
use glam::DVec3;

/// lancer's infinite `plane` as a scene gives it: through `p` with normal `n`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneDesc {
    /// A point of the plane.
    pub p: Vec3,
    /// Its normal.
    pub n: Vec3,
}

/// The rule a plane breaks when its normal is zero (in its description, or once placed in the
/// world by a degenerate transform).
const ZERO_PLANE_NORMAL: &str = "the plane's normal \"n\" is zero";

impl GeometryKind for PlaneDesc {
    type Prim = Box<Plane>;

    fn pbrt_name(&self) -> &'static str {
        "plane"
    }

    /// The normal not zero.
    fn validate(&self) -> Result<(), RuleError> {
        match self.n.try_normalize() {
            Some(_) => Ok(()),
            None => Err(RuleError::on(&["n"], ZERO_PLANE_NORMAL)),
        }
    }

    /// The plane moved to the world: its point as a point, its normal as a normal (flipped by
    /// `ReverseOrientation`).
    fn build(&self, at: &mut Placing<'_>, out: &mut impl Extend<Box<Plane>>) -> Result<(), String> {
        let t = &at.to_world;
        let mut n = t.normal(self.n);
        if at.reverse_orientation {
            n = -n;
        }
        // A degenerate transform can still crush a valid normal.
        let plane = Plane::new(t.point(self.p), n).ok_or_else(|| ZERO_PLANE_NORMAL.to_string())?;
        out.extend([Box::new(plane)]);
        Ok(())
    }
}

/// The plane through `a` with normal `n`, world space. (u, v) are coordinates along two tangent
/// directions from `a`.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane.
    pub a: Vec3,
    /// Unit normal (the side that faces it is the front).
    pub n: Vec3,
    frame: Frame,
}

impl Plane {
    /// The plane through `a` with normal `n` (normalised here); `None` if `n` is zero.
    pub fn new(a: Vec3, n: Vec3) -> Option<Plane> {
        let n = n.try_normalize()?;
        Some(Plane {
            a,
            n,
            frame: Frame::from_z(n),
        })
    }

    /// The course's plane intersection: t = n·(a − o) / n·d, computed in double precision so
    /// that a ray leaving the plane (offset by the error bound of its origin) finds t ≤ 0.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let n = self.n.as_dvec3();
        let denom = n.dot(ray.d.as_dvec3());
        if denom == 0.0 {
            return None;
        }
        let t = n.dot(self.a.as_dvec3() - ray.o.as_dvec3()) / denom;
        (t > 0.0 && t < ray.t_max as f64).then_some(ShapeHit {
            t: t as f32,
            u: 0.0,
            v: 0.0,
        })
    }

    /// The hit point, projected onto the plane in double precision; its error is the rounding
    /// to single precision.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let n = self.n.as_dvec3();
        let a = self.a.as_dvec3();
        let mut p: DVec3 = ray.o.as_dvec3() + hit.t as f64 * ray.d.as_dvec3();
        p -= n * n.dot(p - a);
        let p32 = p.as_vec3a();
        let local = self.frame.to_local(p32 - self.a);
        let p_error = gamma(2) * p32.abs() + gamma(2) * self.a.abs();
        SurfaceInteraction {
            p: p32,
            p_error,
            n: self.n,
            uv: Vec2::new(local.x, local.y),
            dpdu: self.frame.x,
            dpdv: self.frame.y,
            shading: Shading {
                n: self.n,
                dpdu: self.frame.x,
                dpdv: self.frame.y,
            },
            wo: -normalize(ray.d),
            t: hit.t,
            time: 0.0,
        }
    }
}

/// An infinite plane: unbounded (kept out of the BVH, tested on every ray), and of no area, so
/// it cannot emit.
impl ShapeKind for Plane {
    fn bounds(&self) -> Bounds3 {
        Bounds3::new(Vec3::splat(f32::NEG_INFINITY), Vec3::splat(f32::INFINITY))
    }

    fn is_unbounded(&self) -> bool {
        true
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Plane::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Plane::interaction(self, ray, hit)
    }

    fn area(&self) -> f32 {
        0.0
    }

    fn sample_area(&self, _: Vec2, _: &[TriangleMesh]) -> Option<ShapeSample> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::testing::assert_near;

    /// The plane z = 1, its normal given unnormalised.
    fn z1() -> Plane {
        Plane::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 2.0)).unwrap()
    }

    #[test]
    fn hits_from_either_side_with_the_same_normal() {
        // From (0.3, 0.4, 5) down: t = n·(a − o)/n·d = (1 − 5)/(−1) = 4, p = (0.3, 0.4, 1).
        let pl = z1();
        assert_eq!(pl.n, Vec3::Z);
        let ray = Ray::new(Vec3::new(0.3, 0.4, 5.0), -Vec3::Z);
        let h = pl.intersect(&ray).unwrap();
        assert_eq!(h.t, 4.0);
        let si = pl.interaction(&ray, &h);
        assert_near(si.p, Vec3::new(0.3, 0.4, 1.0), 1e-6);
        assert_eq!(si.n, Vec3::Z);
        // (u, v) are coordinates along ∂p/∂u, ∂p/∂v from a: p = a + u·∂p/∂u + v·∂p/∂v.
        assert_near(pl.a + si.uv.x * si.dpdu + si.uv.y * si.dpdv, si.p, 1e-6);
        assert!(si.dpdu.dot(si.n).abs() < 1e-6 && si.dpdv.dot(si.n).abs() < 1e-6);
        // From below, a distance 2 away: the normal is still +z.
        let up = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::new(0.0, 0.0, 2.0));
        let h = pl.intersect(&up).unwrap();
        assert_eq!(h.t, 1.0);
        assert_eq!(pl.interaction(&up, &h).n, Vec3::Z);
    }

    #[test]
    fn parallel_receding_and_short_rays_miss() {
        let pl = z1();
        assert!(pl.intersect(&Ray::new(Vec3::ZERO, Vec3::X)).is_none());
        assert!(pl.intersect(&Ray::new(Vec3::ZERO, -Vec3::Z)).is_none());
        let short = Ray {
            t_max: 0.5,
            ..Ray::new(Vec3::ZERO, Vec3::Z)
        };
        assert!(pl.intersect(&short).is_none());
        assert!(Plane::new(Vec3::ZERO, Vec3::ZERO).is_none(), "no normal");
    }

    #[test]
    fn spawned_rays_never_find_the_plane_again() {
        // A tilted plane far from the origin, hit from far away: rays leaving the hit point
        // to either side (offset by its error bound) must not re-hit it.
        let pl = Plane::new(Vec3::new(100.0, -50.0, 30.0), Vec3::new(1.0, 2.0, 3.0)).unwrap();
        let mut hits = 0;
        for k in 0..50 {
            let o = Vec3::new(300.0 + k as f32, 200.0, 400.0 - 3.0 * k as f32);
            let ray = Ray::new(
                o,
                pl.a + Vec3::new(k as f32 * 0.7, -0.3 * k as f32, 0.1) - o,
            );
            let Some(h) = pl.intersect(&ray) else {
                continue;
            };
            let si = pl.interaction(&ray, &h);
            hits += 1;
            for d in [
                si.n,
                -si.n,
                normalize(si.n + si.dpdu),
                normalize(si.dpdv - si.n),
            ] {
                assert!(
                    pl.intersect(&si.spawn_ray(d)).is_none(),
                    "ray {k} along {d}"
                );
            }
        }
        assert_eq!(hits, 50);
    }
}
