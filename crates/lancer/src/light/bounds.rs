//! What the light BVH knows about a light or a group of lights (pbrt-v4's `LightBounds`): where
//! it is (a box), how much it emits (φ), and in which directions (a cone of normals around `w`
//! with half-angle θ_o, plus the emission spread θ_e beyond each normal). From these,
//! [`LightBounds::importance`] bounds how much the group can light a point.

use super::compact::{CompactLightBounds, safe_sqrt};
use crate::math::{Bounds3, Vec3, cross, normalize};
use std::f32::consts::PI;

/// What the light samplers know of a light's extent ([`super::Light::extent`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightExtent {
    /// A light with bounds, for the BVH.
    Bounded(LightBounds),
    /// Distant and infinite lights, chosen apart.
    Unbounded,
    /// A light that emits nothing: never chosen by the BVH.
    Dark,
}

/// A cone of directions: axis `w` and cos of its half-angle (−1 for the whole sphere).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCone {
    /// Unit axis.
    pub w: Vec3,
    /// cos θ of the half-angle.
    pub cos_theta: f32,
}

/// acos of `x` clamped to [−1, 1].
pub(super) fn safe_acos(x: f32) -> f32 {
    x.clamp(-1.0, 1.0).acos()
}

impl DirectionCone {
    /// Every direction.
    pub const ENTIRE_SPHERE: DirectionCone = DirectionCone {
        w: Vec3::Z,
        cos_theta: -1.0,
    };

    /// The smallest cone holding both (pbrt-v4's `Union`): the half-angle
    /// θ = (θ_a + θ_d + θ_b)/2 around an axis rotated from `a` towards `b`, θ_d being the angle
    /// between the axes.
    pub fn union(a: DirectionCone, b: DirectionCone) -> DirectionCone {
        // A whole sphere holds the other cone: what the tests below answer (θ = π, and
        // min(·, π) ≤ π), without their arc cosines.
        if a.cos_theta <= -1.0 {
            return a;
        }
        if b.cos_theta <= -1.0 {
            return b;
        }
        let theta_a = safe_acos(a.cos_theta);
        let theta_b = safe_acos(b.cos_theta);
        let theta_d = safe_acos(a.w.dot(b.w));
        if (theta_d + theta_b).min(PI) <= theta_a {
            return a;
        }
        if (theta_d + theta_a).min(PI) <= theta_b {
            return b;
        }
        let theta_o = 0.5 * (theta_a + theta_d + theta_b);
        if theta_o >= PI {
            return DirectionCone::ENTIRE_SPHERE;
        }
        // Rotate a.w by θ_r = θ_o − θ_a about a.w × b.w (Rodrigues).
        let theta_r = theta_o - theta_a;
        let axis = cross(a.w, b.w);
        if axis.length_squared() == 0.0 {
            return DirectionCone::ENTIRE_SPHERE;
        }
        let k = normalize(axis);
        let (s, c) = theta_r.sin_cos();
        let w = a.w * c + cross(k, a.w) * s + k * k.dot(a.w) * (1.0 - c);
        DirectionCone {
            w: normalize(w),
            cos_theta: theta_o.cos(),
        }
    }
}

/// Bounds on a light's emission (pbrt-v4's `LightBounds`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightBounds {
    /// Where the light is.
    pub bounds: Bounds3,
    /// Its emitted power (an upper bound, any consistent scale).
    pub phi: f32,
    /// The cone of its surface normals (or emission axes).
    pub normals: DirectionCone,
    /// cos θ_e: how far past each normal it emits (π/2 for area lights).
    pub cos_theta_e: f32,
    /// Emits on both sides of its normals.
    pub two_sided: bool,
}

impl LightBounds {
    /// A light at the point `p` emitting power `phi` in every direction (point, goniometric
    /// and projection lights): normal cone = the whole sphere, cos θ_e = cos(π/2).
    pub fn point(p: Vec3, phi: f32) -> LightBounds {
        LightBounds {
            bounds: Bounds3::from_point(p),
            phi,
            normals: DirectionCone::ENTIRE_SPHERE,
            cos_theta_e: (PI / 2.0).cos(),
            two_sided: false,
        }
    }

    /// The bounds of two groups together: boxes and cones united, powers added, the wider
    /// spread.
    pub fn union(&self, o: &LightBounds) -> LightBounds {
        if self.phi == 0.0 {
            return *o;
        }
        if o.phi == 0.0 {
            return *self;
        }
        LightBounds {
            bounds: self.bounds.union(&o.bounds),
            phi: self.phi + o.phi,
            normals: DirectionCone::union(self.normals, o.normals),
            cos_theta_e: self.cos_theta_e.min(o.cos_theta_e),
            two_sided: self.two_sided || o.two_sided,
        }
    }

    /// These bounds as a light's extent: [`LightExtent::Bounded`] when the power is positive
    /// and finite, else [`LightExtent::Dark`] (never chosen by the BVH).
    pub fn extent(self) -> LightExtent {
        if self.phi > 0.0 && self.phi.is_finite() {
            LightExtent::Bounded(self)
        } else {
            LightExtent::Dark
        }
    }

