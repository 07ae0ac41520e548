//! `Shape`: pbrt-v4's quadrics, meshes (inline, or read from OBJ, PLY and MagicaVoxel files),
//! curves and bilinear patches, and lancer's extensions (`box`, `plane`, `sdf`, `voxels`), as
//! object-space [`Geometry`] with pbrt-v4's defaults.

use super::convert::{Fallback, Reader, locate};
use super::params::{FloatParam, ParamList};
use crate::error::{Location, SceneError};
use crate::obj::read_obj;
use crate::ply::read_ply;
use crate::vox::{default_palette, linear_palette, read_vox};
use lancer::math::{PackedVec3, Rgb, Vec3};
use lancer::scene::desc::Geometry;
use lancer::shape::{
    BilinearMesh, BoxDesc, ConeDesc, CurveBasis, CurveDesc, CurveType, CylinderDesc, DiskDesc,
    HyperboloidDesc, ParaboloidDesc, PlaneDesc, RuleError, SphereDesc, TriangleMesh, VoxelGrid,
};
use lancer::texture::FloatTex;
use std::sync::Arc;

/// A shape as the scene gives it: its object-space geometry and its `alpha` (none when opaque).
#[derive(Clone, Debug)]
pub struct ShapeGeometry {
    /// Object-space geometry.
    pub geometry: Geometry,
    /// A second geometry the same directive makes, under the same attributes: the quads of a
    /// `plymesh` that also has triangles, as bilinear patches (pbrt-v4 makes both).
    pub also: Option<Geometry>,
    /// The alpha cut-out, when not 1.
    pub alpha: Option<FloatTex>,
    /// The displacement of a `plymesh`'s triangles (`geometry`), to apply where the texture
    /// list and the transformation are known.
    pub displacement: Option<Displacement>,
}

/// A `plymesh`'s `displacement` and `edgelength` (pbrt-v4 applies them when it makes the
/// shape: see `builder/displaced.rs`).
#[derive(Clone, Debug)]
pub struct Displacement {
    /// The texture (or constant) moving each vertex along its normal.
    pub texture: FloatTex,
    /// `edgelength`, before `--displacement-edge-scale`.
    pub edge_length: f32,
    /// Where `edgelength` is, when given.
    pub edge_loc: Option<Location>,
    /// The PLY file, for messages.
    pub file: String,
}

/// The shape `ty` at `loc`; `emits` when the current area light would make it glow. The value
/// is `None` when lancer skips the shape (its warning says why).
pub fn shape(
    r: &Reader,
    ty: &str,
    emits: bool,
    loc: &Location,
) -> Result<Fallback<Option<ShapeGeometry>>, SceneError> {
    let converted = match ty {
        "plymesh" => ply_mesh(r),
        _ => geometry(r, ty).map(|g| g.map(|g| g.map(|g| (g, None, None)))),
    }
    .map_err(|e| locate(e, loc))?;
    let Some((geometry, also, displacement)) = converted.value else {
        return Ok(Fallback {
            value: None,
            warnings: converted.warnings,
        });
    };
    let alpha = match r.params.float_or_texture("alpha")? {
        None | Some(FloatParam::Const(1.0)) => None,
        Some(FloatParam::Const(a)) => Some(FloatTex::Const(a)),
        Some(FloatParam::Texture(t, tloc)) => Some(r.textures.float(&t, &tloc)?),
    };
    if emits {
        for g in std::iter::once(&geometry).chain(&also) {
            g.validate_emitter()
                .map_err(|e| SceneError::at(loc.clone(), e.message))?;
        }
    }
    Ok(Fallback {
        value: Some(ShapeGeometry {
            geometry,
            also,
            alpha,
            displacement,
        }),
        warnings: converted.warnings,
    })
}

/// The error of a rule of lancer's descriptions broken ([`Geometry::validate`]): at the
/// parameter it is about (the last given of its fields), else without a location (the caller
/// adds the directive's).
fn rule_error(p: &ParamList, e: RuleError) -> SceneError {
    let param = e.fields.iter().rev().find_map(|&field| {
        // The parameters a field comes from, the more specific first.
        let names: &[&str] = match field {
            "z_max" => &["zmax"],
            "function" => &["expr"],
            "bounds" => &["max", "min"],
            "positions" | "points" => &["P"],
            "normals" => &["N"],
            "uvs" => &["uv", "st"],
            "width0" => &["width0", "width"],
            "width1" => &["width1", "width"],
            other => return p.has(other).then_some(other),
        };
        names.iter().copied().find(|&name| p.has(name))
    });
    match param {
        Some(name) => p.error_at(name, e.message),
        None => SceneError::general(e.message),
    }
}

