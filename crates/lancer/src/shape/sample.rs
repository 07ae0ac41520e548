//! Points sampled on shapes, so that a shape can be an area light: a point uniform by area
//! (density 1/A), with the geometric normal the intersection code gives at that point, which
//! decides the side an area light emits from.
//!
//! Quadrics are sampled in object space and moved to the world; like pbrt, their world area
//! assumes the transform scales uniformly.

use super::{Placement, Shape, TriangleMesh};
use crate::math::{Vec2, Vec3, cross};
use crate::sampling::sample_uniform_triangle;

/// A point on a shape's surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeSample {
    /// The point, world space.
    pub p: Vec3,
    /// Geometric normal there, unit length, oriented as [`Shape::interaction`] orients it.
    pub n: Vec3,
}

/// The factor by which a placement scales areas: |det M|^(2/3) (exact for similarities).
fn area_scale(placement: &Placement) -> f32 {
    let m = placement.to_world.m;
    let det = glam::Mat3::from_mat4(m).determinant().abs();
    det.powf(2.0 / 3.0)
}

/// An object-space point and outward normal moved to the world, the normal flipped as
/// [`super::SurfaceInteraction::from_object`] flips it.
fn placed(placement: &Placement, p: Vec3, n: Vec3) -> ShapeSample {
    let n = if placement.flip_normal { -n } else { n };
    ShapeSample {
        p: placement.to_world.point(p),
        n: placement.to_world.normal(n).normalize_or_zero(),
    }
}

impl Shape {
    /// Surface area, world space (0 for infinite planes, which cannot emit).
    pub fn area(&self) -> f32 {
        match self {
            // A sphere zone's area depends only on its height: A = φmax·r·(zmax − zmin)
            // (Archimedes).
            Shape::Sphere(s) => {
                s.phi_max * s.radius * (s.z_max - s.z_min) * area_scale(&s.placement)
            }
            // A = φmax/2 · (r² − rᵢ²).
            Shape::Disk(d) => {
                0.5 * d.phi_max
                    * (d.radius * d.radius - d.inner_radius * d.inner_radius)
                    * area_scale(&d.placement)
            }
            // A = (zmax − zmin)·r·φmax.
            Shape::Cylinder(c) => {
                (c.z_max - c.z_min) * c.radius * c.phi_max * area_scale(&c.placement)
            }
            Shape::Cone(c) => c.object_area() * area_scale(&c.placement),
            Shape::Paraboloid(p) => p.object_area() * area_scale(&p.placement),
            Shape::Hyperboloid(h) => h.object_area() * area_scale(&h.placement),
            Shape::Box(b) => b.area(),
            // No closed form: SDF objects cannot emit (the scene builder refuses them).
            Shape::Plane(_) | Shape::Sdf(_) => 0.0,
            // Voxel grids cannot emit (Scene::build refuses them as area lights).
            Shape::Voxels(_) => 0.0,
            // A = |(p₁ − p₀) × (p₂ − p₀)| / 2.
            Shape::Triangle(t) => {
                let [p0, p1, p2] = t.vertices();
                0.5 * cross(p1 - p0, p2 - p0).length()
            }
            // pbrt's approximation: control polygon length × mean width.
            Shape::Curve(c) => c.area(),
            // A = ∫∫ |∂p/∂u × ∂p/∂v| du dv.
            Shape::Bilinear(b) => b.area(),
        }
    }

    /// A point uniform by area on the shape; `None` for planes, voxel grids, SDF objects and
    /// curves (which pbrt-v4 cannot sample either).
    pub fn sample_area(&self, u: Vec2, meshes: &[TriangleMesh]) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(s) => {
                // Uniform in z and φ is uniform by area on a sphere zone (Archimedes again).
                let z = s.z_min + u.x * (s.z_max - s.z_min);
                let phi = u.y * s.phi_max;
                let rho = (s.radius * s.radius - z * z).max(0.0).sqrt();
                let p = Vec3::new(rho * phi.cos(), rho * phi.sin(), z);
                Some(placed(&s.placement, p, p / s.radius))
            }
            Shape::Disk(d) => {
                // r² uniform between rᵢ² and r² is uniform by area on the annulus.
                let (ri2, r2) = (d.inner_radius * d.inner_radius, d.radius * d.radius);
                let r = (ri2 + u.x * (r2 - ri2)).sqrt();
                let phi = u.y * d.phi_max;
                let p = Vec3::new(r * phi.cos(), r * phi.sin(), d.height);
                Some(placed(&d.placement, p, Vec3::Z))
            }
            Shape::Cylinder(c) => {
                let z = c.z_min + u.x * (c.z_max - c.z_min);
                let phi = u.y * c.phi_max;
                let (x, y) = (c.radius * phi.cos(), c.radius * phi.sin());
                Some(placed(
                    &c.placement,
                    Vec3::new(x, y, z),
                    Vec3::new(x, y, 0.0) / c.radius,
                ))
            }
            Shape::Cone(c) => {
                let (p, n) = c.sample_object(u);
                Some(placed(&c.placement, p, n))
            }
            Shape::Paraboloid(q) => {
                let (p, n) = q.sample_object(u);
                Some(placed(&q.placement, p, n))
            }
            Shape::Hyperboloid(h) => {
                let (p, n) = h.sample_object(u);
                Some(placed(&h.placement, p, n))
            }
            Shape::Box(b) => {
                let (p, n) = b.sample_object(u);
                Some(placed(&b.placement, p, n))
            }
            Shape::Plane(_) | Shape::Voxels(_) | Shape::Sdf(_) | Shape::Curve(_) => None,
            Shape::Bilinear(b) => {
                let (p, uv) = b.sample_uv(u);
                Some(ShapeSample {
                    p,
                    n: b.normal_at(uv.x, uv.y),
                })
            }
            Shape::Triangle(t) => {
                let [b0, b1, b2] = sample_uniform_triangle(u);
                let [p0, p1, p2] = t.vertices();
                let p = b0 * p0 + b1 * p1 + b2 * p2;
                // The same orientation rule as Triangle::interaction.
                let mesh = &meshes[t.mesh as usize];
                let mut n = cross(p0 - p2, p1 - p2).normalize_or_zero();
                if !mesh.normals.is_empty() {
                    let v = mesh.vertices(t.index);
                    let ns =
                        b0 * mesh.normal(v[0]) + b1 * mesh.normal(v[1]) + b2 * mesh.normal(v[2]);
                    if n.dot(ns) < 0.0 {
                        n = -n;
                    }
                } else if mesh.flip_normal {
                    n = -n;
                }
                Some(ShapeSample { p, n })
            }
        }
    }
}
