//! The description's validation rules, one message per rule.

use super::*;
use crate::math::{Rgb, Vec3};
use crate::shape::{
    BoxDesc, ConeDesc, HyperboloidDesc, ParaboloidDesc, PlaneDesc, SphereDesc, TriangleMesh,
};
use std::sync::Arc;

fn sphere(radius: f32) -> Geometry {
    Geometry::Sphere(SphereDesc {
        radius,
        z_min: -1.0,
        z_max: 1.0,
        phi_max: 360.0,
    })
}

#[test]
fn each_geometry_rule_has_one_message() {
    assert_eq!(sphere(1.0).validate(), Ok(()));
    assert_eq!(
        sphere(0.0).validate(),
        Err(RuleError::on(&["radius"], "radius must be positive, got 0"))
    );
    assert_eq!(
        sphere(f32::NAN).validate(),
        Err(RuleError::on(
            &["radius"],
            "radius must be positive, got NaN"
        ))
    );
    let cone = Geometry::Cone(ConeDesc {
        radius: 1.0,
        height: -2.0,
        phi_max: 360.0,
    });
    assert_eq!(
        cone.validate(),
        Err(RuleError::on(
            &["height"],
            "height must be positive, got -2"
        ))
    );
    let paraboloid = Geometry::Paraboloid(ParaboloidDesc {
        radius: 1.0,
        z_min: -3.0,
        z_max: -1.0,
        phi_max: 360.0,
    });
    assert_eq!(
        paraboloid.validate(),
        Err(RuleError::on(&["z_max"], "zmax must be positive, got -1"))
    );
    let flat = Geometry::Hyperboloid(HyperboloidDesc {
        p1: Vec3::new(1.0, 0.0, 0.5),
        p2: Vec3::new(0.0, 1.0, 0.5),
        phi_max: 360.0,
    });
    assert_eq!(
        flat.validate(),
        Err(RuleError::on(
            &["p1", "p2"],
            "the hyperboloid's \"p1\" [1, 0, 0.5] and \"p2\" [0, 1, 0.5] must be finite and at \
             different heights (at one height the swept segment is a flat annulus: use a disk)"
        ))
    );
    let inverted = Geometry::Box(BoxDesc {
        min: Vec3::new(0.0, 0.0, 1.0),
        max: Vec3::ONE,
    });
    assert_eq!(
        inverted.validate(),
        Err(RuleError::on(
            &["min", "max"],
            "the box's \"min\" [0, 0, 1] must be finite and below its \"max\" [1, 1, 1] on \
             every axis"
        ))
    );
    let plane = Geometry::Plane(PlaneDesc {
        p: Vec3::ZERO,
        n: Vec3::ZERO,
    });
    assert_eq!(
        plane.validate(),
        Err(RuleError::on(&["n"], "the plane's normal \"n\" is zero"))
    );
    let mut mesh = TriangleMesh::default();
    mesh.positions.push(crate::math::PackedVec3::ZERO);
    mesh.indices.extend([0, 0, 1]);
    let mesh = Geometry::TriangleMesh(Arc::new(mesh));
    assert!(mesh.is_mesh());
    assert_eq!(
        mesh.validate(),
        Err(RuleError::on(
            &["indices"],
            "index 1 out of range for 1 vertices"
        ))
    );
}

#[test]
fn emission_rules() {
    let voxels = ShapeDesc {
        medium_interface: None,
        geometry: Geometry::Voxels(Arc::new(
            crate::shape::VoxelGrid::new([1, 1, 1], vec![1], [Rgb::ONE; 256]).unwrap(),
        )),
        object_to_world: Transform::IDENTITY,
        reverse_orientation: false,
        material: 0,
        area_light: Some(AreaLightDesc {
            l: Rgb::ONE,
            two_sided: false,
            spectrum: None,
            power: None,
            image: None,
        }),
        alpha: None,
    };
    assert_eq!(
        voxels.validate(),
        Err(RuleError::on(
            &[],
            "a \"voxels\" shape cannot be an area light (AttributeBegin/AttributeEnd around \
             the AreaLightSource keeps it from the voxels)"
        ))
    );
}