/// The geometry of `ty`, `None` when skipped.
fn geometry(r: &Reader, ty: &str) -> Result<Fallback<Option<Geometry>>, SceneError> {
    let p = r.params;
    // pbrt's sweep angle, in degrees, for every quadric.
    let phi_max = || p.float_checked("phimax", 360.0, "in (0, 360]", |v| v > 0.0 && v <= 360.0);
    let radius = || p.float("radius", 1.0);
    let g = match ty {
        "sphere" => {
            let radius = radius()?;
            Geometry::Sphere(SphereDesc {
                radius,
                z_min: p.float("zmin", -radius)?,
                z_max: p.float("zmax", radius)?,
                phi_max: phi_max()?,
            })
        }
        "disk" => Geometry::Disk(DiskDesc {
            height: p.float("height", 0.0)?,
            radius: radius()?,
            inner_radius: p.float("innerradius", 0.0)?,
            phi_max: phi_max()?,
        }),
        "cylinder" => Geometry::Cylinder(CylinderDesc {
            radius: radius()?,
            z_min: p.float("zmin", -1.0)?,
            z_max: p.float("zmax", 1.0)?,
            phi_max: phi_max()?,
        }),
        "cone" => Geometry::Cone(ConeDesc {
            radius: radius()?,
            height: p.float("height", 1.0)?,
            phi_max: phi_max()?,
        }),
        "paraboloid" => Geometry::Paraboloid(ParaboloidDesc {
            radius: radius()?,
            z_min: p.float("zmin", 0.0)?,
            z_max: p.float("zmax", 1.0)?,
            phi_max: phi_max()?,
        }),
        "hyperboloid" => Geometry::Hyperboloid(HyperboloidDesc {
            p1: p.point3("p1", Vec3::ZERO)?,
            p2: p.point3("p2", Vec3::ONE)?,
            phi_max: phi_max()?,
        }),
        // lancer extension: an axis-aligned box in object space.
        "box" => Geometry::Box(BoxDesc {
            min: p.point3("min", Vec3::splat(-1.0))?,
            max: p.point3("max", Vec3::ONE)?,
        }),
        "plane" => Geometry::Plane(PlaneDesc {
            p: p.point3("p", Vec3::ZERO)?,
            n: p.normal("n", Vec3::Z)?,
        }),
        // lancer extension: a signed-distance object, sphere-traced.
        "sdf" => super::sdf::sdf_geometry(p)?,
        // Inconsistent arrays are trimmed or dropped as pbrt-v4 does, with a warning.
        "trianglemesh" => {
            let m = trianglemesh::triangle_mesh_as_pbrt(p)?;
            if let Some(m) = &m.value {
                m.check().map_err(|e| rule_error(p, e))?;
            }
            return Ok(m.map(|m| m.map(|m| Geometry::TriangleMesh(Arc::new(m)))));
        }
        // pbrt's subdivision surface: the control mesh refined `levels` times (default 3) and
        // moved to the limit surface.
        "loopsubdiv" => {
            let levels = p.int_in("levels", 3, 0..=8)? as u32;
            let control = triangle_mesh(p, ty)?;
            // Subdivision assumes a valid control mesh.
            control.check().map_err(|e| rule_error(p, e))?;
            Geometry::TriangleMesh(Arc::new(lancer::shape::loop_subdivide(&control, levels)))
        }
        "objmesh" => {
            return Ok(obj_mesh(r)?.map(|m| m.map(|m| Geometry::TriangleMesh(Arc::new(m)))));
        }
        // lancer extension: a voxel grid, from a MagicaVoxel file or inline.
        "voxels" => {
            let (grid, notes) = voxel_grid(r)?;
            return Ok(Fallback::noted(
                Some(Geometry::Voxels(Arc::new(grid))),
                notes,
            ));
        }
        "curve" => {
            let (desc, ignored_normals) = curve(p)?;
            let g = Some(Geometry::Curve(Arc::new(desc)));
            return Ok(if ignored_normals {
                Fallback::instead(
                    g,
                    "curve normals \"N\" are only used by \"ribbon\" curves; ignored",
                )
            } else {
                Fallback::done(g)
            });
        }
        "bilinearmesh" => Geometry::BilinearMesh(Arc::new(bilinear_mesh(p)?)),
        _ => {
            return Ok(Fallback::instead(
                None,
                format!("unknown shape \"{ty}\"; skipped"),
            ));
        }
    };
    g.validate().map_err(|e| rule_error(p, e))?;
    // pbrt's ranges for the hole of a disk and the bottom of a paraboloid, which lancer's shapes
    // do not need; checked once lancer's rules (a positive radius and top) hold.
    match g {
        Geometry::Disk(DiskDesc { radius, .. }) => {
            p.float_checked(
                "innerradius",
                0.0,
                "at least 0 and less than the radius",
                |v| (0.0..radius).contains(&v),
            )?;
        }
        Geometry::Paraboloid(ParaboloidDesc { z_max, .. }) => {
            p.float_checked("zmin", 0.0, "at least 0 and less than zmax", |v| {
                (0.0..z_max).contains(&v)
            })?;
        }
        _ => {}
    }
    Ok(Fallback::done(Some(g)))
}

