//! What a scene description holds, counted by kind under pbrt-v4's names: what `lancer info`
//! and the Python module's `Scene.info()` report.

use super::desc::{Geometry, SceneDesc, ShapeDesc};
use std::collections::BTreeMap;

/// Counts of what a scene description holds.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DescCounts {
    /// Shapes by kind ([`Geometry::pbrt_name`]), placed directly in the world.
    pub shapes: BTreeMap<&'static str, u64>,
    /// Shapes by kind inside object definitions (instanced).
    pub object_shapes: BTreeMap<&'static str, u64>,
    /// Lights by kind ([`crate::light::LightDesc::count_name`]: the pbrt-v4 name, an
    /// infinite light with an image as `infinite (image)`), area lights excluded.
    pub lights: BTreeMap<&'static str, u64>,
    /// Area lights (shapes that emit), in the world and in object definitions.
    pub area_lights: u64,
    /// Triangles of world shapes.
    pub triangles: u64,
    /// Triangles of all instances (each instance counted with its object's triangles).
    pub instanced_triangles: u64,
}

impl SceneDesc {
    /// Counts shapes and lights by kind, area lights and triangles.
    pub fn counts(&self) -> DescCounts {
        let mut c = DescCounts::default();
        let (tris, area) = count_shapes(&self.shapes, &mut c.shapes);
        c.triangles = tris;
        c.area_lights = area;
        let mut per_object = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            let (t, a) = count_shapes(&o.shapes, &mut c.object_shapes);
            per_object.push(t);
            c.area_lights += a;
        }
        c.instanced_triangles = self
            .instances
            .iter()
            .filter_map(|i| per_object.get(i.object as usize))
            .sum();
        for l in &self.lights {
            *c.lights.entry(l.count_name()).or_default() += 1;
        }
        c
    }
}

/// Adds `shapes` to `kinds`; returns their triangles and area lights.
fn count_shapes(shapes: &[ShapeDesc], kinds: &mut BTreeMap<&'static str, u64>) -> (u64, u64) {
    let (mut tris, mut area) = (0, 0);
    for s in shapes {
        *kinds.entry(s.geometry.pbrt_name()).or_default() += 1;
        if let Geometry::TriangleMesh(m) = &s.geometry {
            tris += m.triangle_count() as u64;
        }
        area += u64::from(s.area_light.is_some());
    }
    (tris, area)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{PackedVec3, Rgb, Transform, Vec3};
    use crate::scene::desc::{AreaLightDesc, InstanceDesc, ObjectDesc};
    use crate::shape::{SphereDesc, TriangleMesh};
    use std::sync::Arc;

    fn shape(geometry: Geometry, emits: bool) -> ShapeDesc {
        ShapeDesc {
            medium_interface: None,
            geometry,
            object_to_world: Transform::IDENTITY,
            reverse_orientation: false,
            material: 0,
            area_light: emits.then_some(AreaLightDesc {
                l: Rgb::ONE,
                two_sided: false,
                spectrum: None,
                power: None,
                image: None,
            }),
            alpha: None,
        }
    }

    /// Two triangles sharing an edge.
    fn quad() -> Geometry {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        Geometry::TriangleMesh(Arc::new(TriangleMesh {
            positions: p.iter().map(|&v| PackedVec3::from(v)).collect(),
            indices: vec![0, 1, 2, 0, 2, 3],
            ..Default::default()
        }))
    }

    #[test]
    fn shapes_lights_and_triangles_are_counted_by_pbrt_kind() {
        let sphere = Geometry::Sphere(SphereDesc {
            radius: 1.0,
            z_min: -1.0,
            z_max: 1.0,
            phi_max: 360.0,
        });
        let point = crate::light::LightDesc::Point(crate::light::PointDesc {
            from: Vec3::ZERO,
            intensity: Rgb::ONE,
        });
        let d = SceneDesc {
            shapes: vec![shape(sphere.clone(), true), shape(quad(), false)],
            objects: vec![ObjectDesc {
                name: "tuft".into(),
                shapes: vec![shape(quad(), true), shape(sphere, false)],
            }],
            instances: vec![
                InstanceDesc {
                    object: 0,
                    object_to_world: Transform::IDENTITY,
                };
                3
            ],
            lights: vec![point.clone(), point],
            ..Default::default()
        };
        let c = d.counts();
        assert_eq!(c.shapes.get("sphere"), Some(&1));
        assert_eq!(c.shapes.get("trianglemesh"), Some(&1));
        assert_eq!(c.object_shapes.get("trianglemesh"), Some(&1));
        assert_eq!(c.object_shapes.get("sphere"), Some(&1));
        assert_eq!(c.lights.get("point"), Some(&2));
        // One emitting sphere in the world, one emitting mesh in the object definition.
        assert_eq!(c.area_lights, 2);
        assert_eq!(c.triangles, 2);
        // Three instances of an object holding 2 triangles.
        assert_eq!(c.instanced_triangles, 6);
    }
}
