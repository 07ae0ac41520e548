//! glTF 2.0 (`.gltf` with its buffers and images, or a single `.glb`) read into a
//! [`SceneDesc`], so that `lancer render model.glb` works with no scene file.
//!
//! The `gltf` crate parses and validates the JSON document model; the bytes (GLB chunks,
//! buffers, accessors) are read here ([`data`]), every offset checked, and the materials are
//! mapped in [`material`].
//!
//! What is read:
//! - the default scene (else the first; else every root node), its node hierarchy with TRS or
//!   matrix transforms: world = parent · T · R · S;
//! - mesh primitives of mode TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN (the last two made
//!   into triangles), indexed or not, with POSITION, NORMAL and TEXCOORD_0 (glTF's v runs down
//!   the image, lancer's up: v' = 1 − v); points and lines are skipped with a warning. A mesh
//!   that several nodes use is stored once and placed by each;
//! - Draco-compressed primitives (`KHR_draco_mesh_compression`, decoded in [`draco`]), which
//!   then go the same way as uncompressed ones;
//! - the first camera met in the hierarchy (depth first), perspective (`yfov` is the vertical
//!   field of view; `aspectRatio` sets the image's shape) or orthographic (`xmag`, `ymag`);
//! - `KHR_lights_punctual` point, spot and directional lights;
//! - `KHR_texture_transform`'s offset and scale (not its rotation).
//!
//! Not read (a warning says so): normal maps, vertex colours, skins (the bind pose is shown),
//! morph targets (the base shape), texture coordinate sets other than 0; other required
//! extensions are refused.
//!
//! **Handedness.** glTF's world is right-handed, +y up, and a camera looks down its local −z
//! with +x to the right of the image. lancer's camera space is pbrt's: looking down +z, +y up,
//! +x to the right of the image, left-handed. So camera-from-world is diag(1, 1, −1) ·
//! (camera node's world matrix)⁻¹: the z flip turns glTF's view into pbrt's without mirroring
//! the image. The world itself needs no change.
//!
//! **Light units.** glTF gives point and spot intensities in candela (lm/sr) and directional
//! ones in lux (lm/m²); lancer's lights are radiometric. They are converted at the luminous
//! efficacy of 555 nm light, [`LUMENS_PER_WATT`] = 683 lm/W: I = colour · cd / 683 (W/sr),
//! E = colour · lux / 683 (W/m²). This is the factor Blender's glTF exporter uses (a sun of
//! strength 3 W/m² is written as 2049 lux), so exported scenes come back as bright as Blender
//! renders them. Spot cones: lancer's cone angle is `outerConeAngle` and its falloff width
//! `outerConeAngle − innerConeAngle`. `range` is ignored (lancer's lights follow 1/d² all the
//! way).
//!
//! What the file does not give comes from [`crate::mesh_scene::defaults`]: without a camera,
//! the model is framed as a bare mesh is; without any light (punctual or emissive), the
//! default sky and key light are added. Primitives without a material are the light grey of
//! bare meshes (not glTF's default white metal, which renders as a mirror-grey blur).

pub mod data;
pub mod draco;
pub mod loader;
pub mod material;

use crate::LoadedScene;
use crate::error::SceneError;
use crate::mesh_scene::{default_lights, defaults, framing_camera};
use ::gltf::Document;
use ::gltf::mesh::{Mode, Semantic};
use lancer::integrator::Integrator;
use lancer::light::{DistantDesc, PointDesc, SpotDesc};
use lancer::math::{Mat4, PackedVec3, Rgb, Transform, Vec2, Vec3, Vec4};
use lancer::scene::desc::{
    AreaLightDesc, CameraDesc, FilmDesc, Geometry, LightDesc, Projection, SceneDesc, ShapeDesc,
};
use lancer::shape::TriangleMesh;
use loader::GltfLoader;
use std::collections::{HashMap, HashSet};
use std::path::Path;
use std::sync::Arc;

/// Extensions lancer reads (a file requiring any other is refused).
const SUPPORTED_EXTENSIONS: &[&str] = &[
    "KHR_draco_mesh_compression",
    "KHR_lights_punctual",
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
];

