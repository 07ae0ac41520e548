//! A `plymesh` with a `displacement`, made as pbrt-v4 makes it when it creates the shape
//! (`Shape::Create`): its triangles refined until every edge is shorter than `edgelength` ×
//! `--displacement-edge-scale` in render space, each vertex moved along its normal by the
//! texture, the normals recomputed ([`lancer::shape::refine`], [`lancer::shape::displace`]).
//!
//! The texture is looked up as pbrt-v4 does it there: at the vertex's (u, v) and its
//! object-space position taken for a render-space one, with no footprint. pbrt-v4's render
//! space is its default `cameraworld` (world space moved so that the camera is at the origin),
//! so a 3D texture sees the object-space point plus the camera's world position.

use super::Builder;
use crate::LoadOptions;
use crate::error::{Location, SceneError, Warning};
use crate::pbrt::shapes::Displacement;
use lancer::math::{Vec2, Vec3};
use lancer::scene::desc::Geometry;
use lancer::shape::{DisplaceError, Refinement, displace, refine};
use lancer::texture::{
    FloatTexture, FloatTextureDesc, Pyramids, SpectrumTexture, SpectrumTextureDesc, TexCoord,
    TextureEval,
};
use std::sync::Arc;

/// What displacing meshes keeps across a scene: the options, the triangles made so far (the
/// limit is on them all), a note per mesh, and the scene's textures built so far.
pub(super) struct Displacer {
    options: LoadOptions,
    made: u64,
    /// One per displaced mesh: its file, triangle counts and memory.
    pub(super) notes: Vec<Warning>,
    /// The scene's float and spectrum textures as the renderer builds them (image textures
    /// with their pyramids), the first so many of the description's, and the pyramids made
    /// for them: built once and extended by the textures defined since ([`Displacer::textures`]),
    /// not built again for every displaced mesh.
    floats: Vec<FloatTexture>,
    spectra: Vec<SpectrumTexture>,
    pyramids: Pyramids,
}

impl Displacer {
    pub(super) fn new(options: &LoadOptions) -> Displacer {
        Displacer {
            options: *options,
            made: 0,
            notes: Vec::new(),
            floats: Vec::new(),
            spectra: Vec::new(),
            pyramids: Pyramids::default(),
        }
    }

    /// The scene's textures, whose descriptions so far are `floats` and `spectra`, as the
    /// renderer builds them: those defined since the last call are built now (the readers only
    /// append textures, so the ones built before are still the same).
    fn textures(
        &mut self,
        floats: &[FloatTextureDesc],
        spectra: &[SpectrumTextureDesc],
    ) -> TextureEval<'_> {
        let pyramids = &mut self.pyramids;
        let new_floats = floats[self.floats.len()..].iter();
        self.floats.extend(new_floats.map(|t| t.build(pyramids)));
        let new_spectra = spectra[self.spectra.len()..].iter();
        self.spectra.extend(new_spectra.map(|t| t.build(pyramids)));
        TextureEval {
            floats: &self.floats,
            spectra: &self.spectra,
        }
    }
}

impl Builder {
    /// `geometry` (a `plymesh`'s triangles) displaced by `d`, under the current transformation
    /// (its start, when it moves).
    pub(super) fn displaced(
        &mut self,
        geometry: Geometry,
        d: Displacement,
        loc: &Location,
    ) -> Result<Geometry, SceneError> {
        let Geometry::TriangleMesh(mesh) = geometry else {
            return Ok(geometry);
        };
        let options = self.displacer.options;
        let scale = options.displacement_edge_scale;
        let max = options.max_displaced_triangles;
        let r = Refinement {
            to_render: self.gs.ctm,
            edge_length: d.edge_length * scale,
            max_triangles: max.saturating_sub(self.displacer.made),
        };
        let at = d.edge_loc.clone().unwrap_or_else(|| loc.clone());
        let mut m = refine(&mesh, &r).map_err(|e| {
            let what = format!(
                "displacing \"{}\" with \"edgelength\" {} × --displacement-edge-scale {scale}",
                d.file, d.edge_length
            );
            SceneError::at(at, refinement_error(&what, &e, max, self.displacer.made))
        })?;
        let eye = self.camera_position();
        let ev = (self.displacer).textures(&self.desc.float_textures, &self.desc.spectrum_textures);
        let lookup = |p: Vec3, uv: Vec2| TexCoord {
            p: p + eye,
            uv,
            ..TexCoord::default()
        };
        displace(&mut m, |p, uv| ev.float(d.texture, &lookup(p, uv)));
        let tris = m.face_count() as u64;
        self.displacer.made += tris;
        self.displacer.notes.push(Warning {
            location: loc.clone(),
            message: format!(
                "\"{}\" displaced: {} triangles refined to {tris} ({} vertices, {:.1} MiB)",
                d.file,
                mesh.face_count(),
                m.positions.len(),
                m.heap_bytes() as f64 / (1024.0 * 1024.0)
            ),
        });
        Ok(Geometry::TriangleMesh(Arc::new(m)))
    }

    /// The camera's world position at the middle of its motion: the origin of pbrt-v4's
    /// `cameraworld` render space.
    fn camera_position(&self) -> Vec3 {
        let world_from_camera = match &self.desc.motion.camera {
            Some(m) => {
                let [t0, t1] = m.times();
                m.interpolate((t0 + t1) / 2.0)
            }
            None => self.desc.camera.camera_from_world.inverse(),
        };
        world_from_camera.point(Vec3::ZERO)
    }
}

/// The message of a refinement that failed, saying which option changes what.
fn refinement_error(what: &str, e: &DisplaceError, max: u64, made: u64) -> String {
    match e {
        DisplaceError::TooManyTriangles { at_least, .. } => {
            let count = match at_least {
                Some(n) => format!("at least {n} triangles, more than"),
                None => "more triangles than".into(),
            };
            let before = if made > 0 {
                format!(" ({made} of them made by the displaced meshes before it)")
            } else {
                String::new()
            };
            format!(
                "{what} would make {count} the {max} the scene's displaced meshes may have in \
                 all{before}: --max-displaced-triangles raises that limit; a larger \
                 \"edgelength\" or --displacement-edge-scale makes fewer triangles"
            )
        }
        DisplaceError::NoUvs => format!(
            "{what}: the mesh has no per-vertex (u, v), which displacement needs (as in pbrt-v4)"
        ),
        DisplaceError::BadEdgeLength => format!(
            "{what}: the edge length must be positive and large enough to split the mesh's \
             edges at the precision of its coordinates"
        ),
    }
}
