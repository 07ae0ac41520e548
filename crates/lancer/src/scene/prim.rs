//! What the build makes beside the shapes, and what it checks: the per-primitive records, the
//! build's errors, the shape checks and the triangles of a mesh (shared by the flattened
//! shapes and the instanced objects).

use super::desc::ShapeDesc;
use crate::math::PackedRgb;
use crate::shape::IndexedMesh;
use crate::texture::FloatTex;
use std::mem::size_of;

/// What a primitive is made of, beside its shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimInfo {
    /// The material's id ([`Scene::material`](super::Scene::material)).
    pub material: u32,
    /// Emitted radiance when the primitive is an area light.
    pub emission: Option<AreaEmission>,
    /// Alpha cut-out: where it is below 1 the surface is (partly) absent.
    pub alpha: Option<FloatTex>,
    /// The media on its two sides, when they differ (a ray crossing it changes medium), or
    /// when it emits (a light path leaving it starts in one of them); a ray crossing a
    /// surface changes medium only where [`MediumInterface::is_transition`].
    ///
    /// [`MediumInterface::is_transition`]: crate::medium::MediumInterface::is_transition
    pub media: Option<crate::medium::MediumInterface>,
}

/// A primitive's emission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaEmission {
    /// Radiance (packed, so that [`PrimInfo`], one per primitive, stays small).
    pub l: PackedRgb,
    /// Emits from both sides.
    pub two_sided: bool,
    /// Index of its spectrum among the scene's area-light spectra, `NO_SPECTRUM` (`u16::MAX`) for an
    /// RGB colour (16 bits, in what would be padding).
    pub spectrum: u16,
    /// Index of the light in [`Scene::lights`](super::Scene::lights).
    pub light: u32,
}

/// [`AreaEmission::spectrum`] of an emission given as an RGB colour.
pub const NO_SPECTRUM: u16 = u16::MAX;
/// [`AreaEmission::spectrum`] of an emission read from an image (its light,
/// [`crate::light::Light::Area`], holds the image).
pub const IMAGE_EMISSION: u16 = u16::MAX - 1;

/// Why a scene description could not be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BuildError {
    /// A mesh with bad indices or mismatched arrays.
    #[error("shape {shape}: {message}")]
    BadMesh {
        /// Index of the shape in the description.
        shape: usize,
        /// What is wrong.
        message: String,
    },
    /// A material index out of range.
    #[error("shape {shape}: material {material} does not exist")]
    BadMaterial {
        /// Index of the shape.
        shape: usize,
        /// The index given.
        material: u32,
    },
    /// The camera cannot be built from its parameters (a degenerate projection, a lens
    /// system that cannot focus).
    #[error("camera: {0}")]
    BadCamera(String),
    /// A zero or non-finite parameter that makes a shape or light meaningless.
    #[error("{0}")]
    Invalid(String),
}

/// The error for shape `index` breaking a rule of [`ShapeDesc::validate`]: a bad mesh for the
/// mesh geometries, an invalid parameter for the others.
pub(crate) fn invalid_shape(sd: &ShapeDesc, index: usize, message: String) -> BuildError {
    if sd.geometry.is_mesh() {
        BuildError::BadMesh {
            shape: index,
            message,
        }
    } else {
        BuildError::Invalid(format!("shape {index}: {message}"))
    }
}

/// Checks shape `index`'s material index (below `n_materials`) and its rules
/// ([`ShapeDesc::validate`]).
pub(crate) fn check_shape(
    sd: &ShapeDesc,
    index: usize,
    n_materials: usize,
) -> Result<(), BuildError> {
    if sd.material as usize >= n_materials {
        return Err(BuildError::BadMaterial {
            shape: index,
            material: sd.material,
        });
    }

    sd.validate()
        .map_err(|e| invalid_shape(sd, index, e.message))
}

/// The interface a primitive keeps: the shape's, when crossing it changes medium or when the
/// shape emits (the medium its light paths start in; pbrt-v4's area lights keep their shape's
/// interface).
pub(crate) fn prim_media(sd: &ShapeDesc) -> Option<crate::medium::MediumInterface> {
    sd.medium_interface
        .filter(|mi| mi.is_transition() || (sd.area_light.is_some() && mi.outside.is_some()))
}

/// Checks that every medium the shapes, the lights and the camera name exists.
pub(crate) fn check_media(desc: &super::desc::SceneDesc) -> Result<(), BuildError> {
    let n = desc.media.len();
    let bad = |m: Option<u32>| m.filter(|&m| m as usize >= n);
    if let Some(m) = bad(desc.camera_medium) {
        return Err(BuildError::Invalid(format!(
            "the camera's medium {m} does not exist"
        )));
    }
    for (index, &m) in desc.light_media.iter().enumerate() {
        if let Some(m) = bad(m) {
            return Err(BuildError::Invalid(format!(
                "light {index}: medium {m} does not exist"
            )));
        }
    }
    let shapes = desc
        .shapes
        .iter()
        .chain(desc.objects.iter().flat_map(|o| &o.shapes));
    for (index, sd) in shapes.enumerate() {
        if let Some(mi) = sd.medium_interface
            && let Some(m) = bad(mi.inside).or(bad(mi.outside))
        {
            return Err(BuildError::Invalid(format!(
                "shape {index}: medium {m} does not exist"
            )));
        }
    }
    Ok(())
}

/// Bytes of a `Vec` of `T` with capacity `cap`.
pub(crate) fn vec_bytes<T>(cap: usize) -> usize {
    cap * size_of::<T>()
}

/// Bytes of a mesh's arrays: positions, normals, uvs, indices.
pub(crate) fn mesh_bytes<const N: usize>(m: &IndexedMesh<N>) -> usize {
    m.heap_bytes()
}