/// Luminous efficacy used to turn glTF's photometric light intensities into radiometric ones:
/// 683 lm/W, the peak of the photopic curve (light of 555 nm).
pub const LUMENS_PER_WATT: f32 = 683.0;

/// Longest side of the image made for a camera's aspect ratio, pixels.
const MAX_FILM_SIDE: f32 = 4096.0;

/// Refuses primitives whose attributes or indices name an accessor that does not exist. The
/// `gltf` crate's validation reads the POSITION accessor without checking its index first (a
/// panic found by fuzzing), so this runs before it.
fn check_accessor_references(root: &::gltf::json::Root) -> Result<(), String> {
    let count = root.accessors.len();
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let attributes = prim.attributes.values().map(|a| a.value());
            for a in attributes.chain(prim.indices.iter().map(|i| i.value())) {
                if a >= count {
                    return Err(format!(
                        "mesh {m}, primitive {p} refers to accessor {a}, but the file has {count}"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Reads a `.gltf` or `.glb` file into a scene.
pub fn load_gltf_scene(path: &Path) -> Result<LoadedScene, SceneError> {
    let name = path.display().to_string();
    let fail = |msg: String| SceneError::general(format!("{name}: {msg}"));
    crate::files_read::record(path);
    let bytes = std::fs::read(path).map_err(|e| fail(format!("cannot read: {e}")))?;
    let (json, bin) = if bytes.starts_with(b"glTF") {
        let glb = data::split_glb(&bytes).map_err(fail)?;
        (glb.json, glb.bin)
    } else {
        (&bytes[..], None)
    };
    let root = ::gltf::json::Root::from_slice(json)
        .map_err(|e| fail(format!("invalid glTF JSON: {e}")))?;
    let unsupported: Vec<&str> = root
        .extensions_required
        .iter()
        .map(String::as_str)
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(e))
        .collect();
    if !unsupported.is_empty() {
        return Err(fail(format!(
            "the file requires glTF extension{} {}, which lancer does not support",
            if unsupported.len() > 1 { "s" } else { "" },
            unsupported.join(", "),
        )));
    }
    check_accessor_references(&root).map_err(fail)?;
    let doc = validated(root).map_err(|e| fail(e.to_string()))?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let buffers = data::load_buffers(&doc, bin, &dir).map_err(fail)?;
    let mut loader = GltfLoader {
        name: name.clone(),
        dir,
        doc: &doc,
        buffers,
        images: HashMap::new(),
        material_cache: HashMap::new(),
        materials: Vec::new(),
        float_textures: Vec::new(),
        spectrum_textures: Vec::new(),
        warnings: Vec::new(),
        meshes: HashMap::new(),
        shapes: Vec::new(),
        lights: Vec::new(),
        camera: None,
        lo: Vec3::splat(f32::INFINITY),
        hi: Vec3::splat(f32::NEG_INFINITY),
    };
    loader.load().map_err(fail)?;
    let desc = loader.scene().map_err(fail)?;
    Ok(LoadedScene {
        desc,
        warnings: loader.warnings,
        files: Vec::new(),
        notes: Vec::new(),
    })
}

/// The document checked by the `gltf` crate's validation, less the two complaints a Draco
/// file always draws from it: that `KHR_draco_mesh_compression` is required (the crate does
/// not know it; lancer does), and that the accessors of Draco primitives have no buffer view
/// (their data is in the Draco stream).
fn validated(root: ::gltf::json::Root) -> Result<Document, ::gltf::Error> {
    use ::gltf::json::validation::{Error, Validate};
    let mut draco_accessors = HashSet::new();
    for prim in root.meshes.iter().flat_map(|m| &m.primitives) {
        let is_draco = prim
            .extensions
            .as_ref()
            .is_some_and(|e| e.others.contains_key(draco::EXTENSION));
        if is_draco {
            draco_accessors.extend(prim.attributes.values().map(|a| a.value()));
            draco_accessors.extend(prim.indices.map(|a| a.value()));
        }
    }
    let mut errors = Vec::new();
    root.validate(&root, ::gltf::json::Path::new, &mut |path, error| {
        let path = path();
        let text = path.to_string();
        let draco_required =
            text.starts_with("extensionsRequired[") && text.contains(draco::EXTENSION);
        let draco_accessor = matches!(error, Error::Missing)
            && draco_accessors
                .iter()
                .any(|i| text == format!("accessors[{i}].bufferView"));
        if !draco_required && !draco_accessor {
            errors.push((path, error));
        }
    });
    if errors.is_empty() {
        Ok(Document::from_json_without_validation(root))
    } else {
        Err(::gltf::Error::Validation(errors))
    }
}

impl GltfLoader<'_> {
    /// Walks the scene's node trees depth first, placing meshes, the first camera and lights.
    fn load(&mut self) -> Result<(), String> {
        let doc = self.doc;
        let roots: Vec<::gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(scene) => scene.nodes().collect(),
            None => {
                let children: HashSet<usize> = doc
                    .nodes()
                    .flat_map(|n| n.children().map(|c| c.index()))
                    .collect();
                doc.nodes()
                    .filter(|n| !children.contains(&n.index()))
                    .collect()
            }
        };
        let mut visited = HashSet::new();
        // Depth first, children in order: the stack holds them reversed.
        let mut stack: Vec<(::gltf::Node, Mat4)> = roots
            .into_iter()
            .rev()
            .map(|n| (n, Mat4::IDENTITY))
            .collect();
        while let Some((node, parent)) = stack.pop() {
            if !visited.insert(node.index()) {
                self.warn(format!(
                    "node {} is reached twice in the hierarchy (glTF nodes form trees); the second time is skipped",
                    node.index()
                ));
                continue;
            }
            let local = Mat4::from_cols_array_2d(&node.transform().matrix());
            let world = parent * local;
            if !world.is_finite() {
                return Err(format!(
                    "node {}: its transform is not made of finite numbers",
                    node.index()
                ));
            }
            if let Some(mesh) = node.mesh() {
                if node.skin().is_some() {
                    self.warn(format!(
                        "node {}: skinning is not supported; the mesh is shown in its bind pose",
                        node.index()
                    ));
                }
                self.place_mesh(&node, &mesh, world)?;
            }
            if let Some(camera) = node.camera()
                && self.camera.is_none()
            {
                self.camera = Some(self.camera_desc(&camera, world)?);
            }
            if let Some(light) = node.light() {
                self.place_light(&light, world);
            }
            let children: Vec<_> = node.children().collect();
            for child in children.into_iter().rev() {
                stack.push((child, world));
            }
        }
        Ok(())
    }

    /// One shape per triangle primitive of `mesh`, placed by `world`.
    fn place_mesh(
        &mut self,
        node: &::gltf::Node,
        mesh: &::gltf::Mesh,
        world: Mat4,
    ) -> Result<(), String> {
        let Some(to_world) = Transform::from_matrix(world) else {
            self.warn(format!(
                "node {}: its transform is singular (a zero scale); its mesh is not shown",
                node.index()
            ));
            return Ok(());
        };
        for prim in mesh.primitives() {
            let key = (mesh.index(), prim.index());
            let tri = match self.meshes.get(&key) {
                Some(t) => t.clone(),
                None => {
                    let t = self.primitive_mesh(mesh, &prim)?.map(Arc::new);
                    self.meshes.insert(key, t.clone());
                    t
                }
            };
            let Some(tri) = tri else { continue };
            for p in &tri.positions {
                let w = world.transform_point3a((*p).into());
                self.lo = self.lo.min(w);
                self.hi = self.hi.max(w);
            }
            let info = self.material(prim.material().index())?;
            self.shapes.push(ShapeDesc {
                medium_interface: None,
                geometry: Geometry::TriangleMesh(tri),
                object_to_world: to_world,
                reverse_orientation: false,
                material: info.material,
                area_light: info.emission.map(|l| AreaLightDesc {
                    l,
                    two_sided: info.double_sided,
                    spectrum: None,
                    power: None,
                    image: None,
                }),
                alpha: info.alpha,
            });
        }
        Ok(())
    }

    /// The triangles of one primitive, in the mesh's own space (`None`: skipped, with a
    /// warning).
    fn primitive_mesh(
        &mut self,
        mesh: &::gltf::Mesh,
        prim: &::gltf::Primitive,
    ) -> Result<Option<TriangleMesh>, String> {
        let label = match mesh.name() {
            Some(n) => format!("mesh {} '{n}' primitive {}", mesh.index(), prim.index()),
            None => format!("mesh {} primitive {}", mesh.index(), prim.index()),
        };
        let mode = prim.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.warn(format!(
                "{label}: {mode:?} primitives are not rendered (lancer renders triangles)"
            ));
            return Ok(None);
        }
        if prim.morph_targets().next().is_some() {
            self.warn(format!(
                "{label}: morph targets are not supported; the base shape is used"
            ));
        }
        if prim.get(&Semantic::Colors(0)).is_some() {
            self.warn(format!(
                "{label}: vertex colours (COLOR_0) are not supported; ignored"
            ));
        }
        let e = |msg: String| format!("{label}: {msg}");
        // A Draco primitive's accessors hold no bytes: its arrays come from the decoder.
        let mut decoded = match prim.extension_value(draco::EXTENSION) {
            Some(ext) => {
                Some(draco::decode_primitive(&self.buffers, self.doc, prim, ext).map_err(e)?)
            }
            None => None,
        };
        let Some(pos) = prim.get(&Semantic::Positions) else {
            self.warn(format!("{label}: no POSITION attribute; skipped"));
            return Ok(None);
        };
        // The decoded arrays are moved out, not copied.
        let positions: Vec<PackedVec3> = match decoded.as_mut() {
            Some(d) => std::mem::take(&mut d.positions),
            None => data::read_vecs::<3>(&self.buffers, &pos).map_err(e)?,
        }
        .into_iter()
        .map(PackedVec3::from)
        .collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(e(format!(
                "vertex {i} has a coordinate that is not a finite number"
            )));
        }
        let n = positions.len();
        let order: Vec<u32> = match (decoded.as_mut(), prim.indices()) {
            (Some(d), _) => std::mem::take(&mut d.indices),
            (None, Some(a)) => data::read_indices(&self.buffers, &a).map_err(e)?,
            (None, None) => (0..n as u32).collect(),
        };
        if let Some(&bad) = order.iter().find(|&&i| i as usize >= n) {
            return Err(e(format!("index {bad} is out of range for {n} vertices")));
        }
        let indices = triangulate(mode, &order);
        let raw_normals = match (decoded.as_mut(), prim.get(&Semantic::Normals)) {
            (Some(d), _) => Some(std::mem::take(&mut d.normals)).filter(|v| !v.is_empty()),
            (None, Some(a)) => Some(data::read_vecs::<3>(&self.buffers, &a).map_err(e)?),
            (None, None) => None,
        };
        let normals = match raw_normals {
            Some(raw) => {
                let v: Vec<PackedVec3> = raw.into_iter().map(PackedVec3::from).collect();
                if v.len() != n || v.iter().any(|v| !v.is_finite() || *v == PackedVec3::ZERO) {
                    self.warn(format!(
                        "{label}: NORMAL has a wrong count or zero or non-finite normals; the flat normals are used"
                    ));
                    Vec::new()
                } else {
                    v
                }
            }
            None => Vec::new(),
        };
        let raw_uvs = match (decoded.as_mut(), prim.get(&Semantic::TexCoords(0))) {
            (Some(d), _) => Some(std::mem::take(&mut d.uvs)).filter(|v| !v.is_empty()),
            (None, Some(a)) => Some(data::read_vecs::<2>(&self.buffers, &a).map_err(e)?),
            (None, None) => None,
        };
        let uvs = match raw_uvs {
            Some(raw) => {
                let v: Vec<Vec2> = raw
                    .into_iter()
                    // glTF's v = 0 is the image's top row, lancer's its bottom.
                    .map(|[s, t]| Vec2::new(s, 1.0 - t))
                    .collect();
                if v.len() != n {
                    self.warn(format!(
                        "{label}: TEXCOORD_0 has {} elements for {n} vertices; not used",
                        v.len()
                    ));
                    Vec::new()
                } else {
                    v
                }
            }
            None => Vec::new(),
        };
        let mesh = TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
            flip_normal: false,
        };
        mesh.validate().map_err(e)?;
        if mesh.triangle_count() == 0 {
            return Ok(None);
        }
        Ok(Some(mesh))
    }

    /// The camera of a node whose world matrix is `world`, and the film its aspect ratio asks.
    fn camera_desc(
        &mut self,
        camera: &::gltf::Camera,
        world: Mat4,
    ) -> Result<(CameraDesc, FilmDesc), String> {
        // The camera's frame without scale: glTF asks camera nodes not to scale, but some do.
        let x = world.x_axis.truncate().normalize_or_zero();
        let y = world.y_axis.truncate().normalize_or_zero();
        let z = world.z_axis.truncate().normalize_or_zero();
        let t = world.w_axis;
        let camera_to_world = Mat4::from_cols(x.extend(0.0), y.extend(0.0), z.extend(0.0), t);
        // glTF camera space (looking down −z) → pbrt's (looking down +z): flip z.
        let flip = Mat4::from_diagonal(Vec4::new(1.0, 1.0, -1.0, 1.0));
        let camera_from_world = Transform::from_matrix(flip * camera_to_world.inverse())
            .ok_or_else(|| format!("camera {}: its node's axes are degenerate", camera.index()))?;
        let film_for = |aspect: f32| {
            let base = defaults::FILM_HEIGHT as f32;
            let (w, h) = if aspect >= 1.0 {
                (base * aspect, base)
            } else {
                (base, base / aspect)
            };
            FilmDesc {
                xresolution: w.round().clamp(1.0, MAX_FILM_SIDE) as u32,
                yresolution: h.round().clamp(1.0, MAX_FILM_SIDE) as u32,
                ..FilmDesc::default()
            }
        };
        let default_film = FilmDesc {
            xresolution: defaults::FILM_WIDTH,
            yresolution: defaults::FILM_HEIGHT,
            ..FilmDesc::default()
        };
        let bad = |what: &str| format!("camera {}: {what}", camera.index());
        Ok(match camera.projection() {
            ::gltf::camera::Projection::Perspective(p) => {
                let yfov = p.yfov();
                if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
                    return Err(bad(&format!("yfov {yfov} is not in (0, π)")));
                }
                let (film, fov) = match p.aspect_ratio().filter(|a| a.is_finite() && *a > 0.0) {
                    // lancer's fov spans the shorter image axis: the vertical one when the
                    // image is wide, else tan(fov_x/2) = aspect · tan(yfov/2).
                    Some(a) if a < 1.0 => (film_for(a), 2.0 * (a * (yfov * 0.5).tan()).atan()),
                    Some(a) => (film_for(a), yfov),
                    None => (default_film, yfov),
                };
                (
                    CameraDesc {
                        projection: Projection::Perspective {
                            fov: fov.to_degrees(),
                        },
                        camera_from_world,
                        ..CameraDesc::default()
                    },
                    film,
                )
            }
            ::gltf::camera::Projection::Orthographic(o) => {
                let (xmag, ymag) = (o.xmag().abs(), o.ymag().abs());
                if !(xmag > 0.0 && ymag > 0.0 && xmag.is_finite() && ymag.is_finite()) {
                    return Err(bad("xmag and ymag must be positive"));
                }
                (
                    CameraDesc {
                        projection: Projection::Orthographic,
                        camera_from_world,
                        screen_window: Some([-xmag, xmag, -ymag, ymag]),
                        ..CameraDesc::default()
                    },
                    film_for(xmag / ymag),
                )
            }
        })
    }

    /// A `KHR_lights_punctual` light at a node whose world matrix is `world`: it sits at the
    /// node's origin and shines down the node's −z axis.
    fn place_light(&mut self, light: &::gltf::khr_lights_punctual::Light, world: Mat4) {
        use ::gltf::khr_lights_punctual::Kind;
        let from = Vec3::from_vec4(world.w_axis);
        let dir = Vec3::from_vec4(-world.z_axis).normalize_or_zero();
        // cd → W/sr and lux → W/m²: divide by 683 lm/W.
        let power = Rgb::from(light.color()) * (light.intensity() / LUMENS_PER_WATT);
        if !power.is_finite() || dir == Vec3::ZERO {
            self.warn(format!(
                "light {}: its intensity or direction is not usable; skipped",
                light.index()
            ));
            return;
        }
        let desc = match light.kind() {
            Kind::Point => LightDesc::Point(PointDesc {
                from,
                intensity: power,
            }),
            Kind::Spot {
                inner_cone_angle,
                outer_cone_angle,
            } => {
                let outer = outer_cone_angle.to_degrees();
                let inner = inner_cone_angle.to_degrees().clamp(0.0, outer);
                LightDesc::Spot(SpotDesc {
                    from,
                    to: from + dir,
                    intensity: power,
                    cone_angle: outer,
                    cone_delta_angle: outer - inner,
                })
            }
            Kind::Directional => LightDesc::Distant(DistantDesc {
                direction: -dir,
                l: power,
            }),
        };
        self.lights.push(desc);
    }

    /// The finished scene.
    fn scene(&mut self) -> Result<SceneDesc, String> {
        if self.shapes.is_empty() {
            return Err("the file has no triangles to render".into());
        }
        let (camera, film) = match self.camera.take() {
            Some(c) => c,
            None => (
                framing_camera(self.lo, self.hi),
                FilmDesc {
                    xresolution: defaults::FILM_WIDTH,
                    yresolution: defaults::FILM_HEIGHT,
                    ..FilmDesc::default()
                },
            ),
        };
        let mut lights = std::mem::take(&mut self.lights);
        if lights.is_empty() && self.shapes.iter().all(|s| s.area_light.is_none()) {
            lights = default_lights();
        }
        Ok(SceneDesc {
            camera,
            film,
            integrator: Integrator::Path {
                max_depth: defaults::MAX_DEPTH,
                regularize: false,
            },
            materials: std::mem::take(&mut self.materials),
            float_textures: std::mem::take(&mut self.float_textures),
            spectrum_textures: std::mem::take(&mut self.spectrum_textures),
            shapes: std::mem::take(&mut self.shapes),
            lights,
            ..SceneDesc::default()
        })
    }
}

