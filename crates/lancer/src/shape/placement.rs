//! Where a shape sits in the world ([`Placement`]), and the helpers the quadrics share: the
//! azimuth of a point, the double-precision hit distance carried in a [`ShapeHit`], the error
//! bound of a quadric's hit point, the object-space hit ([`LocalHit`]) and its interaction,
//! the normal's derivatives by the Weingarten equations ([`weingarten`], bilinear patches use
//! it too), and moving object-space samples to the world. A leaf module beside `hit`: the
//! shape files use it, it uses no shape.

use super::hit::{ShadingDerivatives, ShapeHit, ShapeSample, SurfaceInteraction};
use crate::math::{Transform, Vec2, Vec3, cross, difference_of_products, gamma, normalize};
use crate::ray::Ray;
use glam::{DMat4, DVec3};

/// Where a quadric sits: its object-to-world transform and orientation.
///
/// Rays are moved into object space in double precision: the rounding error of that transform
/// is then negligible next to the single-precision error bounds by which spawned rays are
/// offset, so a ray leaving a quadric can never find it again at a tiny positive `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Object space → world space.
    pub to_world: Transform,
    /// World space → object space, in double precision.
    pub to_object: DMat4,
    /// Normals flipped (reverse orientation xor the transform swaps handedness).
    pub flip_normal: bool,
}

impl Placement {
    /// A placement from a transform and pbrt's `ReverseOrientation` state.
    pub fn new(to_world: Transform, reverse_orientation: bool) -> Placement {
        Placement {
            to_world,
            to_object: to_world.m.as_dmat4().inverse(),
            flip_normal: reverse_orientation ^ to_world.swaps_handedness(),
        }
    }

    /// The ray in object space, double precision: (origin, direction).
    #[inline]
    pub fn object_ray(&self, ray: &Ray) -> (DVec3, DVec3) {
        (
            self.to_object.transform_point3(ray.o.as_dvec3()),
            self.to_object.transform_vector3(ray.d.as_dvec3()),
        )
    }

    /// The factor by which the placement scales areas: |det M|^(2/3) for the linear part M of
    /// object-to-world (exact for similarities, which is what the quadrics' area sampling
    /// assumes, like pbrt's).
    pub fn area_scale(&self) -> f32 {
        let det = glam::Mat3::from_mat4(self.to_world.m).determinant().abs();
        det.powf(2.0 / 3.0)
    }

    /// The world interaction of the object-space hit `l` of `ray` at distance `t`
    /// ([`SurfaceInteraction::from_object`], flipped as the placement says).
    #[inline(always)]
    pub(crate) fn interaction(&self, l: LocalHit, ray: &Ray, t: f32) -> SurfaceInteraction {
        SurfaceInteraction::from_object(
            &self.to_world,
            l.p,
            l.p_error,
            l.uv,
            l.dpdu,
            l.dpdv,
            self.flip_normal,
            -normalize(ray.d),
            t,
        )
    }

    /// The shading derivatives of a hit `si` on the placed quadric whose object-space normal
    /// has derivatives `dndu`, `dndv`: ∂p/∂u, ∂p/∂v as `si` has them (the object's moved by M),
    /// ∂n/∂u, ∂n/∂v moved as normals, by (M⁻¹)ᵀ, as pbrt-v4 moves them (not flipped).
    #[inline]
    pub fn derivatives(
        &self,
        si: &SurfaceInteraction,
        (dndu, dndv): (Vec3, Vec3),
    ) -> ShadingDerivatives {
        ShadingDerivatives {
            dpdu: si.shading.dpdu,
            dpdv: si.shading.dpdv,
            dndu: self.to_world.normal(dndu),
            dndv: self.to_world.normal(dndv),
        }
    }

    /// An object-space point and outward normal moved to the world, the normal flipped as
    /// [`SurfaceInteraction::from_object`](super::SurfaceInteraction::from_object) flips it.
    pub fn place(&self, p: Vec3, n: Vec3) -> ShapeSample {
        let n = if self.flip_normal { -n } else { n };
        ShapeSample {
            p: self.to_world.point(p),
            n: self.to_world.normal(n).normalize_or_zero(),
        }
    }
}