/// A mesh's `point3 P`: `what` names the shape in the error when it is missing.
fn positions(p: &ParamList, what: &str) -> Result<Vec<PackedVec3>, SceneError> {
    p.point3s("P")?.ok_or_else(|| {
        SceneError::general(format!("a \"{what}\" needs vertex positions \"point3 P\""))
    })
}

/// pbrt's `trianglemesh`: `P`, `indices` (optional for a single triangle), `N`, `uv` (or
/// pbrt-v3's `st`).
fn triangle_mesh(p: &ParamList, what: &str) -> Result<TriangleMesh, SceneError> {
    let positions = positions(p, what)?;
    let indices: Vec<u32> = match p.ints("indices")? {
        Some((idx, loc)) => face_indices(idx, loc)?,
        None if positions.len() == 3 => vec![0, 1, 2],
        None => {
            return Err(p.error_at(
                "P",
                format!("a \"{what}\" with more than 3 vertices needs \"integer indices\""),
            ));
        }
    };
    let uv_name = if p.has("uv") { "uv" } else { "st" };
    Ok(TriangleMesh {
        positions,
        normals: p.normals("N")?.unwrap_or_default(),
        uvs: p.point2s(uv_name)?.unwrap_or_default(),
        indices,
        flip_normal: false,
    })
}

/// pbrt-v4's `bilinearmesh`: `P`, `indices` (four per patch: p₀₀, p₁₀, p₀₁, p₁₁; optional for
/// a single patch), `uv`, `N`.
fn bilinear_mesh(p: &ParamList) -> Result<BilinearMesh, SceneError> {
    let positions = positions(p, "bilinearmesh")?;
    let indices: Vec<u32> = match p.ints("indices")? {
        Some((idx, loc)) if idx.is_empty() => {
            return Err(SceneError::at(loc, "\"integer indices\" is empty"));
        }
        Some((idx, loc)) => face_indices(idx, loc)?,
        None if positions.len() == 4 => vec![0, 1, 2, 3],
        None => {
            return Err(p.error_at(
                "P",
                "a \"bilinearmesh\" with other than 4 vertices needs \"integer indices\"",
            ));
        }
    };
    Ok(BilinearMesh {
        positions,
        normals: p.normals("N")?.unwrap_or_default(),
        uvs: p.point2s("uv")?.unwrap_or_default(),
        indices,
        flip_normal: false,
    })
}

/// A mesh's `"integer indices"` as vertex numbers (none negative); whether they fit the mesh
/// is one of its rules ([`lancer::shape::IndexedMesh::check`]).
fn face_indices(idx: Vec<i32>, loc: Location) -> Result<Vec<u32>, SceneError> {
    if let Some(bad) = idx.iter().find(|&&i| i < 0) {
        return Err(SceneError::at(
            loc,
            format!("index {bad} in \"integer indices\" is negative"),
        ));
    }
    Ok(idx.into_iter().map(|i| i as u32).collect())
}

