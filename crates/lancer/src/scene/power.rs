//! Area lights given by their power (pbrt-v4's `"float power"` on a `diffuse` area light):
//! each primitive a shape becomes emits the power Φ on its own, so its radiance is
//! `L · Φ / (π · sides · A)` with `sides` 2 for a two-sided light and `A` the primitive's area
//! as pbrt-v4 measures it ([`crate::shape::Shape::emission_area`]; a diffuse emitter of
//! radiance L and area A emits Φ = π·L·A per side).

use crate::math::Rgb;
use std::f32::consts::PI;

/// The radiance of one primitive of an area light of radiance `l` (already normalised to unit
/// luminance for spectra, as pbrt-v4 does) given by power `phi`:
/// `l · Φ / (π · sides · A)`. A primitive of zero area keeps `l` (pbrt-v4 would divide by 0;
/// such a primitive is never hit nor sampled).
pub fn power_radiance(l: Rgb, phi: f32, two_sided: bool, area: f32) -> Rgb {
    let sides = if two_sided { 2.0 } else { 1.0 };
    let k = PI * sides * area;
    if k > 0.0 { l * (phi / k) } else { l }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Transform, Vec3};
    use crate::shape::{Disk, Placement, Shape, Sphere};

    #[test]
    fn a_unit_disk_of_power_pi_has_radiance_one_over_pi() {
        // A = π·1²: Φ = π gives L = π / (π·π) = 1/π per unit L.
        let d = Shape::Disk(Box::new(Disk::new(
            Placement::new(Transform::IDENTITY, false),
            0.0,
            1.0,
            0.0,
            360.0,
        )));
        let a = d.emission_area();
        assert!((a - PI).abs() < 1e-5, "{a}");
        let l = power_radiance(Rgb::ONE, PI, false, a);
        assert!((l.x - 1.0 / PI).abs() < 1e-6, "{l:?}");
        // Two-sided: half the radiance per side.
        let l2 = power_radiance(Rgb::new(2.0, 1.0, 0.5), PI, true, a);
        assert!((l2.x - 1.0 / PI).abs() < 1e-6 && (l2.z - 0.25 / PI).abs() < 1e-6);
    }

    #[test]
    fn a_scaled_sphere_uses_its_object_space_area() {
        // Radius 0.5 scaled by 4: pbrt-v4 divides by 4π·0.25 = π, not by the world area 16π.
        let s = Shape::Sphere(Box::new(Sphere::new(
            Placement::new(Transform::scale(Vec3::splat(4.0)).unwrap(), false),
            0.5,
            -0.5,
            0.5,
            360.0,
        )));
        let a = s.emission_area();
        assert!((a - PI).abs() < 1e-5, "{a}");
        let l = power_radiance(Rgb::ONE, 10.0, false, a);
        // 10 / (π·π) = 1.01321.
        assert!((l.y - 1.013_211_8).abs() < 1e-5, "{l:?}");
    }

    #[test]
    fn zero_area_keeps_the_radiance() {
        assert_eq!(power_radiance(Rgb::ONE, 5.0, false, 0.0), Rgb::ONE);
    }
}
