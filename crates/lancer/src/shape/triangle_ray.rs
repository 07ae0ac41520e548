//! The part of the watertight ray–triangle test that depends on the ray alone, computed once
//! per ray for every triangle (and packet of triangles) it is tested against. A leaf module:
//! the shape files and the accelerators use it.

use crate::math::Vec3;
use crate::ray::Ray;

/// The part of the watertight test that depends on the ray alone, computed once per ray
/// rather than once per triangle: the axis `kz` along which the ray runs most (it becomes z),
/// and the shear (sx, sy, sz) that turns the permuted direction into +z.
#[derive(Clone, Copy, Debug)]
pub struct TriangleRay {
    kz: u8,
    /// (kz + 1) mod 3 and (kz + 2) mod 3, kept rather than recomputed for every packet.
    kxy: [u8; 2],
    shear: Vec3,
}

impl TriangleRay {
    /// Precomputes the permutation and shear for `ray`.
    #[inline]
    pub fn new(ray: &Ray) -> TriangleRay {
        let ad = ray.d.abs();
        let kz = if ad.x > ad.y {
            if ad.x > ad.z { 0 } else { 2 }
        } else if ad.y > ad.z {
            1
        } else {
            2
        };
        let mut pre = TriangleRay {
            kz,
            kxy: [(kz + 1) % 3, (kz + 2) % 3],
            shear: Vec3::ZERO,
        };
        let d = pre.permute(ray.d);
        // One vector division for the three: each lane is rounded as its scalar quotient
        // would be, and the three scalar divisions stood in a row on every ray.
        pre.shear = Vec3::new(-d.x, -d.y, 1.0) / Vec3::splat(d.z);
        pre
    }

    /// The axis kz along which the ray's direction is largest (0, 1, 2 for x, y, z); the
    /// permutation is (kx, ky, kz) = (kz + 1, kz + 2, kz) mod 3.
    #[inline(always)]
    pub fn kz(&self) -> usize {
        self.kz as usize
    }

    /// The two other axes (kx, ky) = ((kz + 1) mod 3, (kz + 2) mod 3).
    #[inline(always)]
    pub fn kxy(&self) -> (usize, usize) {
        (self.kxy[0] as usize, self.kxy[1] as usize)
    }

    /// The shear (S_x, S_y, S_z) = (−d_x/d_z, −d_y/d_z, 1/d_z) of the permuted direction.
    #[inline(always)]
    pub fn shear(&self) -> Vec3 {
        self.shear
    }

    /// (v[kx], v[ky], v[kz]) with kx, ky the two other axes in cyclic order.
    #[inline(always)]
    pub(super) fn permute(&self, v: Vec3) -> Vec3 {
        match self.kz {
            0 => Vec3::new(v.y, v.z, v.x),
            1 => Vec3::new(v.z, v.x, v.y),
            _ => v,
        }
    }
}