/// pbrt-v4's `curve`: `P`, `basis` (`bezier` | `bspline`), `degree` (2 | 3), `type` (`flat` |
/// `ribbon` | `cylinder`), `width` / `width0` / `width1`, `N` (ribbons: one per segment
/// boundary), `splitdepth` (default 3). Also says whether `N` was given to a curve that does
/// not use it.
fn curve(p: &ParamList) -> Result<(CurveDesc, bool), SceneError> {
    let Some(points) = p.point3s("P")? else {
        return Err(SceneError::general(
            "a \"curve\" needs control points \"point3 P\"",
        ));
    };
    let width = p.float("width", 1.0)?;
    let width0 = p.float("width0", width)?;
    let width1 = p.float("width1", width)?;
    let degree = p.int_in("degree", 3, 2..=3)? as u32;
    let basis = match p.string("basis")?.as_deref() {
        None | Some("bezier") => CurveBasis::Bezier,
        Some("bspline") => CurveBasis::BSpline,
        Some(other) => {
            return Err(p.error_at(
                "basis",
                format!("unknown curve basis \"{other}\" (expected \"bezier\" or \"bspline\")"),
            ));
        }
    };
    let kind = match p.string("type")?.as_deref() {
        None | Some("flat") => CurveType::Flat,
        Some("ribbon") => CurveType::Ribbon,
        Some("cylinder") => CurveType::Cylinder,
        Some(other) => {
            return Err(p.error_at(
                "type",
                format!(
                    "unknown curve type \"{other}\" (expected \"flat\", \"ribbon\" or \"cylinder\")"
                ),
            ));
        }
    };
    let split_depth = p.int_in("splitdepth", 3, 0..=10)? as u32;
    let mut normals = p.normals("N")?.unwrap_or_default();
    let ignored_normals = kind != CurveType::Ribbon && !normals.is_empty();
    if ignored_normals {
        normals.clear();
    }
    let desc = CurveDesc {
        points,
        basis,
        degree,
        kind,
        width0,
        width1,
        normals,
        split_depth,
    };
    desc.validate().map_err(|e| rule_error(p, e))?;
    Ok((desc, ignored_normals))
}

/// A mesh read from `path`, or `None` (with a warning) when it has no faces; faces with fewer
/// than 3 vertices, which the file readers skip, are noted.
fn file_mesh(
    mesh: TriangleMesh,
    skipped_faces: u64,
    path: &std::path::Path,
) -> (Option<TriangleMesh>, Vec<String>) {
    if mesh.triangle_count() == 0 {
        let skipped = format!("{} has no faces; the shape is skipped", path.display());
        return (None, vec![skipped]);
    }
    let mut notes = Vec::new();
    if skipped_faces > 0 {
        notes.push(format!(
            "{}: {skipped_faces} faces with fewer than 3 vertices skipped",
            path.display()
        ));
    }
    (Some(mesh), notes)
}

/// pbrt-v4's `objmesh`: every triangle of the OBJ file `filename` in one mesh (objects, groups
/// and materials merged; the file's materials are not used, the shape takes the current pbrt
/// material as any other shape does).
fn obj_mesh(r: &Reader) -> Result<Fallback<Option<TriangleMesh>>, SceneError> {
    let path = r.file("an \"objmesh\" needs the name of its OBJ file")?;
    let obj = read_obj(&path).map_err(|e| SceneError::general(e.to_string()))?;
    let mesh = obj.merged_mesh();
    mesh.validate()
        .map_err(|e| SceneError::general(format!("{}: {e}", path.display())))?;
    let (mesh, notes) = file_mesh(mesh, obj.skipped_faces, &path);
    Ok(Fallback::noted(mesh, notes))
}

/// A `plymesh`'s geometries: its triangles, its quads as bilinear patches, or both; and its
/// displacement.
type PlyGeometries = Option<(Geometry, Option<Geometry>, Option<Displacement>)>;

