//! The state of one glTF load, shared by the scene walk ([`super`]) and the material
//! mapping ([`super::material`]): the document, its bytes, and the scene as it is built.

use crate::error::{Location, Warning};
use crate::image_read::DecodedImage;
use ::gltf::Document;
use lancer::material::MaterialDesc;
use lancer::math::{Rgb, Vec3};
use lancer::scene::desc::{CameraDesc, FilmDesc, LightDesc, ShapeDesc};
use lancer::shape::TriangleMesh;
use lancer::texture::{FloatTex, FloatTextureDesc, SpectrumTextureDesc};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// What a glTF material became.
#[derive(Clone, Copy, Debug)]
pub struct MaterialInfo {
    /// Index into the scene's materials.
    pub material: u32,
    /// Alpha cut-out, when the material is not opaque.
    pub alpha: Option<FloatTex>,
    /// Emitted radiance, when the material glows.
    pub emission: Option<Rgb>,
    /// glTF `doubleSided`: emission from both sides.
    pub double_sided: bool,
}

/// The state of one load: the document, its bytes, and the scene as it is built.
pub(crate) struct GltfLoader<'a> {
    pub(super) name: String,
    pub(super) dir: PathBuf,
    pub(super) doc: &'a Document,
    pub(super) buffers: Vec<Vec<u8>>,
    /// Decoded images by (image index, sRGB?).
    pub(super) images: HashMap<(usize, bool), Arc<DecodedImage>>,
    pub(super) material_cache: HashMap<Option<usize>, MaterialInfo>,
    pub(super) materials: Vec<MaterialDesc>,
    pub(super) float_textures: Vec<FloatTextureDesc>,
    pub(super) spectrum_textures: Vec<SpectrumTextureDesc>,
    pub(super) warnings: Vec<Warning>,
    /// Triangle meshes by (mesh, primitive); `None` for primitives that were skipped.
    pub(super) meshes: HashMap<(usize, usize), Option<Arc<TriangleMesh>>>,
    pub(super) shapes: Vec<ShapeDesc>,
    pub(super) lights: Vec<LightDesc>,
    pub(super) camera: Option<(CameraDesc, FilmDesc)>,
    /// World-space bounds of every vertex placed.
    pub(super) lo: Vec3,
    pub(super) hi: Vec3,
}

impl GltfLoader<'_> {
    /// A warning about the file (glTF has no lines: it points at its start).
    pub(super) fn warn(&mut self, message: String) {
        self.warnings.push(Warning {
            location: Location {
                file: Arc::from(self.name.as_str()),
                line: 1,
                col: 1,
            },
            message,
        });
    }
}
