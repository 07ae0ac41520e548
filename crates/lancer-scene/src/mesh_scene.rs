//! A bare mesh file (`.obj`, `.ply`) made into a whole scene, so that `lancer render
//! model.obj` works without writing a pbrt file around it.
//!
//! The mesh is placed as it is (object space = world space). An OBJ's MTL materials become
//! one shape per material: `Kd` the diffuse reflectance, or the sRGB image `map_Kd` names
//! (used instead of `Kd`, when the faces have texture coordinates; otherwise a warning says
//! `Kd` is used), `Ke` an area light; `Ks`/`Ns` are not used. Everything a mesh file does not say
//! comes from [`defaults`]: a camera framing the mesh, the film size, the light grey material,
//! a uniform sky and a distant key light.

use crate::LoadedScene;
use crate::error::{Location, SceneError, Warning};
use crate::image_read::{Encoding, ImageCache};
use crate::obj::{ObjError, read_mtl, read_obj};
use crate::ply::read_ply;
use lancer::integrator::Integrator;
use lancer::light::{DistantDesc, UniformInfiniteDesc};
use lancer::material::DiffuseMaterial;
use lancer::material::MaterialDesc;
use lancer::math::{Rgb, Transform, Vec3, normalize};
use lancer::scene::desc::{
    AreaLightDesc, CameraDesc, FilmDesc, Geometry, LightDesc, Projection, SceneDesc, ShapeDesc,
};
use lancer::shape::TriangleMesh;
use lancer::texture::{
    ImageFilter, ImageTextureDesc, SpectrumTex, SpectrumTextureDesc, UvMapping, WrapMode,
};
use std::path::Path;
use std::sync::Arc;

/// What a scene made from a bare mesh file uses where the file says nothing: the one place
/// these choices live.
pub mod defaults {
    use lancer::math::Vec3;

    /// Full field of view of the image's shorter axis, degrees.
    pub const FOV_DEGREES: f32 = 40.0;
    /// Image width, pixels (the command line's `--resolution` overrides it).
    pub const FILM_WIDTH: u32 = 800;
    /// Image height, pixels.
    pub const FILM_HEIGHT: u32 = 600;
    /// Where the camera looks from, as a direction from the mesh's centre: the +z side,
    /// slightly above (+y is taken as up, as in most OBJ and PLY files).
    pub const VIEW_FROM: Vec3 = Vec3::new(0.0, 0.3, 1.0);
    /// Room left around the bounding sphere: its radius is multiplied by this before framing.
    pub const FRAME_MARGIN: f32 = 1.0;
    /// Reflectance of meshes without a material (and of MTL materials without `Kd`).
    pub const ALBEDO: f32 = 0.6;
    /// Radiance of the uniform sky.
    pub const SKY_RADIANCE: f32 = 0.5;
    /// Direction *towards* the key light: above, in front, a little to the left.
    pub const KEY_LIGHT_FROM: Vec3 = Vec3::new(-0.4, 1.0, 0.7);
    /// Radiance of the key light.
    pub const KEY_LIGHT_RADIANCE: f32 = 2.0;
    /// Path tracer depth.
    pub const MAX_DEPTH: u32 = 5;
}

/// Reads a PLY mesh (gzipped when the name ends in `.gz`) into a scene around it.
pub fn load_ply_scene(path: &Path) -> Result<LoadedScene, SceneError> {
    let name = path.display().to_string();
    let ply = read_ply(path).map_err(|e| SceneError::general(e.to_string()))?;
    let mut warnings = Vec::new();
    if ply.skipped_faces > 0 {
        warnings.push(warning(
            &name,
            1,
            format!(
                "{} faces with fewer than 3 vertices skipped",
                ply.skipped_faces
            ),
        ));
    }
    let material = MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: SpectrumTex::Const(Rgb::splat(defaults::ALBEDO)),
    });
    let parts = vec![Part {
        mesh: ply.mesh,
        material: 0,
        emission: None,
    }];
    Ok(LoadedScene {
        desc: scene_around(&name, parts, vec![material])?,
        warnings,
        files: Vec::new(),
        notes: Vec::new(),
    })
}