/// pbrt's `plymesh`: the faces of the PLY file `filename` (gzipped when it ends in `.gz`) as
/// pbrt-v4 makes them: triangles, and each quad a bilinear patch (its `BilinearPatchMesh`).
/// With `displacement` (a float texture, or a constant), the quads are triangles too (as
/// pbrt-v4 displaces them) and the mesh is refined and displaced by the builder.
fn ply_mesh(r: &Reader) -> Result<Fallback<PlyGeometries>, SceneError> {
    let p = r.params;
    let path = r.file("a \"plymesh\" needs the name of its PLY file")?;
    let ply = read_ply(&path).map_err(|e| SceneError::general(e.to_string()))?;
    let quads = ply.quads;
    let (mesh, mut notes) = file_mesh(ply.mesh, ply.skipped_faces, &path);
    let Some(mesh) = mesh else {
        return Ok(Fallback::noted(None, notes));
    };
    let texture = match p.float_or_texture("displacement")? {
        None => None,
        Some(FloatParam::Const(d)) => Some(FloatTex::Const(d)),
        Some(FloatParam::Texture(t, tloc)) => Some(r.textures.float(&t, &tloc)?),
    };
    let edge_loc = p.location("edgelength").cloned();
    let edge_length = p.float("edgelength", 1.0)?;
    let displacement = texture.map(|texture| Displacement {
        texture,
        edge_length,
        edge_loc,
        file: path.display().to_string(),
    });
    if displacement.is_none() && p.has("edgelength") {
        notes.push("\"edgelength\" only matters with \"displacement\"; ignored".into());
    }
    // pbrt-v4 displaces triangles (its `Displace` splits quads as the mesh holds them), so a
    // mesh with displacement keeps its quads' triangles.
    let quads = if displacement.is_some() { 0 } else { quads };
    let (tris, patches) = crate::ply::PlyMesh {
        mesh,
        quads,
        skipped_faces: 0,
    }
    .split_quads();
    // Both keep the rules `read_ply` checked: the same vertex arrays, and indices from its
    // triangles' (four to a patch).
    let patches = patches.map(|m| Geometry::BilinearMesh(Arc::new(m)));
    let geometries = match (tris, patches) {
        (Some(t), patches) => Some((Geometry::TriangleMesh(Arc::new(t)), patches, displacement)),
        (None, Some(patches)) => Some((patches, None, None)),
        (None, None) => None,
    };
    Ok(Fallback::noted(geometries, notes))
}

/// lancer's `voxels`: the first model of the MagicaVoxel file `filename`, or the inline grid
/// `integer dims` [nx ny nz] with `integer indices` (nx·ny·nz palette indices, x fastest,
/// 0 = empty) and an optional `float palette` (linear r, g, b of indices 1, 2, …; indices it
/// does not reach keep MagicaVoxel's default palette; `float` because pbrt's `rgb` holds one
/// colour). Also gives the file's warnings.
fn voxel_grid(r: &Reader) -> Result<(VoxelGrid, Vec<String>), SceneError> {
    let p = r.params;
    if let Some(name) = p.string("filename")? {
        let path = r.dir.resolve(&name);
        let model = read_vox(&path).map_err(|e| SceneError::general(e.to_string()))?;
        let warnings = model
            .warnings
            .iter()
            .map(|w| format!("{}: {w}", path.display()))
            .collect();
        return Ok((model.grid, warnings));
    }
    let Some((dims, dloc)) = p.ints("dims")? else {
        return Err(SceneError::general(
            "a \"voxels\" shape needs \"string filename\" or \"integer dims\" with \"integer indices\"",
        ));
    };
    if dims.len() != 3 || dims.iter().any(|&d| d <= 0) {
        return Err(SceneError::at(
            dloc,
            format!("\"integer dims\" must be three positive values, got {dims:?}"),
        ));
    }
    let dims = [dims[0] as u32, dims[1] as u32, dims[2] as u32];
    let Some((indices, iloc)) = p.ints("indices")? else {
        return Err(p.error_at(
            "dims",
            "a \"voxels\" shape with \"integer dims\" needs \"integer indices\"",
        ));
    };
    let count = dims.iter().map(|&d| d as u64).product::<u64>();
    if indices.len() as u64 != count {
        return Err(SceneError::at(
            iloc,
            format!(
                "\"integer indices\" holds {} values for {}×{}×{} = {count} cells",
                indices.len(),
                dims[0],
                dims[1],
                dims[2]
            ),
        ));
    }
    if let Some(bad) = indices.iter().find(|&&i| !(0..=255).contains(&i)) {
        return Err(SceneError::at(
            iloc,
            format!("palette index {bad} in \"integer indices\" is not in 0..=255"),
        ));
    }
    let cells = indices.iter().map(|&i| i as u8).collect();
    let mut palette = linear_palette(&default_palette());
    if let Some(values) = p.floats("palette")? {
        if values.len() % 3 != 0 || values.len() > 3 * 255 {
            return Err(p.error_at(
                "palette",
                format!(
                    "\"float palette\" holds {} values: it needs 3 (r, g, b) per colour, at most 255 colours",
                    values.len()
                ),
            ));
        }
        for (i, c) in values.chunks_exact(3).enumerate() {
            palette[i + 1] = Rgb::new(c[0], c[1], c[2]);
        }
    }
    let grid = VoxelGrid::new(dims, cells, palette).map_err(|m| p.error_at("dims", m))?;
    Ok((grid, Vec::new()))
}

#[cfg(test)]
mod tests;
mod trianglemesh;
