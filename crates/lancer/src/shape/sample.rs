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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{PackedVec3, Transform, Vec3};
    use crate::shape::{
        Cone, Cuboid, Cylinder, Disk, Hyperboloid, Paraboloid, Placement, Plane, Sphere, Triangle,
    };
    use std::f64::consts::PI;

    #[test]
    fn world_areas_scale_by_the_placement() {
        // Scaled by 2 about (5, 0, 0): every area ×4.
        let pl = Placement::new(
            Transform::translate(Vec3::new(5.0, 0.0, 0.0))
                * Transform::scale(Vec3::splat(2.0)).unwrap(),
            false,
        );
        let cases: Vec<(Shape, f64)> = vec![
            // 4πr², r = 1.
            (
                Shape::Sphere(Box::new(Sphere::new(pl, 1.0, -1.0, 1.0, 360.0))),
                4.0 * PI,
            ),
            // πr², r = 1.
            (
                Shape::Disk(Box::new(Disk::new(pl, 0.0, 1.0, 0.0, 360.0))),
                PI,
            ),
            // 2πr·h = 2π·1·2.
            (
                Shape::Cylinder(Box::new(Cylinder::new(pl, 1.0, -1.0, 1.0, 360.0))),
                4.0 * PI,
            ),
            // πr·√(h² + r²) = π·√2 for r = h = 1.
            (
                Shape::Cone(Box::new(Cone::new(pl, 1.0, 1.0, 360.0))),
                PI * 2f64.sqrt(),
            ),
            // π/6·(5√5 − 1).
            (
                Shape::Paraboloid(Box::new(Paraboloid::new(pl, 1.0, 0.0, 1.0, 360.0))),
                PI / 6.0 * (5.0 * 5f64.sqrt() - 1.0),
            ),
            // A cylinder r = 1, h = 2 as a hyperboloid: 4π.
            (
                Shape::Hyperboloid(Box::new(
                    Hyperboloid::new(
                        pl,
                        Vec3::new(1.0, 0.0, -1.0),
                        Vec3::new(1.0, 0.0, 1.0),
                        360.0,
                    )
                    .unwrap(),
                )),
                4.0 * PI,
            ),
            // The unit cube: 6.
            (
                Shape::Box(Box::new(Cuboid::new(pl, Vec3::ZERO, Vec3::ONE))),
                6.0,
            ),
        ];
        for (i, (shape, object_area)) in cases.into_iter().enumerate() {
            let (got, want) = (shape.area() as f64, 4.0 * object_area);
            assert!(
                (got - want).abs() < 1e-5 * want,
                "case {i}: {got} vs {want}"
            );
        }
        let plane = Shape::Plane(Box::new(Plane::new(Vec3::ZERO, Vec3::Z).unwrap()));
        assert_eq!(plane.area(), 0.0);
        assert!(plane.sample_area(Vec2::splat(0.5), &[]).is_none());
    }

    #[test]
    fn placed_samples_keep_the_intersection_orientation() {
        // A unit sphere at (0, 0, 10) with reverse orientation: u = (½, 0) is z = 0, φ = 0,
        // the object point (1, 0, 0), world (1, 0, 10), normal flipped inwards.
        let pl = Placement::new(Transform::translate(Vec3::new(0.0, 0.0, 10.0)), true);
        let s = Shape::Sphere(Box::new(Sphere::new(pl, 1.0, -1.0, 1.0, 360.0)));
        let smp = s.sample_area(Vec2::new(0.5, 0.0), &[]).unwrap();
        assert!(
            (smp.p - Vec3::new(1.0, 0.0, 10.0)).length() < 1e-6,
            "{}",
            smp.p
        );
        assert!((smp.n + Vec3::X).length() < 1e-6, "{}", smp.n);
    }

    #[test]
    fn triangle_area_and_samples() {
        // (0, 0, 0), (2, 0, 0), (0, 2, 0): A = |(2, 0, 0) × (0, 2, 0)|/2 = 2; the geometric
        // normal (p₀ − p₂) × (p₁ − p₂) ∝ +z, −z when the mesh is reversed.
        let p = [
            PackedVec3::ZERO,
            PackedVec3::new(2.0, 0.0, 0.0),
            PackedVec3::new(0.0, 2.0, 0.0),
        ];
        let tri = Shape::Triangle(Triangle {
            p,
            mesh: 0,
            index: 0,
        });
        assert_eq!(tri.area(), 2.0);
        for flip in [false, true] {
            let mesh = TriangleMesh {
                positions: p.to_vec(),
                indices: vec![0, 1, 2],
                flip_normal: flip,
                ..Default::default()
            };
            for u in [
                Vec2::new(0.1, 0.2),
                Vec2::new(0.9, 0.5),
                Vec2::new(0.5, 0.99),
            ] {
                let s = tri.sample_area(u, std::slice::from_ref(&mesh)).unwrap();
                assert!(s.p.z == 0.0 && s.p.x >= 0.0 && s.p.y >= 0.0 && s.p.x + s.p.y <= 2.0);
                assert_eq!(s.n, if flip { -Vec3::Z } else { Vec3::Z });
            }
        }
    }
}