/// A quadric's hit in object space: the point, its error bound, its (u, v) and ∂p/∂u, ∂p/∂v,
/// from which its interaction ([`Placement::interaction`]) and, when a bump map asks, its
/// normal's derivatives are made.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LocalHit {
    /// The point.
    pub p: Vec3,
    /// Bound on the absolute rounding error of `p`, per axis.
    pub p_error: Vec3,
    /// Its (u, v).
    pub uv: Vec2,
    /// ∂p/∂u.
    pub dpdu: Vec3,
    /// ∂p/∂v.
    pub dpdv: Vec3,
}

impl LocalHit {
    /// ∂n/∂u, ∂n/∂v by the Weingarten equations ([`weingarten`]) on a quadric swept about z
    /// up to φmax with u = φ/φmax, whose ∂p/∂u = φmax·(−y, x, 0) gives them all
    /// ∂²p/∂u² = −φmax²·(x, y, 0); `d2pduv` and `d2pdvv` are the shape's own.
    #[inline]
    pub(crate) fn swept_normal_derivatives(
        &self,
        phi_max: f32,
        d2pduv: Vec3,
        d2pdvv: Vec3,
    ) -> (Vec3, Vec3) {
        let d2pduu = -phi_max * phi_max * Vec3::new(self.p.x, self.p.y, 0.0);
        weingarten(self.dpdu, self.dpdv, d2pduu, d2pduv, d2pdvv)
    }
}

/// ∂n/∂u and ∂n/∂v of the unit normal n = normalize(∂p/∂u × ∂p/∂v) by the Weingarten
/// equations, as pbrt-v4's quadrics compute them: with the first fundamental form
/// E = ∂p/∂u·∂p/∂u, F = ∂p/∂u·∂p/∂v, G = ∂p/∂v·∂p/∂v and the second e = n·∂²p/∂u²,
/// f = n·∂²p/∂u∂v, g = n·∂²p/∂v²,
///
///   ∂n/∂u = ((fF − eG)·∂p/∂u + (eF − fE)·∂p/∂v) / (EG − F²),
///   ∂n/∂v = ((gF − fG)·∂p/∂u + (fF − gE)·∂p/∂v) / (EG − F²),
///
/// both zero where EG − F² = 0 (pbrt-v4's guard).
#[inline]
pub(crate) fn weingarten(
    dpdu: Vec3,
    dpdv: Vec3,
    d2pduu: Vec3,
    d2pduv: Vec3,
    d2pdvv: Vec3,
) -> (Vec3, Vec3) {
    let (e1, f1, g1) = (dpdu.dot(dpdu), dpdu.dot(dpdv), dpdv.dot(dpdv));
    let n = cross(dpdu, dpdv).normalize_or_zero();
    let (e2, f2, g2) = (n.dot(d2pduu), n.dot(d2pduv), n.dot(d2pdvv));
    let egf2 = difference_of_products(e1, g1, f1, f1);
    let inv = if egf2 == 0.0 { 0.0 } else { 1.0 / egf2 };
    let dndu = (f2 * f1 - e2 * g1) * inv * dpdu + (e2 * f1 - f2 * e1) * inv * dpdv;
    let dndv = (g2 * f1 - f2 * g1) * inv * dpdu + (f2 * f1 - g2 * e1) * inv * dpdv;
    (dndu, dndv)
}

/// The azimuth φ = atan2(y, x) of an object-space point, in [0, 2π).
#[inline]
pub(crate) fn phi_of(p: DVec3) -> f64 {
    let phi = p.y.atan2(p.x);
    if phi < 0.0 {
        phi + 2.0 * std::f64::consts::PI
    } else {
        phi
    }
}