    /// The centre of the box.
    pub fn centroid(&self) -> Vec3 {
        self.bounds.centroid()
    }

    /// A conservative estimate of how much this group lights point `p` with surface normal
    /// `n` (zero for a point in a medium), pbrt-v4's `LightBounds::Importance`:
    ///
    /// I = φ · cos θ′ / d² · cos θ′ᵢ, where d² is the squared distance to the box's centre
    /// (at least half its diagonal), θ′ = max(0, θ_w − θ_o − θ_b) the smallest angle between
    /// an emission direction the cone allows and the direction to `p` (θ_w the angle from the
    /// cone's axis to `p`, θ_b the half-angle the box subtends from `p`), zero when θ′ ≥ θ_e;
    /// θ′ᵢ = max(0, θᵢ − θ_b) likewise for the angle θᵢ between `n` and the box.
    pub fn importance(&self, p: Vec3, n: Vec3) -> f32 {
        self.compact().importance(p, n)
    }

    /// What [`LightBounds::importance`] needs, precomputed: the box's centre and half
    /// diagonal (and its reciprocal), its bounding sphere's r and r², cos θ_o and
    /// sin θ_o = √(1 − cos² θ_o). (A light's box is never empty: a point light's is one point.)
    pub fn compact(&self) -> CompactLightBounds {
        let (centre, r) = self.bounds.bounding_sphere();
        let cos_theta_o = self.normals.cos_theta;
        let min_d2 = self.bounds.diagonal().length() / 2.0;
        CompactLightBounds {
            centre,
            w: self.normals.w,
            phi: self.phi,
            min_d2,
            inv_min_d2: 1.0 / min_d2,
            r,
            r2: r * r,
            cos_theta_o,
            sin_theta_o: safe_sqrt(1.0 - cos_theta_o * cos_theta_o),
            cos_theta_e: self.cos_theta_e,
            two_sided: self.two_sided,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::compact::CompactLightBounds4;
    use crate::sampling::Pcg32;

    fn quad_light(two_sided: bool) -> LightBounds {
        // A small light at the origin facing +z.
        LightBounds {
            bounds: Bounds3::new(Vec3::new(-0.1, -0.1, 0.0), Vec3::new(0.1, 0.1, 0.0)),
            phi: 1.0,
            normals: DirectionCone {
                w: Vec3::Z,
                cos_theta: 1.0,
            },
            cos_theta_e: 0.0,
            two_sided,
        }
    }

    #[test]
    fn importance_is_zero_behind_a_one_sided_emitter() {
        let b = quad_light(false);
        assert_eq!(b.importance(Vec3::new(0.0, 0.0, -2.0), Vec3::Z), 0.0);
        assert_eq!(b.importance(Vec3::new(0.5, 0.3, -1.0), Vec3::ZERO), 0.0);
        // In front it is φ·cos θ′/d²: straight ahead at distance 2, normal facing it, 1/4.
        let front = b.importance(Vec3::new(0.0, 0.0, 2.0), -Vec3::Z);
        assert!((front - 0.25).abs() < 1e-6, "{front}");
        // Two-sided, the back is as bright as the front.
        let two = quad_light(true);
        let back = two.importance(Vec3::new(0.0, 0.0, -2.0), Vec3::Z);
        assert!((back - 0.25).abs() < 1e-6, "{back}");
    }

    #[test]
    fn cone_union_holds_both_cones() {
        let a = DirectionCone {
            w: Vec3::X,
            cos_theta: 1.0,
        };
        let b = DirectionCone {
            w: Vec3::Y,
            cos_theta: 1.0,
        };
        let u = DirectionCone::union(a, b);
        // Half-angle π/4 around (x + y)/√2.
        assert!((u.cos_theta - (PI / 4.0).cos()).abs() < 1e-6);
        assert!((u.w - normalize(Vec3::new(1.0, 1.0, 0.0))).length() < 1e-5);
        let c = DirectionCone::union(a, DirectionCone::ENTIRE_SPHERE);
        assert_eq!(c.cos_theta, -1.0);
    }

    /// Random bounds: boxes from points to wide ones, cones from a line to the whole sphere,
    /// one- and two-sided.
    fn random_bounds(rng: &mut Pcg32) -> LightBounds {
        let mut v = || Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0 - 2.0;
        let (a, size, w) = (v(), v().abs() * 0.5, normalize(v()));
        let size = if a.x > 1.0 { Vec3::ZERO } else { size };
        LightBounds {
            bounds: Bounds3::new(a, a + size),
            phi: rng.uniform() * 10.0,
            normals: DirectionCone {
                w,
                cos_theta: rng.uniform() * 2.0 - 1.0,
            },
            cos_theta_e: rng.uniform() * 1.2 - 0.1,
            two_sided: rng.uniform() < 0.3,
        }
    }

    #[test]
    fn four_lanes_give_the_bits_of_one_at_a_time() {
        let mut rng = Pcg32::new(11, 3);
        let mut nonzero = 0;
        for _ in 0..2000 {
            let b = [(); 4].map(|_| random_bounds(&mut rng));
            let lanes = CompactLightBounds4::new(b.map(|b| b.compact()));
            let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 6.0 - 3.0;
            let n = match (rng.uniform() * 3.0) as u32 {
                0 => Vec3::ZERO,
                _ => normalize(Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5),
            };
            // Also the point at a box's centre (wi = 0) and inside its sphere.
            let p = if rng.uniform() < 0.05 {
                b[0].centroid()
            } else {
                p
            };
            let got = lanes.importance(p, n).to_array();
            for (i, b) in b.iter().enumerate() {
                let want = b.importance(p, n);
                assert_eq!(
                    got[i].to_bits(),
                    want.to_bits(),
                    "lane {i}: {b:?} at {p:?} {n:?}"
                );
                nonzero += usize::from(want > 0.0);
            }
        }
        // The cases are not all trivial zeros.
        assert!(nonzero > 1000, "{nonzero}");
    }

    /// pbrt-v4's `LightBounds::Importance` as it is written there, in f64: the unit direction
    /// to `p`, then the sines and cosines of θ_w, θ_b, θ_x, θ′ and θᵢ one after the other.
    /// Also returns cos θ′, to tell cases on the edge of the emission cut.
    fn pbrt_importance(b: &LightBounds, p: Vec3, n: Vec3) -> (f64, f64) {
        let f = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
        let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let sqrt0 = |x: f64| x.max(0.0).sqrt();
        // cos(θa − θb), 1 when θa < θb.
        let cos_sub = |sa: f64, ca: f64, sb: f64, cb: f64| {
            if ca > cb { 1.0 } else { ca * cb + sa * sb }
        };
        let (c, r) = b.bounds.bounding_sphere();
        let v = [0, 1, 2].map(|k| f(p)[k] - f(c)[k]);
        let d2 = dot(v, v).max(b.bounds.diagonal().length() as f64 / 2.0);
        let len = dot(v, v).sqrt();
        let wi = if len > 0.0 {
            v.map(|x| x / len)
        } else {
            [0.0; 3]
        };
        let mut cos_w = dot(f(b.normals.w), wi);
        if b.two_sided {
            cos_w = cos_w.abs();
        }
        let sin_w = sqrt0(1.0 - cos_w * cos_w);
        let r2 = (r as f64) * (r as f64);
        let cos_b = if dot(v, v) < r2 {
            -1.0
        } else {
            sqrt0(1.0 - r2 / dot(v, v))
        };
        let sin_b = sqrt0(1.0 - cos_b * cos_b);
        let cos_o = b.normals.cos_theta as f64;
        let sin_o = sqrt0(1.0 - cos_o * cos_o);
        let (cos_x, sin_x) = if cos_w > cos_o {
            (1.0, 0.0)
        } else {
            (cos_w * cos_o + sin_w * sin_o, sin_w * cos_o - cos_w * sin_o)
        };
        let cos_p = cos_sub(sin_x, cos_x, sin_b, cos_b);
        if cos_p <= b.cos_theta_e as f64 {
            return (0.0, cos_p);
        }
        let mut imp = b.phi as f64 * cos_p / d2;
        if n != Vec3::ZERO {
            let cos_i = dot(wi, f(n)).abs();
            imp *= cos_sub(sqrt0(1.0 - cos_i * cos_i), cos_i, sin_b, cos_b);
        }
        (imp.max(0.0), cos_p)
    }

    #[test]
    fn importance_is_pbrt_v4_s_up_to_rounding() {
        // Random bounds seen from random points (some at a box's centre, inside its sphere,
        // on its cone's axis), against pbrt-v4's formula in f64: equal to a few ulps of the
        // largest importance the node can have, φ/d². Points within 1e-5 of the emission cut
        // (cos θ′ = cos θ_e), where the importance jumps, could fall either side.
        let mut rng = Pcg32::new(5, 9);
        let (mut nonzero, mut compared) = (0, 0);
        for k in 0..20000 {
            let b = random_bounds(&mut rng);
            let mut p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 6.0 - 3.0;
            match k % 20 {
                0 => p = b.centroid(),
                1 => p = b.centroid() + b.normals.w * (1.0 + rng.uniform()),
                _ => {}
            }
            let n = match (rng.uniform() * 3.0) as u32 {
                0 => Vec3::ZERO,
                _ => normalize(Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) - 0.5),
            };
            let (want, cos_p) = pbrt_importance(&b, p, n);
            let d2 = (p - b.centroid())
                .length_squared()
                .max(b.bounds.diagonal().length() / 2.0);
            if (cos_p - b.cos_theta_e as f64).abs() < 1e-5 || d2 == 0.0 {
                continue;
            }
            let got = b.importance(p, n) as f64;
            let scale = b.phi as f64 / d2 as f64;
            assert!(
                (got - want).abs() <= 2e-6 * scale,
                "{got} vs {want} (φ/d² {scale}): {b:?} at {p:?} {n:?}"
            );
            compared += 1;
            nonzero += usize::from(want > 0.0);
        }
        assert!(compared > 19000 && nonzero > 8000, "{compared} {nonzero}");
    }
}
