//! pbrt-v4's `spherical` camera: every pixel looks in one direction of the whole sphere, from a
//! single point.
//!
//! With (u, v) = the raster point divided by the image's size:
//! - `equirectangular`: θ = π·v, φ = 2π·u, d = (sin θ cos φ, sin θ sin φ, cos θ);
//! - `equalarea`: d = the equal-area octahedral map of (u, v) (points just outside [0, 1]²,
//!   where the pixel filter reaches, are mirrored back in as pbrt-v4's `WrapEqualAreaSquare`).
//!
//! Then y and z are swapped, as pbrt-v4 does, so that the poles are camera space's ±y (the
//! camera's up): an equirectangular image's top row looks up, its middle row along the horizon,
//! with the viewing direction +z a quarter of the way from its left edge (and −x at its
//! centre); an equal-area image's centre looks straight up and its corners straight down.

use super::lens::SphericalMapping;
use crate::math::{PI, Vec2, Vec3};
use crate::sampling::{equal_area_sphere_to_square, equal_area_square_to_sphere};

/// pbrt-v4's `WrapEqualAreaSquare`: a point up to one square outside [0, 1]² mirrored to the
/// point of the square that neighbours it on the sphere (across u = 0 or 1: mirrored in u and
/// reflected about v = ½; across v = 0 or 1: the other way round).
pub fn wrap_equal_area_square(mut uv: Vec2) -> Vec2 {
    if uv.x < 0.0 {
        uv = Vec2::new(-uv.x, 1.0 - uv.y);
    } else if uv.x > 1.0 {
        uv = Vec2::new(2.0 - uv.x, 1.0 - uv.y);
    }
    if uv.y < 0.0 {
        uv = Vec2::new(1.0 - uv.x, -uv.y);
    } else if uv.y > 1.0 {
        uv = Vec2::new(1.0 - uv.x, 2.0 - uv.y);
    }
    uv
}

/// The camera-space direction (unit) that image point `uv` ∈ [0, 1]² looks along.
#[inline]
pub fn spherical_direction(mapping: SphericalMapping, uv: Vec2) -> Vec3 {
    let d = match mapping {
        SphericalMapping::Equirectangular => {
            let (theta, phi) = (PI * uv.y, 2.0 * PI * uv.x);
            let (st, ct) = theta.sin_cos();
            let (sp, cp) = phi.sin_cos();
            Vec3::new(st.clamp(-1.0, 1.0) * cp, st.clamp(-1.0, 1.0) * sp, ct)
        }
        SphericalMapping::EqualArea => equal_area_square_to_sphere(wrap_equal_area_square(uv)),
    };
    Vec3::new(d.x, d.z, d.y)
}

/// The inverse of [`spherical_direction`]: the image point in [0, 1]² of a unit camera-space
/// direction.
pub fn spherical_uv(mapping: SphericalMapping, d: Vec3) -> Vec2 {
    // Undo the swap of y and z.
    let d = Vec3::new(d.x, d.z, d.y);
    match mapping {
        SphericalMapping::Equirectangular => {
            let theta = d.z.clamp(-1.0, 1.0).acos();
            let mut phi = d.y.atan2(d.x);
            if phi < 0.0 {
                phi += 2.0 * PI;
            }
            Vec2::new(phi / (2.0 * PI), theta / PI)
        }
        SphericalMapping::EqualArea => equal_area_sphere_to_square(d),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[track_caller]
    fn close(a: Vec3, b: Vec3) {
        assert!((a - b).length() < 1e-5, "{a} vs {b}");
    }

    #[test]
    fn equirectangular_directions_by_hand() {
        let m = SphericalMapping::Equirectangular;
        // Top row: θ = 0, straight up camera space's +y (after the y/z swap).
        close(spherical_direction(m, Vec2::new(0.3, 0.0)), Vec3::Y);
        // Bottom row: −y.
        close(spherical_direction(m, Vec2::new(0.7, 1.0)), -Vec3::Y);
        // The horizon (v = ½): φ = 0 looks along +x, φ = π/2 (u = ¼) along +z (the camera's
        // viewing direction), φ = π along −x.
        close(spherical_direction(m, Vec2::new(0.0, 0.5)), Vec3::X);
        close(spherical_direction(m, Vec2::new(0.25, 0.5)), Vec3::Z);
        close(spherical_direction(m, Vec2::new(0.5, 0.5)), -Vec3::X);
        // θ = π/4, φ = 3π/2: (sin θ cos φ, cos θ, sin θ sin φ) = (0, √½, −√½).
        let h = 0.5f32.sqrt();
        close(
            spherical_direction(m, Vec2::new(0.75, 0.25)),
            Vec3::new(0.0, h, -h),
        );
    }

    #[test]
    fn equal_area_directions_by_hand() {
        let m = SphericalMapping::EqualArea;
        // The centre of the octahedral square is +z before the swap: +y (up) after it; the
        // corners are −z: −y.
        close(spherical_direction(m, Vec2::new(0.5, 0.5)), Vec3::Y);
        close(spherical_direction(m, Vec2::new(0.0, 0.0)), -Vec3::Y);
        close(spherical_direction(m, Vec2::new(1.0, 1.0)), -Vec3::Y);
        // Edge midpoints of the inner diamond are on the equator: u = 1, v = ½ is +x;
        // u = ½, v = 1 is +y before the swap, +z after it.
        close(spherical_direction(m, Vec2::new(1.0, 0.5)), Vec3::X);
        close(spherical_direction(m, Vec2::new(0.5, 1.0)), Vec3::Z);
        close(spherical_direction(m, Vec2::new(0.5, 0.0)), -Vec3::Z);
    }

    #[test]
    fn mappings_round_trip() {
        for m in [
            SphericalMapping::EqualArea,
            SphericalMapping::Equirectangular,
        ] {
            for i in 0..37 {
                for j in 1..19 {
                    let uv = Vec2::new((i as f32 + 0.3) / 37.0, (j as f32 - 0.4) / 19.0);
                    let d = spherical_direction(m, uv);
                    assert!((d.length() - 1.0).abs() < 1e-5);
                    let back = spherical_uv(m, d);
                    assert!((back - uv).length() < 1e-4, "{m:?}: {uv} → {d} → {back}");
                }
            }
        }
    }

    #[test]
    fn points_outside_the_square_wrap_to_their_neighbours_on_the_sphere() {
        // Just left of u = 0 at v = 0.2 is the point just right of u = 0 at v = 0.8: the
        // octahedral map's left edge is glued to itself, mirrored about v = ½.
        let m = SphericalMapping::EqualArea;
        let eps = 1e-3;
        let outside = spherical_direction(m, Vec2::new(-eps, 0.2));
        close(outside, spherical_direction(m, Vec2::new(eps, 0.8)));
        // And it is close to the direction just inside at v = 0.2 (continuity on the sphere).
        let inside = spherical_direction(m, Vec2::new(eps, 0.2));
        assert!((outside - inside).length() < 0.02, "{outside} vs {inside}");
        assert_eq!(
            wrap_equal_area_square(Vec2::new(0.3, 1.1)),
            Vec2::new(0.7, 0.9)
        );
        assert_eq!(
            wrap_equal_area_square(Vec2::new(1.25, 0.5)),
            Vec2::new(0.75, 0.5)
        );
    }
}
