//! The infinite plane of the course (a lancer extension to pbrt's shapes).

use super::hit::{Shading, ShapeHit, SurfaceInteraction};
use crate::math::{Frame, Vec2, Vec3, gamma, normalize};
use crate::ray::Ray;
use glam::DVec3;

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
        }
    }
}
