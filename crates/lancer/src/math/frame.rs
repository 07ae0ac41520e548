//! Orthonormal frames: shading coordinates where the normal is +z; the rotation between two
//! directions.

use super::{Vec3, cross};

/// An orthonormal basis (x, y, z). BSDFs work in the frame where the shading normal is `z`, so
/// that cos θ is simply the z component of a direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// First tangent.
    pub x: Vec3,
    /// Second tangent.
    pub y: Vec3,
    /// Normal.
    pub z: Vec3,
}

impl Frame {
    /// A frame around the unit vector `z`, branch-free (Duff et al. 2017, "Building an
    /// orthonormal basis, revisited").
    #[inline]
    pub fn from_z(z: Vec3) -> Frame {
        let sign = 1.0f32.copysign(z.z);
        let a = -1.0 / (sign + z.z);
        let b = z.x * z.y * a;
        let x = Vec3::new(1.0 + sign * z.x * z.x * a, sign * b, -sign * z.x);
        let y = Vec3::new(b, sign + z.y * z.y * a, -z.y);
        Frame { x, y, z }
    }

    /// A frame with normal `z` whose first tangent is `x` made perpendicular to it (falls back
    /// to [`Frame::from_z`] if `x` is parallel to `z`).
    #[inline]
    pub fn from_xz(x: Vec3, z: Vec3) -> Frame {
        let x = x - z * z.dot(x);
        match x.try_normalize() {
            Some(x) => Frame {
                x,
                y: cross(z, x),
                z,
            },
            None => Frame::from_z(z),
        }
    }

    /// World → local coordinates.
    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.x), v.dot(self.y), v.dot(self.z))
    }

    /// Local → world coordinates.
    #[inline]
    pub fn from_local(&self, v: Vec3) -> Vec3 {
        self.x * v.x + self.y * v.y + self.z * v.z
    }
}

/// The rotation taking unit `from` to unit `to` (pbrt-v4's `RotateFromTo`: two reflections,
/// through a helper axis chosen away from both), as its three rows.
pub fn rotate_from_to(from: Vec3, to: Vec3) -> [Vec3; 3] {
    let refl = if from.x.abs() < 0.72 && to.x.abs() < 0.72 {
        Vec3::X
    } else if from.y.abs() < 0.72 && to.y.abs() < 0.72 {
        Vec3::Y
    } else {
        Vec3::Z
    };
    let (u, v) = (refl - from, refl - to);
    let (uu, vv, uv) = (u.dot(u), v.dot(v), u.dot(v));
    // r_ij = δ_ij − 2/(u·u)·u_i u_j − 2/(v·v)·v_i v_j + 4(u·v)/((u·u)(v·v))·v_i u_j.
    let row = |i: usize| {
        Vec3::from_array(std::array::from_fn(|j| {
            f32::from(i == j) - 2.0 / uu * u[i] * u[j] - 2.0 / vv * v[i] * v[j]
                + 4.0 * uv / (uu * vv) * v[i] * u[j]
        }))
    };
    [row(0), row(1), row(2)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::normalize;

    #[test]
    fn frame_is_orthonormal_and_round_trips() {
        for z in [
            Vec3::Z,
            -Vec3::Z,
            normalize(Vec3::new(0.3, -0.5, 0.8)),
            Vec3::X,
        ] {
            let f = Frame::from_z(z);
            assert!((f.x.length() - 1.0).abs() < 1e-5 && (f.y.length() - 1.0).abs() < 1e-5);
            assert!(f.x.dot(f.y).abs() < 1e-5 && f.x.dot(f.z).abs() < 1e-5);
            assert!((cross(f.x, f.y) - f.z).length() < 1e-5, "right-handed");
            let v = Vec3::new(0.1, 0.7, -0.2);
            assert!((f.from_local(f.to_local(v)) - v).length() < 1e-5);
        }
    }
}
