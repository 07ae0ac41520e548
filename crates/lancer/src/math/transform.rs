//! Affine and projective transforms that carry their inverse: the course's "repère du monde".

use super::{Bounds3, Vec3, cross, gamma};
use glam::{Mat4, Vec4};

/// A 4×4 transformation and its inverse, so that points, vectors and normals can be moved both
/// ways without inverting a matrix per ray.
///
/// Points transform as `M·(x, y, z, 1)` (then divided by w), vectors as `M·(x, y, z, 0)`, and
/// normals by the inverse transpose `(M⁻¹)ᵀ·n` so that they stay perpendicular to the surface
/// under non-uniform scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// The matrix.
    pub m: Mat4,
    /// Its inverse.
    pub m_inv: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Transform = Transform {
        m: Mat4::IDENTITY,
        m_inv: Mat4::IDENTITY,
    };

    /// A transform from a matrix; `None` if the matrix is singular or not finite.
    pub fn from_matrix(m: Mat4) -> Option<Transform> {
        let det = m.determinant();
        if !det.is_finite() || det.abs() < 1e-30 || !m.is_finite() {
            return None;
        }
        let m_inv = m.inverse();
        m_inv.is_finite().then_some(Transform { m, m_inv })
    }

    /// A transform from a matrix and its known inverse.
    pub const fn from_pair(m: Mat4, m_inv: Mat4) -> Transform {
        Transform { m, m_inv }
    }

    /// Translation by `d`.
    pub fn translate(d: Vec3) -> Transform {
        Transform {
            m: Mat4::from_translation(d.into()),
            m_inv: Mat4::from_translation((-d).into()),
        }
    }

    /// Scale by `s` along the axes; `None` if a factor is zero.
    pub fn scale(s: Vec3) -> Option<Transform> {
        if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 || !s.is_finite() {
            return None;
        }
        Some(Transform {
            m: Mat4::from_scale(s.into()),
            m_inv: Mat4::from_scale(s.recip().into()),
        })
    }

    /// Rotation by `degrees` about `axis` (right-handed: counter-clockwise looking down the
    /// axis towards the origin), as pbrt's `Rotate`. `None` for a zero axis.
    pub fn rotate(degrees: f32, axis: Vec3) -> Option<Transform> {
        let a = axis.try_normalize()?;
        let m = Mat4::from_axis_angle(a.into(), degrees.to_radians());
        Some(Transform {
            m,
            m_inv: m.transpose(),
        })
    }

    /// pbrt's `LookAt`: the transform from world space to a camera space at `eye`, looking at
    /// `look`, with `up` the vertical. Camera space is pbrt's: the camera looks down +z, +y is
    /// up and +x is `cross(up, dir)`, which makes the frame left-handed.
    pub fn look_at(eye: Vec3, look: Vec3, up: Vec3) -> Option<Transform> {
        let dir = (look - eye).try_normalize()?;
        let right = cross(up.try_normalize()?, dir).try_normalize()?;
        let new_up = cross(dir, right);
        let world_from_camera = Mat4::from_cols(
            right.extend(0.0),
            new_up.extend(0.0),
            dir.extend(0.0),
            eye.extend(1.0),
        );
        Some(Transform {
            m: world_from_camera.inverse(),
            m_inv: world_from_camera,
        })
    }

    /// pbrt's perspective projection: camera space to a screen space where the frustum of full
    /// angle `fov_degrees` maps to [−1, 1], with z mapped from [near, far] to [0, 1].
    pub fn perspective(fov_degrees: f32, near: f32, far: f32) -> Option<Transform> {
        let persp = Mat4::from_cols(
            Vec4::new(1.0, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 1.0, 0.0, 0.0),
            Vec4::new(0.0, 0.0, far / (far - near), 1.0),
            Vec4::new(0.0, 0.0, -far * near / (far - near), 0.0),
        );
        let inv_tan = 1.0 / (fov_degrees.to_radians() / 2.0).tan();
        let s = Transform::scale(Vec3::new(inv_tan, inv_tan, 1.0))?;
        Some(s * Transform::from_matrix(persp)?)
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Transform {
        Transform {
            m: self.m_inv,
            m_inv: self.m,
        }
    }

    /// True for the identity.
    pub fn is_identity(&self) -> bool {
        self.m == Mat4::IDENTITY
    }

    /// True when the transform turns a right-handed frame into a left-handed one (negative
    /// determinant of the linear part): normals must then be flipped to keep facing outwards.
    pub fn swaps_handedness(&self) -> bool {
        glam::Mat3::from_mat4(self.m).determinant() < 0.0
    }

    /// Transforms a point.
    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        let r = self.m * p.extend(1.0);
        if r.w == 1.0 {
            Vec3::from_vec4(r)
        } else {
            Vec3::from_vec4(r) / r.w
        }
    }

    /// Transforms a point known to be affine (w stays 1), and bounds the rounding error of the
    /// result: |error| ≤ γ₃ (|m₀₀x| + |m₀₁y| + |m₀₂z| + |m₀₃|) per component (PBRT §6.8.3).
    #[inline]
    pub fn point_with_error(&self, p: Vec3) -> (Vec3, Vec3) {
        let r = self.m.transform_point3a(p);
        let a = self.m.abs();
        let err = gamma(3) * (a.transform_point3a(p.abs()));
        (r, err)
    }

    /// Transforms a point carrying an error bound `p_err`; the result's bound accounts for both
    /// the incoming error and the rounding of this transform (PBRT §6.8.3).
    #[inline]
    pub fn point_with_error_in(&self, p: Vec3, p_err: Vec3) -> (Vec3, Vec3) {
        let r = self.m.transform_point3a(p);
        let a = self.m.abs();
        let err = (gamma(3) + 1.0) * a.transform_vector3a(p_err)
            + gamma(3) * a.transform_point3a(p.abs());
        (r, err)
    }

    /// Transforms a vector (ignores translation).
    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.m.transform_vector3a(v)
    }

    /// Transforms a normal by the inverse transpose; the result is not normalised.
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        self.m_inv.transpose().transform_vector3a(n)
    }

    /// The bounds of a transformed box (the box of its eight transformed corners).
    pub fn bounds(&self, b: &Bounds3) -> Bounds3 {
        let mut out = Bounds3::EMPTY;
        for i in 0..8 {
            out = out.union_point(self.point(b.corner(i)));
        }
        out
    }
}

