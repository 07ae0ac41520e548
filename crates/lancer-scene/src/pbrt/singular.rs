//! Shapes under a singular transformation (`Scale 0 1 1`, a `ConcatTransform` with a zero
//! column, as exporters write for flattened objects).
//!
//! pbrt-v4 keeps such a matrix and fills its inverse with NaNs. Meshes (triangles, bilinear
//! patches) are moved to render space when they are loaded, so they collapse onto a plane or a
//! line and render as that; every other shape is intersected in object space through the NaN
//! inverse, so it is never hit (disks, curves) or aborts pbrt-v4 (spheres, cylinders: a NaN
//! normal). lancer does the same for meshes — their positions are moved by the matrix here, once,
//! and the shape is placed by the identity — and skips the other shapes with a warning.

use super::convert::Fallback;
use lancer::math::{Mat4, PackedVec3, Transform, Vec3};
use lancer::scene::desc::Geometry;
use lancer::shape::IndexedMesh;
use std::sync::Arc;

/// A transformation that flattens space: the matrix `m`, and an inverse of NaNs (as pbrt-v4's
/// `Transform` has when `Inverse` fails), which tells it apart ([`is_singular`]).
pub fn singular(m: Mat4) -> Transform {
    Transform::from_pair(m, Mat4::NAN)
}

/// The transformation of matrix `m`: with its inverse, or [`singular`] when it has none (pbrt-v4
/// accepts every matrix in `Transform`, `ConcatTransform` and `Scale`).
pub fn kept(m: Mat4) -> Transform {
    Transform::from_matrix(m).unwrap_or_else(|| singular(m))
}

/// The warning (or error) for `what` (`LightSource "point"`, …) under a singular transformation.
pub fn unplaced(what: &str) -> String {
    format!(
        "{what} is under a singular transformation (it flattens space), which cannot place it; \
         skipped"
    )
}

/// True when `t` has no inverse (made by [`singular`], or composed with such a transformation).
pub fn is_singular(t: &Transform) -> bool {
    !t.m_inv.is_finite()
}

/// A mesh's positions moved by `m`; its shading normals dropped, since a flattening matrix has
/// no inverse transpose to move them with (the faces' own normals, from the moved positions,
/// remain). Says whether there were normals to drop.
fn flattened<const N: usize>(mesh: &IndexedMesh<N>, m: &Mat4) -> (IndexedMesh<N>, bool) {
    let positions = mesh
        .positions
        .iter()
        .map(|&p| PackedVec3::from(m.transform_point3a(Vec3::from(p))))
        .collect();
    let had_normals = !mesh.normals.is_empty();
    let flat = IndexedMesh {
        positions,
        normals: Vec::new(),
        uvs: mesh.uvs.clone(),
        indices: mesh.indices.clone(),
        flip_normal: mesh.flip_normal,
    };
    (flat, had_normals)
}

/// `geometry` (of a shape of type `ty`) placed by the singular `ctm`, to be placed by the
/// identity: a mesh with its positions moved; `None` (with a warning) for a shape that cannot
/// be flattened.
pub fn flatten(geometry: Geometry, ty: &str, ctm: &Transform) -> Fallback<Option<Geometry>> {
    const NORMALS: &str = "the transformation is singular (it flattens space): the mesh's shading \
                           normals \"N\" cannot follow it and are dropped; its faces' own normals \
                           shade it";
    let (flat, dropped) = match &geometry {
        Geometry::TriangleMesh(m) => {
            let (flat, dropped) = flattened(m, &ctm.m);
            (Geometry::TriangleMesh(Arc::new(flat)), dropped)
        }
        Geometry::BilinearMesh(m) => {
            let (flat, dropped) = flattened(m, &ctm.m);
            (Geometry::BilinearMesh(Arc::new(flat)), dropped)
        }
        _ => {
            let what = format!("Shape \"{ty}\"");
            return Fallback::instead(None, unplaced(&what));
        }
    };
    if dropped {
        Fallback::instead(Some(flat), NORMALS)
    } else {
        Fallback::done(Some(flat))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lancer::math::Vec2;
    use lancer::shape::{SphereDesc, TriangleMesh};

    fn v3(x: f32, y: f32, z: f32) -> PackedVec3 {
        Vec3::new(x, y, z).into()
    }

    #[test]
    fn a_zero_column_collapses_a_mesh_onto_a_plane() {
        // The matrix of robustness/singular-transform.pbrt: x ↦ 0, y ↦ y, z ↦ -z.
        let m = Mat4::from_cols_array(&[
            -0.0, -0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        assert!(Transform::from_matrix(m).is_none());
        let t = singular(m) * Transform::translate(Vec3::new(0.0, 0.0, 1.0));
        assert!(is_singular(&t));
        assert!(!is_singular(&Transform::translate(Vec3::X)));
        let mesh = TriangleMesh {
            positions: vec![v3(1.0, 2.0, 3.0), v3(-1.0, 0.0, 0.0), v3(0.5, 1.0, -1.0)],
            normals: vec![v3(0.0, 0.0, 1.0); 3],
            uvs: vec![Vec2::ZERO, Vec2::X, Vec2::Y],
            indices: vec![0, 1, 2],
            flip_normal: false,
        };
        let out = flatten(Geometry::TriangleMesh(Arc::new(mesh)), "trianglemesh", &t);
        let Some(Geometry::TriangleMesh(flat)) = out.value else {
            panic!("a mesh")
        };
        // (x, y, z) ↦ (0, y, -(z + 1)).
        assert_eq!(
            flat.positions,
            [v3(0.0, 2.0, -4.0), v3(0.0, 0.0, -1.0), v3(0.0, 1.0, 0.0)]
        );
        assert!(flat.normals.is_empty());
        assert_eq!(flat.uvs.len(), 3);
        assert_eq!(out.warnings.len(), 1);
        assert!(out.warnings[0].contains("\"N\""), "{}", out.warnings[0]);
    }

    #[test]
    fn shapes_placed_through_the_inverse_are_skipped() {
        let t = singular(Mat4::from_scale(Vec3::new(0.0, 1.0, 1.0).into()));
        let sphere = Geometry::Sphere(SphereDesc {
            radius: 1.0,
            z_min: -1.0,
            z_max: 1.0,
            phi_max: 360.0,
        });
        let out = flatten(sphere, "sphere", &t);
        assert!(out.value.is_none());
        assert_eq!(
            out.warnings,
            [
                "Shape \"sphere\" is under a singular transformation (it flattens space), which \
              cannot place it; skipped"
            ]
        );
    }
}
