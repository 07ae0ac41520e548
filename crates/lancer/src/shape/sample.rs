//! Points sampled on shapes, so that a shape can be an area light: a point uniform by area
//! (density 1/A), with the geometric normal the intersection code gives at that point, which
//! decides the side an area light emits from.
//!
//! Quadrics are sampled in object space and moved to the world; like pbrt, their world area
//! assumes the transform scales uniformly.

use super::Shape;
use super::hit::ShapeSample;
use super::triangle::TriangleMesh;
use crate::math::{Vec2, cross};
use crate::sampling::sample_uniform_triangle;

impl Shape {
    /// Surface area, world space (0 for infinite planes, which cannot emit).
    pub fn area(&self) -> f32 {
        match self {
            // The quadrics: their object-space area (closed forms beside each shape) scaled
            // by the placement.
            Shape::Sphere(s) => s.object_area() * s.placement.area_scale(),
            Shape::Disk(d) => d.object_area() * d.placement.area_scale(),
            Shape::Cylinder(c) => c.object_area() * c.placement.area_scale(),
            Shape::Cone(c) => c.object_area() * c.placement.area_scale(),
            Shape::Paraboloid(p) => p.object_area() * p.placement.area_scale(),
            Shape::Hyperboloid(h) => h.object_area() * h.placement.area_scale(),
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
            // The quadrics and the box: a point sampled in object space, then placed.
            Shape::Sphere(s) => {
                let (p, n) = s.sample_object(u);
                Some(s.placement.place(p, n))
            }
            Shape::Disk(d) => {
                let (p, n) = d.sample_object(u);
                Some(d.placement.place(p, n))
            }
            Shape::Cylinder(c) => {
                let (p, n) = c.sample_object(u);
                Some(c.placement.place(p, n))
            }
            Shape::Cone(c) => {
                let (p, n) = c.sample_object(u);
                Some(c.placement.place(p, n))
            }
            Shape::Paraboloid(q) => {
                let (p, n) = q.sample_object(u);
                Some(q.placement.place(p, n))
            }
            Shape::Hyperboloid(h) => {
                let (p, n) = h.sample_object(u);
                Some(h.placement.place(p, n))
            }
            Shape::Box(b) => {
                let (p, n) = b.sample_object(u);
                Some(b.placement.place(p, n))
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