/// Vertex indices in primitive order made into triangles (three per triangle):
/// - TRIANGLES: (3i, 3i+1, 3i+2) (a trailing partial triangle is dropped);
/// - TRIANGLE_STRIP: triangle i is (i, i+1, i+2) for even i and (i+1, i, i+2) for odd i, so
///   that every triangle keeps the first one's winding;
/// - TRIANGLE_FAN: triangle i is (i+1, i+2, 0).
pub fn triangulate(mode: Mode, order: &[u32]) -> Vec<u32> {
    let n = order.len();
    match mode {
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .flat_map(|i| {
                if i % 2 == 0 {
                    [order[i], order[i + 1], order[i + 2]]
                } else {
                    [order[i + 1], order[i], order[i + 2]]
                }
            })
            .collect(),
        Mode::TriangleFan => (0..n.saturating_sub(2))
            .flat_map(|i| [order[i + 1], order[i + 2], order[0]])
            .collect(),
        _ => order[..n - n % 3].to_vec(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_keep_the_winding() {
        // A strip of 5 vertices: 3 triangles, alternate ones swapped.
        assert_eq!(
            triangulate(Mode::TriangleStrip, &[0, 1, 2, 3, 4]),
            [0, 1, 2, 2, 1, 3, 2, 3, 4]
        );
        assert_eq!(
            triangulate(Mode::TriangleFan, &[0, 1, 2, 3]),
            [1, 2, 0, 2, 3, 0]
        );
        assert_eq!(triangulate(Mode::Triangles, &[0, 1, 2, 3]), [0, 1, 2]);
        assert!(triangulate(Mode::TriangleStrip, &[0, 1]).is_empty());
    }
}
