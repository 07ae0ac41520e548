//! Each kind of light's [`LightBounds`] (pbrt-v4's `Bounds()` of each light): where it is, its
//! power and the cone of directions it emits in.

use super::Light;
use super::bounds::{DirectionCone, LightBounds, LightExtent, safe_acos};
use crate::math::Bounds3;
use crate::shape::{Shape, TriangleMesh};
use std::f32::consts::PI;

impl Light {
    /// The bounds of this light (pbrt-v4's `Light::Bounds`); distant and infinite lights have
    /// none, and lights that emit nothing are left out.
    pub fn extent(&self, shapes: &[Shape], meshes: &[TriangleMesh]) -> LightExtent {
        let max = |c: crate::math::Rgb| c.x.max(c.y).max(c.z);
        let b = match self {
            // A point emits everywhere: normal cone = sphere, no spread needed.
            Light::Point { p, intensity } => LightBounds {
                bounds: Bounds3::from_point(*p),
                phi: 4.0 * PI * max(*intensity),
                normals: DirectionCone::ENTIRE_SPHERE,
                cos_theta_e: (PI / 2.0).cos(),
                two_sided: false,
            },
            // A spot: full intensity inside θ_start, falling off over θ_end − θ_start.
            Light::Spot {
                p,
                axis,
                intensity,
                cos_falloff_start,
                cos_falloff_end,
            } => {
                let mut cos_theta_e =
                    (safe_acos(*cos_falloff_end) - safe_acos(*cos_falloff_start)).cos();
                // Slack for round-off in the importance's cos θ' (as pbrt-v4).
                if cos_theta_e == 1.0 && cos_falloff_end != cos_falloff_start {
                    cos_theta_e = 0.999;
                }
                LightBounds {
                    bounds: Bounds3::from_point(*p),
                    phi: 4.0 * PI * max(*intensity),
                    normals: DirectionCone {
                        w: *axis,
                        cos_theta: *cos_falloff_start,
                    },
                    cos_theta_e,
                    two_sided: false,
                }
            }
            // An area light: φ = π·A·L, its normals' cone, emission over a hemisphere.
            Light::Area {
                prim,
                l,
                two_sided,
                area,
                ..
            } => {
                let shape = &shapes[*prim as usize];
                let normals = match shape {
                    // Flat shapes: one normal, as the shape orients it.
                    Shape::Triangle(_) | Shape::Disk(_) => shape
                        .sample_area(crate::math::Vec2::splat(1.0 / 3.0), meshes)
                        .map(|s| DirectionCone {
                            w: s.n,
                            cos_theta: 1.0,
                        })
                        .unwrap_or(DirectionCone::ENTIRE_SPHERE),
                    _ => DirectionCone::ENTIRE_SPHERE,
                };
                let bounds = shape.bounds();
                if bounds.is_empty() || !bounds.diagonal().is_finite() {
                    return LightExtent::Dark;
                }
                LightBounds {
                    bounds,
                    phi: max((*l).into()) * area * PI,
                    normals,
                    cos_theta_e: (PI / 2.0).cos(),
                    two_sided: *two_sided,
                }
            }
            // Image-shaped emitters at a point: bounded by their total power over the whole
            // sphere of directions (coarser than pbrt-v4's per-light cones, but never zero
            // where they shine, so the choice stays unbiased).
            Light::Goniometric(g) => LightBounds {
                bounds: Bounds3::from_point(g.position()),
                phi: g.power(),
                normals: DirectionCone::ENTIRE_SPHERE,
                cos_theta_e: (PI / 2.0).cos(),
                two_sided: false,
            },
            Light::Projection(pl) => LightBounds {
                bounds: Bounds3::from_point(pl.position()),
                phi: pl.power(),
                normals: DirectionCone::ENTIRE_SPHERE,
                cos_theta_e: (PI / 2.0).cos(),
                two_sided: false,
            },
            Light::Distant { .. }
            | Light::UniformInfinite { .. }
            | Light::ImageInfinite(_)
            | Light::PortalInfinite(_)
            | Light::Sunsky(_) => {
                return LightExtent::Unbounded;
            }
        };
        if b.phi > 0.0 && b.phi.is_finite() {
            LightExtent::Bounded(b)
        } else {
            LightExtent::Dark
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;

    #[test]
    fn importance_bounds_the_true_contribution() {
        // A point light of intensity I: the irradiance at p on a surface of normal n is
        // I·cos θᵢ/d², and φ = 4π·I, so importance/(4π) must be at least it.
        let light = Light::Point {
            p: Vec3::new(0.3, 1.0, -0.2),
            intensity: crate::math::Rgb::splat(2.0),
        };
        let LightExtent::Bounded(b) = light.extent(&[], &[]) else {
            panic!("a point light has bounds")
        };
        let mut rng = crate::sampling::Pcg32::new(3, 4);
        for _ in 0..1000 {
            let p = Vec3::new(rng.uniform(), rng.uniform(), rng.uniform()) * 4.0 - 2.0;
            let n = crate::sampling::sample_uniform_sphere(crate::math::Vec2::new(
                rng.uniform(),
                rng.uniform(),
            ));
            let d = Vec3::new(0.3, 1.0, -0.2) - p;
            let e = 2.0 * n.dot(crate::math::normalize(d)).abs() / d.length_squared();
            assert!(b.importance(p, n) / (4.0 * PI) >= e * 0.9999, "{p:?}");
        }
    }
}