/// Reads an OBJ mesh and its MTL libraries into a scene around it.
pub fn load_obj_scene(path: &Path) -> Result<LoadedScene, SceneError> {
    let name = path.display().to_string();
    let general = |e: ObjError| SceneError::general(e.to_string());
    let obj = read_obj(path).map_err(general)?;
    let mut warnings = Vec::new();
    if obj.skipped_faces > 0 {
        warnings.push(warning(
            &name,
            1,
            format!(
                "{} faces with fewer than 3 vertices skipped",
                obj.skipped_faces
            ),
        ));
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut library = Vec::new();
    for (line, lib) in &obj.mtllibs {
        let lib_path = dir.join(lib);
        // `mtllib a.mtl b.mtl` names several libraries; a single name may hold spaces.
        if !lib_path.exists() && lib.contains(char::is_whitespace) {
            for part in lib.split_whitespace() {
                let p = dir.join(part);
                if p.exists() {
                    library.extend(read_mtl(&p).map_err(general)?);
                } else {
                    warnings.push(warning(
                        &name,
                        *line,
                        format!(
                            "material library {} not found; its materials are light grey",
                            p.display()
                        ),
                    ));
                }
            }
            continue;
        }
        if !lib_path.exists() {
            warnings.push(warning(
                &name,
                *line,
                format!(
                    "material library {} not found; its materials are light grey",
                    lib_path.display()
                ),
            ));
            continue;
        }
        library.extend(read_mtl(&lib_path).map_err(general)?);
    }

    let grey = MaterialDesc::Diffuse(DiffuseMaterial {
        reflectance: SpectrumTex::Const(Rgb::splat(defaults::ALBEDO)),
    });
    let mut materials = vec![grey];
    let mut parts = Vec::new();
    let mut textures = Vec::new();
    let images = ImageCache::default();
    for (which, mesh) in obj.meshes_by_material() {
        let mut part = Part {
            mesh,
            material: 0,
            emission: None,
        };
        if let Some(i) = which {
            let i = i as usize;
            let (mat_name, line) = (&obj.material_names[i], obj.material_lines[i]);
            match library.iter().rev().find(|m| m.name == *mat_name) {
                None => {
                    if !obj.mtllibs.is_empty() {
                        warnings.push(warning(
                            &name,
                            line,
                            format!(
                                "material '{mat_name}' is not in the material libraries; light grey used"
                            ),
                        ));
                    }
                }
                Some(m) => {
                    let kd = m.kd.unwrap_or(Rgb::splat(defaults::ALBEDO));
                    let mut reflectance = SpectrumTex::Const(kd.clamp(Vec3::ZERO, Vec3::ONE));
                    if let Some(map) = &m.map_kd {
                        let texture = if part.mesh.uvs.is_empty() {
                            Err("the faces using it have no texture coordinates".to_string())
                        } else {
                            image_texture(&images, &dir.join(map))
                        };
                        match texture {
                            Ok(t) => {
                                textures.push(SpectrumTextureDesc::Image(t));
                                reflectance = SpectrumTex::Tex((textures.len() - 1) as u32);
                            }
                            Err(e) => warnings.push(warning(
                                &name,
                                line,
                                format!(
                                    "material '{mat_name}': texture map_Kd {map} not used ({e}); its Kd colour is used"
                                ),
                            )),
                        }
                    }
                    materials.push(MaterialDesc::Diffuse(DiffuseMaterial { reflectance }));
                    part.material = (materials.len() - 1) as u32;
                    part.emission = m.ke.filter(|ke| ke.max_element() > 0.0);
                }
            }
        }
        parts.push(part);
    }
    let mut desc = scene_around(&name, parts, materials)?;
    desc.spectrum_textures = textures;
    Ok(LoadedScene {
        desc,
        warnings,
        files: Vec::new(),
        notes: Vec::new(),
    })
}

/// A diffuse texture: the sRGB image at `path`, tiled, looked up bilinearly with the OBJ's
/// (u, v) as they are (pbrt's convention: v = 0 is the image's bottom row, as in OBJ).
fn image_texture(images: &ImageCache, path: &Path) -> Result<ImageTextureDesc, String> {
    let image = images
        .rgb(path, Encoding::Srgb)
        .map_err(|e| e.to_string())?;
    Ok(ImageTextureDesc {
        image,
        to_srgb: None,
        mip: false,
        mapping: UvMapping::default().into(),
        wrap: WrapMode::Repeat,
        scale: 1.0,
        invert: false,
        filter: ImageFilter::Bilinear,
    })
}

/// One shape of a mesh scene.
struct Part {
    mesh: TriangleMesh,
    material: u32,
    emission: Option<Rgb>,
}

fn warning(file: &str, line: u32, message: String) -> Warning {
    Warning {
        location: Location {
            file: Arc::from(file),
            line,
            col: 1,
        },
        message,
    }
}

/// The scene: the parts as shapes, with the default camera, film, integrator and lights.
fn scene_around(
    name: &str,
    parts: Vec<Part>,
    materials: Vec<MaterialDesc>,
) -> Result<SceneDesc, SceneError> {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    let mut shapes = Vec::new();
    for part in parts {
        part.mesh
            .validate()
            .map_err(|e| SceneError::general(format!("{name}: {e}")))?;
        if part.mesh.triangle_count() == 0 {
            continue;
        }
        for &i in &part.mesh.indices {
            let p = part.mesh.position(i as usize);
            if !p.is_finite() {
                return Err(SceneError::general(format!(
                    "{name}: vertex {i} has a coordinate that is not a finite number"
                )));
            }
            lo = lo.min(p);
            hi = hi.max(p);
        }
        shapes.push(ShapeDesc {
            medium_interface: None,
            geometry: Geometry::TriangleMesh(Arc::new(part.mesh)),
            object_to_world: Transform::IDENTITY,
            reverse_orientation: false,
            material: part.material,
            area_light: part.emission.map(|l| AreaLightDesc {
                l,
                two_sided: false,
                spectrum: None,
                power: None,
                image: None,
            }),
            alpha: None,
        });
    }
    if shapes.is_empty() {
        return Err(SceneError::general(format!(
            "{name}: the file has no triangles to render"
        )));
    }
    Ok(SceneDesc {
        camera: framing_camera(lo, hi),
        film: FilmDesc {
            xresolution: defaults::FILM_WIDTH,
            yresolution: defaults::FILM_HEIGHT,
            ..FilmDesc::default()
        },
        integrator: Integrator::Path {
            max_depth: defaults::MAX_DEPTH,
            regularize: false,
        },
        materials,
        shapes,
        lights: default_lights(),
        ..SceneDesc::default()
    })
}

/// The lights of a scene whose file has none: the uniform sky and the distant key light.
pub fn default_lights() -> Vec<LightDesc> {
    vec![
        LightDesc::UniformInfinite(UniformInfiniteDesc {
            l: Rgb::splat(defaults::SKY_RADIANCE),
        }),
        LightDesc::Distant(DistantDesc {
            direction: defaults::KEY_LIGHT_FROM,
            l: Rgb::splat(defaults::KEY_LIGHT_RADIANCE),
        }),
    ]
}

/// A perspective camera (fov [`defaults::FOV_DEGREES`]) looking at the centre of the box
/// `lo..hi` from [`defaults::VIEW_FROM`], far enough for the bounding sphere to fit in the
/// shorter image axis, +y up and +x to the right of the image.
pub fn framing_camera(lo: Vec3, hi: Vec3) -> CameraDesc {
    let centre = (lo + hi) * 0.5;
    let radius = ((hi - lo).length() * 0.5).max(1e-3) * defaults::FRAME_MARGIN;
    let half_fov = (defaults::FOV_DEGREES * 0.5).to_radians();
    let distance = radius / half_fov.sin();
    let eye = centre + normalize(defaults::VIEW_FROM) * distance;
    // pbrt's camera space is left-handed: LookAt alone puts world +x on the image's left when
    // looking down −z. Mirroring camera x (pbrt's `Scale -1 1 1` before `LookAt`) puts it on
    // the right, as people expect of a model seen from the front.
    let look = Transform::look_at(eye, centre, Vec3::Y).unwrap_or(Transform::IDENTITY);
    let mirror = Transform::scale(Vec3::new(-1.0, 1.0, 1.0)).unwrap_or(Transform::IDENTITY);
    CameraDesc {
        projection: Projection::Perspective {
            fov: defaults::FOV_DEGREES,
        },
        camera_from_world: mirror * look,
        ..CameraDesc::default()
    }
}
