//! Pieces of scene descriptions that the integrators' unit tests share (bdpt's and sppm's
//! rooms): a quad, a constant diffuse material, and a small view with a box filter.

use super::Integrator;
use crate::material::{DiffuseMaterial, MaterialDesc};
use crate::math::{PackedVec3, Rgb, Transform, Vec3};
use crate::scene::desc::{
    CameraDesc, FilmDesc, FilterDesc, Geometry, Projection, SceneDesc, ShapeDesc,
};
use crate::shape::TriangleMesh;
use crate::texture::SpectrumTex;
use std::sync::Arc;

/// The width of [`view`]'s film, in pixels.
pub(crate) const W: u32 = 24;
/// The height of [`view`]'s film, in pixels.
pub(crate) const H: u32 = 18;

/// The quad of corners `p` (two triangles, 0-1-2 and 0-2-3) with material `material`.
pub(crate) fn quad(p: [[f32; 3]; 4], material: u32) -> ShapeDesc {
    let mesh = TriangleMesh {
        positions: p
            .iter()
            .map(|v| PackedVec3::new(v[0], v[1], v[2]))
            .collect(),
        normals: vec![],
        uvs: vec![],
        indices: vec![0, 1, 2, 0, 2, 3],
        flip_normal: false,
    };
    ShapeDesc::new(Geometry::TriangleMesh(Arc::new(mesh)), material)
}

/// A full sphere of radius `radius` centred at `centre`, with material `material`.
pub(crate) fn sphere(centre: Vec3, radius: f32, material: u32) -> ShapeDesc {
    ShapeDesc {
        object_to_world: Transform::translate(centre),
        ..ShapeDesc::new(
            Geometry::Sphere(crate::shape::SphereDesc {
                radius,
                z_min: -radius,
                z_max: radius,
                phi_max: 360.0,
            }),
            material,
        )
    }
}

/// A diffuse material of constant reflectance `c`.
pub(crate) fn diffuse(c: Rgb) -> MaterialDesc {
    MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: SpectrumTex::Const(c),
    })
}

/// A W × H film with a box filter, seen by a perspective camera (field of view `fov`) at
/// `eye` looking at `target` with `up` up, rendered by `integrator`; no shapes, lights or
/// materials yet.
pub(crate) fn view(
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    fov: f32,
    integrator: Integrator,
) -> SceneDesc {
    SceneDesc {
        camera: CameraDesc {
            camera_from_world: Transform::look_at(eye, target, up).unwrap(),
            projection: Projection::Perspective { fov },
            ..CameraDesc::default()
        },
        film: FilmDesc {
            xresolution: W,
            yresolution: H,
            ..FilmDesc::default()
        },
        filter: FilterDesc::Box { radius: [0.5, 0.5] },
        integrator,
        ..SceneDesc::default()
    }
}