/// A quadric's hit at the double-precision distance `t`: `t` rounded to `f32`, and the
/// rounding residual kept in `u` so that [`quadric_t`] recovers `t` to about 48 bits.
#[inline]
pub(crate) fn quadric_hit(t: f64) -> ShapeHit {
    let tf = t as f32;
    ShapeHit {
        t: tf,
        u: (t - tf as f64) as f32,
        v: 0.0,
    }
}

/// The double-precision distance stored by [`quadric_hit`].
#[inline]
pub(crate) fn quadric_t(hit: &ShapeHit) -> f64 {
    hit.t as f64 + hit.u as f64
}

/// Error bound of the object-space point p = o + t·d computed in double precision from the
/// root t and rounded to `f32`, for quadrics whose hit points are not reprojected onto the
/// surface: γ₃·|p| covers the rounding to `f32` with room to spare, and 10⁻¹²·(|o| + |t·d|)
/// the double-precision error of the root and of o + t·d, per axis.
#[inline]
pub(crate) fn quadric_error(o: DVec3, d: DVec3, t: f64, p: Vec3) -> Vec3 {
    gamma(3) * p.abs() + (1e-12 * (o.abs() + (t * d).abs())).as_vec3a()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn object_rays_undo_the_placement() {
        // Object → world: translate (1, 2, 3) after scaling by 2. The world ray from
        // (1, 2, 7) along −z starts at (0, 0, 2) in object space, direction (0, 0, −½).
        let xf = Transform::translate(Vec3::new(1.0, 2.0, 3.0))
            * Transform::scale(Vec3::splat(2.0)).unwrap();
        let pl = Placement::new(xf, false);
        let (o, d) = pl.object_ray(&Ray::new(Vec3::new(1.0, 2.0, 7.0), -Vec3::Z));
        assert!((o - DVec3::new(0.0, 0.0, 2.0)).length() < 1e-12);
        assert!((d - DVec3::new(0.0, 0.0, -0.5)).length() < 1e-12);
        assert!(!pl.flip_normal);
    }

    #[test]
    fn flips_follow_reverse_orientation_xor_handedness() {
        let mirror = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap();
        for (xf, reverse, flip) in [
            (Transform::IDENTITY, false, false),
            (Transform::IDENTITY, true, true),
            (mirror, false, true),
            (mirror, true, false),
        ] {
            assert_eq!(Placement::new(xf, reverse).flip_normal, flip);
        }
        // place(): the point moved, the normal flipped and moved as a normal.
        let pl = Placement::new(Transform::translate(Vec3::X), true);
        let s = pl.place(Vec3::new(0.0, 0.0, 1.0), Vec3::Z);
        assert_eq!((s.p, s.n), (Vec3::new(1.0, 0.0, 1.0), -Vec3::Z));
    }

    #[test]
    fn area_scale_is_the_determinant_to_the_two_thirds() {
        // Identity: 1; uniform scale 3: |27|^(2/3) = 9 = 3²; a mirror changes nothing.
        assert_eq!(Placement::new(Transform::IDENTITY, false).area_scale(), 1.0);
        let s3 = Transform::scale(Vec3::new(-3.0, 3.0, 3.0)).unwrap();
        let a = Placement::new(s3, false).area_scale();
        assert!((a - 9.0).abs() < 1e-5, "{a}");
    }

    #[test]
    fn azimuths_and_double_precision_distances() {
        assert_eq!(phi_of(DVec3::new(1.0, 0.0, 5.0)), 0.0);
        assert!((phi_of(DVec3::new(0.0, -1.0, 0.0)) - 1.5 * PI).abs() < 1e-15);
        assert!((phi_of(DVec3::new(-1.0, 1.0, 0.0)) - 0.75 * PI).abs() < 1e-15);
        // t = 1/3 rounds to f32 with an error ~10⁻⁸; the residual kept in u recovers it to
        // about 48 bits.
        let t = 1.0 / 3.0;
        let h = quadric_hit(t);
        assert_eq!(h.t, t as f32);
        assert!((h.t as f64 - t).abs() > 1e-9);
        assert!((quadric_t(&h) - t).abs() < 1e-15);
    }
}