impl std::ops::Mul for Transform {
    type Output = Transform;
    /// Composition: `(a * b)` applies `b` first, then `a`.
    fn mul(self, rhs: Transform) -> Transform {
        Transform {
            m: self.m * rhs.m,
            m_inv: rhs.m_inv * self.m_inv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_maps_eye_to_origin_and_look_to_plus_z() {
        let t = Transform::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, -7.0), Vec3::Y)
            .unwrap();
        assert!(t.point(Vec3::new(1.0, 2.0, 3.0)).length() < 1e-6);
        let p = t.point(Vec3::new(1.0, 2.0, -7.0));
        assert!((p - Vec3::new(0.0, 0.0, 10.0)).length() < 1e-5);
        // pbrt's camera space is left-handed: world +x appears at camera −x.
        assert!(t.vector(Vec3::X).x < -0.99);
    }

    #[test]
    fn normals_stay_perpendicular_under_non_uniform_scale() {
        let t = Transform::scale(Vec3::new(4.0, 1.0, 1.0)).unwrap()
            * Transform::rotate(30.0, Vec3::Z).unwrap();
        let (tangent, n) = (Vec3::new(1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0));
        assert!(t.vector(tangent).dot(t.normal(n)).abs() < 1e-5);
    }

    #[test]
    fn rotate_is_right_handed() {
        let r = Transform::rotate(90.0, Vec3::Z).unwrap();
        assert!((r.vector(Vec3::X) - Vec3::Y).length() < 1e-6);
        assert!((r.inverse() * r).m.abs_diff_eq(Mat4::IDENTITY, 1e-6));
    }

    #[test]
    fn singular_matrices_are_refused() {
        assert!(Transform::from_matrix(Mat4::ZERO).is_none());
        assert!(Transform::scale(Vec3::new(1.0, 0.0, 1.0)).is_none());
    }
}
