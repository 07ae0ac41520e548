//! `Shape` conversions: the defaults, every parameter, and each error at its place.

use super::*;
use crate::pbrt::convert::TextureNames;
use crate::pbrt::convert::testing::{err, typed_in, unused, with_textures};
use lancer::math::Vec2;
use lancer::shape::{
    BoxDesc, ConeDesc, CylinderDesc, DiskDesc, HyperboloidDesc, ParaboloidDesc, PlaneDesc,
    SphereDesc,
};
use std::path::{Path, PathBuf};

mod rules;

/// The conversion of the one `Shape` of `text` (relative names against `dir`, `textures`
/// defined), and the messages of the parameters it left unread.
fn convert_full(
    text: &str,
    dir: &Path,
    textures: &TextureNames,
    emits: bool,
) -> (
    Result<Fallback<Option<ShapeGeometry>>, SceneError>,
    Vec<String>,
) {
    let (ty, params, loc) = typed_in(text, dir);
    let out = with_textures(&params, dir, textures, |r| shape(r, &ty, emits, &loc));
    (out, unused(&params))
}

fn convert(text: &str) -> Result<Fallback<Option<ShapeGeometry>>, SceneError> {
    convert_full(text, Path::new("."), &TextureNames::default(), false).0
}

/// The geometry of a shape that converts without warnings and reads every parameter.
#[track_caller]
fn geometry(text: &str) -> Geometry {
    let (out, unused) = convert_full(text, Path::new("."), &TextureNames::default(), false);
    let f = out.unwrap_or_else(|e| panic!("{e}"));
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    assert!(unused.is_empty(), "{unused:?}");
    f.value.expect("kept").geometry
}

#[track_caller]
fn error(text: &str) -> String {
    err(convert(text))
}

fn mesh(g: Geometry) -> TriangleMesh {
    match g {
        Geometry::TriangleMesh(m) => (*m).clone(),
        other => panic!("not a triangle mesh: {other:?}"),
    }
}

fn v3(x: f32, y: f32, z: f32) -> PackedVec3 {
    PackedVec3::new(x, y, z)
}

#[test]
fn quadrics_take_pbrt_defaults() {
    let sphere = Geometry::Sphere(SphereDesc {
        radius: 1.0,
        z_min: -1.0,
        z_max: 1.0,
        phi_max: 360.0,
    });
    assert_eq!(geometry(r#"Shape "sphere""#), sphere);
    let disk = Geometry::Disk(DiskDesc {
        height: 0.0,
        radius: 1.0,
        inner_radius: 0.0,
        phi_max: 360.0,
    });
    assert_eq!(geometry(r#"Shape "disk""#), disk);
    let cylinder = Geometry::Cylinder(CylinderDesc {
        radius: 1.0,
        z_min: -1.0,
        z_max: 1.0,
        phi_max: 360.0,
    });
    assert_eq!(geometry(r#"Shape "cylinder""#), cylinder);
    let cone = Geometry::Cone(ConeDesc {
        radius: 1.0,
        height: 1.0,
        phi_max: 360.0,
    });
    assert_eq!(geometry(r#"Shape "cone""#), cone);
    let paraboloid = Geometry::Paraboloid(ParaboloidDesc {
        radius: 1.0,
        z_min: 0.0,
        z_max: 1.0,
        phi_max: 360.0,
    });
    assert_eq!(geometry(r#"Shape "paraboloid""#), paraboloid);
    let hyperboloid = Geometry::Hyperboloid(HyperboloidDesc {
        p1: Vec3::ZERO,
        p2: Vec3::ONE,
        phi_max: 360.0,
    });
    assert_eq!(geometry(r#"Shape "hyperboloid""#), hyperboloid);
    let cuboid = Geometry::Box(BoxDesc {
        min: Vec3::splat(-1.0),
        max: Vec3::ONE,
    });
    assert_eq!(geometry(r#"Shape "box""#), cuboid);
    let plane = Geometry::Plane(PlaneDesc {
        p: Vec3::ZERO,
        n: Vec3::Z,
    });
    assert_eq!(geometry(r#"Shape "plane""#), plane);
}

#[test]
fn quadrics_read_every_parameter() {
    let g = geometry(
        r#"Shape "sphere" "float radius" 2 "float zmin" -1 "float zmax" 1.5 "float phimax" 90"#,
    );
    let sphere = Geometry::Sphere(SphereDesc {
        radius: 2.0,
        z_min: -1.0,
        z_max: 1.5,
        phi_max: 90.0,
    });
    assert_eq!(g, sphere);
    // A sphere's zmin and zmax default to ∓ its radius.
    let Geometry::Sphere(SphereDesc { z_min, z_max, .. }) =
        geometry(r#"Shape "sphere" "float radius" 3"#)
    else {
        panic!("a sphere")
    };
    assert_eq!((z_min, z_max), (-3.0, 3.0));
    let g = geometry(
        r#"Shape "disk" "float height" 0.5 "float radius" 2 "float innerradius" 1 "float phimax" 180"#,
    );
    let disk = Geometry::Disk(DiskDesc {
        height: 0.5,
        radius: 2.0,
        inner_radius: 1.0,
        phi_max: 180.0,
    });
    assert_eq!(g, disk);
    let g = geometry(
        r#"Shape "cylinder" "float radius" 2 "float zmin" 0 "float zmax" 3 "float phimax" 45"#,
    );
    let cylinder = Geometry::Cylinder(CylinderDesc {
        radius: 2.0,
        z_min: 0.0,
        z_max: 3.0,
        phi_max: 45.0,
    });
    assert_eq!(g, cylinder);
    let g = geometry(r#"Shape "cone" "float radius" 2 "float height" 3 "float phimax" 10"#);
    let cone = Geometry::Cone(ConeDesc {
        radius: 2.0,
        height: 3.0,
        phi_max: 10.0,
    });
    assert_eq!(g, cone);
    let g = geometry(
        r#"Shape "paraboloid" "float radius" 2 "float zmin" 0.5 "float zmax" 3 "float phimax" 20"#,
    );
    let paraboloid = Geometry::Paraboloid(ParaboloidDesc {
        radius: 2.0,
        z_min: 0.5,
        z_max: 3.0,
        phi_max: 20.0,
    });
    assert_eq!(g, paraboloid);
    let g = geometry(
        r#"Shape "hyperboloid" "point3 p1" [1 0 -1] "point3 p2" [0 1 1] "float phimax" 30"#,
    );
    let hyperboloid = Geometry::Hyperboloid(HyperboloidDesc {
        p1: Vec3::new(1.0, 0.0, -1.0),
        p2: Vec3::new(0.0, 1.0, 1.0),
        phi_max: 30.0,
    });
    assert_eq!(g, hyperboloid);
    let g = geometry(r#"Shape "box" "point3 min" [0 0 0] "point3 max" [1 2 3]"#);
    let cuboid = Geometry::Box(BoxDesc {
        min: Vec3::ZERO,
        max: Vec3::new(1.0, 2.0, 3.0),
    });
    assert_eq!(g, cuboid);
    let g = geometry(r#"Shape "plane" "point3 p" [0 1 0] "normal n" [0 2 0]"#);
    // The normal is kept as written (the renderer normalises it).
    let plane = Geometry::Plane(PlaneDesc {
        p: Vec3::Y,
        n: Vec3::new(0.0, 2.0, 0.0),
    });
    assert_eq!(g, plane);
}

#[test]
fn quadric_errors_are_at_their_parameter() {
    assert_eq!(
        error("Shape \"sphere\"\n  \"float radius\" -1"),
        "t.pbrt:2:3: radius must be positive, got -1"
    );
    assert_eq!(
        error("Shape \"cylinder\"\n  \"float phimax\" 400"),
        "t.pbrt:2:3: \"float phimax\" must be in (0, 360], not 400"
    );
    assert_eq!(
        error("Shape \"disk\" \"float radius\" 1\n  \"float innerradius\" 1"),
        "t.pbrt:2:3: \"float innerradius\" must be at least 0 and less than the radius, not 1"
    );
    assert_eq!(
        error("Shape \"cone\"\n  \"float height\" 0"),
        "t.pbrt:2:3: height must be positive, got 0"
    );
    assert_eq!(
        error("Shape \"paraboloid\" \"float zmax\" 1\n  \"float zmin\" 2"),
        "t.pbrt:2:3: \"float zmin\" must be at least 0 and less than zmax, not 2"
    );
    let (p1, p2) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(1.0, 1.0, 1.0));
    assert_eq!(
        error("Shape \"hyperboloid\" \"point3 p1\" [0 0 1]\n  \"point3 p2\" [1 1 1]"),
        format!(
            "t.pbrt:2:3: the hyperboloid's \"p1\" {p1} and \"p2\" {p2} must be finite and at \
             different heights (at one height the swept segment is a flat annulus: use a disk)"
        )
    );
    // Without "p2", the message points at "p1".
    assert!(error("Shape \"hyperboloid\"\n  \"point3 p1\" [0 0 1]").starts_with("t.pbrt:2:3: "),);
    let (min, max) = (Vec3::ONE, Vec3::new(0.0, 2.0, 2.0));
    assert_eq!(
        error("Shape \"box\" \"point3 min\" [1 1 1]\n  \"point3 max\" [0 2 2]"),
        format!(
            "t.pbrt:2:3: the box's \"min\" {min} must be finite and below its \"max\" {max} on \
             every axis"
        )
    );
    assert_eq!(
        error("Shape \"plane\"\n  \"normal n\" [0 0 0]"),
        "t.pbrt:2:3: the plane's normal \"n\" is zero"
    );
}

#[test]
fn a_single_triangle_needs_no_indices() {
    let m = mesh(geometry(
        r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0]"#,
    ));
    assert_eq!(
        m.positions,
        [v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0), v3(0.0, 1.0, 0.0)]
    );
    assert_eq!(m.indices, [0, 1, 2]);
    assert!(m.normals.is_empty() && m.uvs.is_empty() && !m.flip_normal);
}

#[test]
fn triangle_meshes_read_every_parameter() {
    let m = mesh(geometry(
        r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0 1 1 0] "integer indices" [0 1 2 2 1 3]
           "normal N" [0 0 1 0 0 1 0 0 1 0 0 1] "point2 uv" [0 0 1 0 0 1 1 1]"#,
    ));
    assert_eq!(m.indices, [0, 1, 2, 2, 1, 3]);
    assert_eq!(m.normals, vec![v3(0.0, 0.0, 1.0); 4]);
    assert_eq!(m.uvs[3], Vec2::new(1.0, 1.0));
    // pbrt-v3's "st" and untyped "float" pairs are read as uv.
    let m = mesh(geometry(
        r#"Shape "trianglemesh" "point3 P" [0 0 0 1 0 0 0 1 0] "float st" [0 0 1 0 0 1]"#,
    ));
    assert_eq!(m.uvs, [Vec2::ZERO, Vec2::X, Vec2::Y]);
}

/// The warnings of a shape that converts, and its mesh if kept.
#[track_caller]
fn mesh_warnings(text: &str) -> (Option<TriangleMesh>, Vec<String>) {
    let (out, unused) = convert_full(text, Path::new("."), &TextureNames::default(), false);
    let f = out.unwrap_or_else(|e| panic!("{e}"));
    let kept = f.value.map(|s| mesh(s.geometry));
    if kept.is_some() {
        assert!(unused.is_empty(), "{unused:?}");
    }
    (kept, f.warnings)
}

#[test]
fn inconsistent_triangle_mesh_arrays_are_treated_as_pbrt_v4_does() {
    let tri = "\"point3 P\" [0 0 0 1 0 0 0 1 0]";
    // Meshes pbrt-v4 drops (with an error message, going on with the scene).
    let (m, w) = mesh_warnings(r#"Shape "trianglemesh""#);
    assert!(m.is_none());
    assert_eq!(
        w,
        [
            "a \"trianglemesh\" with 0 vertices needs vertex indices \"integer indices\"; the mesh \
          is skipped"
        ]
    );
    let (m, w) = mesh_warnings(r#"Shape "trianglemesh" "integer indices" [0 1 2]"#);
    assert!(m.is_none());
    assert_eq!(
        w,
        ["a \"trianglemesh\" needs vertex positions \"point3 P\"; the mesh is skipped"]
    );
    let (m, w) = mesh_warnings("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]");
    assert!(m.is_none());
    assert!(
        w[0].starts_with("a \"trianglemesh\" with 4 vertices needs"),
        "{w:?}"
    );
    for bad in ["3", "-1"] {
        let (m, w) = mesh_warnings(&format!(
            "Shape \"trianglemesh\" {tri} \"integer indices\" [0 1 2 0 1 {bad}]"
        ));
        assert!(m.is_none());
        assert_eq!(
            w,
            [format!(
                "vertex index {bad} is out of range for 3 vertices \"P\"; the mesh is skipped"
            )]
        );
    }
    // What pbrt-v4 trims or drops from a mesh it keeps.
    let (m, w) = mesh_warnings(&format!(
        "Shape \"trianglemesh\" {tri} \"integer indices\" [0 1 2 2 1]\n  \
         \"normal N\" [0 0 1 0 0 1] \"point2 uv\" [0 0 1 0 0 1 1 1]"
    ));
    let m = m.expect("kept");
    assert_eq!(m.indices, [0, 1, 2]);
    assert!(m.normals.is_empty() && m.uvs.is_empty());
    assert_eq!(
        w,
        [
            "\"integer indices\" has 5 values, not a multiple of 3: the last 2 are dropped; 4 uvs \
          for 3 vertices: the uvs are dropped; 2 normals \"N\" for 3 vertices: the normals are \
          dropped"
        ]
    );
    // Two indices make no triangle.
    let (m, w) = mesh_warnings(&format!(
        "Shape \"trianglemesh\" {tri} \"integer indices\" [0 1]"
    ));
    assert!(m.is_none());
    assert!(
        w[0].ends_with("no triangle is left; the mesh is skipped"),
        "{w:?}"
    );
}

#[test]
fn loop_subdivision_refines_the_control_mesh() {
    // Each level splits every triangle into 4: 3 levels (the default) give 64 triangles.
    let m = mesh(geometry(
        r#"Shape "loopsubdiv" "point3 P" [0 0 0 1 0 0 0 1 0]"#,
    ));
    assert_eq!(m.indices.len(), 3 * 64);
    let m = mesh(geometry(
        r#"Shape "loopsubdiv" "integer levels" 1 "point3 P" [0 0 0 1 0 0 0 1 0]"#,
    ));
    assert_eq!(m.indices.len(), 3 * 4);
    assert_eq!(
        error("Shape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n  \"integer levels\" 9"),
        "t.pbrt:2:3: \"integer levels\" must be between 0 and 8, not 9"
    );
    assert_eq!(
        error(r#"Shape "loopsubdiv""#),
        "t.pbrt:1:1: a \"loopsubdiv\" needs vertex positions \"point3 P\""
    );
}

#[test]
fn bilinear_meshes() {
    let one = r#"Shape "bilinearmesh" "point3 P" [0 0 0 1 0 0 0 1 0 1 1 0]"#;
    let Geometry::BilinearMesh(m) = geometry(one) else {
        panic!("a bilinear mesh")
    };
    assert_eq!(m.indices, [0, 1, 2, 3]);
    let Geometry::BilinearMesh(m) = geometry(
        r#"Shape "bilinearmesh" "point3 P" [0 0 0 1 0 0 0 1 0 1 1 0] "integer indices" [3 2 1 0]
           "normal N" [0 0 1 0 0 1 0 0 1 0 0 1] "point2 uv" [0 0 1 0 0 1 1 1]"#,
    ) else {
        panic!("a bilinear mesh")
    };
    assert_eq!(
        (m.indices.as_slice(), m.normals.len(), m.uvs.len()),
        (&[3, 2, 1, 0][..], 4, 4)
    );
    assert_eq!(
        error(r#"Shape "bilinearmesh""#),
        "t.pbrt:1:1: a \"bilinearmesh\" needs vertex positions \"point3 P\""
    );
    assert_eq!(
        error("Shape \"bilinearmesh\"\n  \"point3 P\" [0 0 0 1 0 0 0 1 0]"),
        "t.pbrt:2:3: a \"bilinearmesh\" with other than 4 vertices needs \"integer indices\""
    );
    assert_eq!(
        error(
            "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n  \"integer indices\" [0 1 2]"
        ),
        "t.pbrt:2:3: the mesh has 3 indices, not a multiple of 4"
    );
    assert_eq!(
        error(
            "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n  \"normal N\" [0 0 1]"
        ),
        "t.pbrt:2:3: 1 normals for 4 vertices"
    );
}

#[test]
fn curves() {
    let cubic = r#"Shape "curve" "point3 P" [0 0 0 1 0 0 2 0 0 3 0 0]"#;
    let Geometry::Curve(c) = geometry(cubic) else {
        panic!("a curve")
    };
    let expected = CurveDesc {
        points: vec![
            v3(0.0, 0.0, 0.0),
            v3(1.0, 0.0, 0.0),
            v3(2.0, 0.0, 0.0),
            v3(3.0, 0.0, 0.0),
        ],
        basis: CurveBasis::Bezier,
        degree: 3,
        kind: CurveType::Flat,
        width0: 1.0,
        width1: 1.0,
        normals: Vec::new(),
        split_depth: 3,
    };
    assert_eq!(*c, expected);
    let Geometry::Curve(c) = geometry(
        r#"Shape "curve" "point3 P" [0 0 0 1 0 0 2 0 0] "string basis" "bspline" "integer degree" 2
           "string type" "ribbon" "float width0" 0.5 "float width1" 0.25 "normal N" [0 0 1 0 0 1]
           "integer splitdepth" 2"#,
    ) else {
        panic!("a curve")
    };
    assert_eq!(
        (
            c.basis,
            c.degree,
            c.kind,
            c.width0,
            c.width1,
            c.normals.len(),
            c.split_depth
        ),
        (CurveBasis::BSpline, 2, CurveType::Ribbon, 0.5, 0.25, 2, 2)
    );
    // `width` sets both ends.
    let Geometry::Curve(c) = geometry(&format!("{cubic} \"float width\" 0.1")) else {
        panic!("a curve")
    };
    assert_eq!((c.width0, c.width1), (0.1, 0.1));
    // Normals of a flat curve are dropped, with a warning.
    let f = convert(&format!("{cubic} \"normal N\" [0 0 1 0 0 1]")).unwrap();
    assert_eq!(
        f.warnings,
        ["curve normals \"N\" are only used by \"ribbon\" curves; ignored"]
    );
    let Some(ShapeGeometry {
        geometry: Geometry::Curve(c),
        ..
    }) = f.value
    else {
        panic!("a curve")
    };
    assert!(c.normals.is_empty());
}

#[test]
fn curve_errors_are_at_their_parameter() {
    assert_eq!(
        error(r#"Shape "curve""#),
        "t.pbrt:1:1: a \"curve\" needs control points \"point3 P\""
    );
    let p = "Shape \"curve\" \"point3 P\" [0 0 0 1 0 0 2 0 0 3 0 0]\n  ";
    assert_eq!(
        error(&format!("{p}\"string basis\" \"nurbs\"")),
        "t.pbrt:2:3: unknown curve basis \"nurbs\" (expected \"bezier\" or \"bspline\")"
    );
    assert_eq!(
        error(&format!("{p}\"string type\" \"tube\"")),
        "t.pbrt:2:3: unknown curve type \"tube\" (expected \"flat\", \"ribbon\" or \"cylinder\")"
    );
    assert_eq!(
        error(&format!("{p}\"float width\" -1")),
        "t.pbrt:2:3: curve widths must be finite and at least 0, got -1 and -1"
    );
    assert_eq!(
        error(&format!("{p}\"integer degree\" 4")),
        "t.pbrt:2:3: \"integer degree\" must be between 2 and 3, not 4"
    );
    assert_eq!(
        error(&format!("{p}\"integer splitdepth\" 11")),
        "t.pbrt:2:3: \"integer splitdepth\" must be between 0 and 10, not 11"
    );
}

#[test]
fn inline_voxels() {
    let Geometry::Voxels(g) = geometry(
        r#"Shape "voxels" "integer dims" [2 1 1] "integer indices" [1 0] "float palette" [1 0 0]"#,
    ) else {
        panic!("voxels")
    };
    assert_eq!(g.dims(), [2, 1, 1]);
    assert_eq!((g.get(0, 0, 0), g.get(1, 0, 0)), (1, 0));
    assert_eq!(g.palette()[1], Rgb::new(1.0, 0.0, 0.0));
    // Indices the palette does not reach keep MagicaVoxel's default colours.
    let default = linear_palette(&default_palette());
    assert_eq!(g.palette()[2], default[2]);
}

#[test]
fn voxel_errors_are_at_their_parameter() {
    assert_eq!(
        error(r#"Shape "voxels""#),
        "t.pbrt:1:1: a \"voxels\" shape needs \"string filename\" or \"integer dims\" with \"integer indices\""
    );
    assert_eq!(
        error("Shape \"voxels\"\n  \"integer dims\" [2 1]"),
        "t.pbrt:2:3: \"integer dims\" must be three positive values, got [2, 1]"
    );
    assert_eq!(
        error("Shape \"voxels\"\n  \"integer dims\" [2 1 1]"),
        "t.pbrt:2:3: a \"voxels\" shape with \"integer dims\" needs \"integer indices\""
    );
    assert_eq!(
        error("Shape \"voxels\" \"integer dims\" [2 1 1]\n  \"integer indices\" [1]"),
        "t.pbrt:2:3: \"integer indices\" holds 1 values for 2×1×1 = 2 cells"
    );
    assert_eq!(
        error("Shape \"voxels\" \"integer dims\" [2 1 1]\n  \"integer indices\" [1 300]"),
        "t.pbrt:2:3: palette index 300 in \"integer indices\" is not in 0..=255"
    );
    assert_eq!(
        error(
            "Shape \"voxels\" \"integer dims\" [2 1 1] \"integer indices\" [1 0]\n  \"float palette\" [1 0]"
        ),
        "t.pbrt:2:3: \"float palette\" holds 2 values: it needs 3 (r, g, b) per colour, at most 255 colours"
    );
}

#[test]
fn unknown_shapes_are_skipped_with_a_warning() {
    let f = convert(r#"Shape "teapot" "float size" 2"#).unwrap();
    assert!(f.value.is_none());
    assert_eq!(f.warnings, ["unknown shape \"teapot\"; skipped"]);
}

#[test]
fn alpha_is_a_constant_or_a_float_texture() {
    let alpha = |text: &str, textures: &TextureNames| {
        let (out, unused) = convert_full(text, Path::new("."), textures, false);
        assert!(unused.is_empty(), "{unused:?}");
        out.map(|f| f.value.expect("kept").alpha)
    };
    let none = TextureNames::default();
    assert_eq!(alpha(r#"Shape "sphere""#, &none), Ok(None));
    assert_eq!(alpha(r#"Shape "sphere" "float alpha" 1"#, &none), Ok(None));
    assert_eq!(
        alpha(r#"Shape "sphere" "float alpha" 0.5"#, &none),
        Ok(Some(FloatTex::Const(0.5)))
    );
    let mut textures = TextureNames::default();
    textures.floats.insert("cut".into(), 4);
    textures.spectra.insert("colour".into(), 0);
    assert_eq!(
        alpha(r#"Shape "sphere" "texture alpha" "cut""#, &textures),
        Ok(Some(FloatTex::Tex(4)))
    );
    assert_eq!(
        err(alpha(
            "Shape \"sphere\"\n  \"texture alpha\" \"colour\"",
            &textures
        )),
        "t.pbrt:2:3: no float texture named \"colour\" (there is a spectrum texture of that name)"
    );
    assert_eq!(
        err(alpha(
            "Shape \"sphere\"\n  \"texture alpha\" \"nope\"",
            &textures
        )),
        "t.pbrt:2:3: no float texture named \"nope\""
    );
}

#[test]
fn curves_voxels_and_sdfs_cannot_emit() {
    let emitting =
        |text: &str| convert_full(text, Path::new("."), &TextureNames::default(), true).0;
    assert!(emitting(r#"Shape "sphere""#).is_ok());
    assert_eq!(
        err(emitting(
            r#"Shape "curve" "point3 P" [0 0 0 1 0 0 2 0 0 3 0 0]"#
        )),
        "t.pbrt:1:1: a curve cannot be an area light (pbrt-v4 cannot sample curves either)"
    );
    assert_eq!(
        err(emitting(
            r#"Shape "voxels" "integer dims" [1 1 1] "integer indices" [1]"#
        )),
        "t.pbrt:1:1: a \"voxels\" shape cannot be an area light (AttributeBegin/AttributeEnd around the AreaLightSource keeps it from the voxels)"
    );
    assert_eq!(
        err(emitting(r#"Shape "sdf" "string expr" "sphere(1)""#)),
        "t.pbrt:1:1: an sdf shape cannot be an area light (its area has no closed form)"
    );
}

/// A fresh folder holding `files` (name, contents).
fn folder(test: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lancer-shapes-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    dir
}

const TRIANGLE_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
const EMPTY_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";

#[test]
fn mesh_files_are_read_with_their_warnings() {
    let dir = folder(
        "files",
        &[
            ("t.ply", TRIANGLE_PLY),
            ("empty.ply", EMPTY_PLY),
            ("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2\n"),
        ],
    );
    let read = |text: &str| {
        let (out, unused) = convert_full(text, &dir, &TextureNames::default(), false);
        (out.unwrap_or_else(|e| panic!("{e}")), unused)
    };
    let (f, unused) = read(r#"Shape "plymesh" "string filename" "t.ply""#);
    assert!(f.warnings.is_empty() && unused.is_empty());
    let m = mesh(f.value.expect("kept").geometry);
    assert_eq!(m.indices, [0, 1, 2]);
    // A displacement is passed on to the builder with its edge length (read where given).
    let (f, unused) = read(
        r#"Shape "plymesh" "string filename" "t.ply" "float displacement" 0.1 "float edgelength" 0.5"#,
    );
    assert!(f.warnings.is_empty() && unused.is_empty());
    let d = f.value.expect("kept").displacement.expect("displaced");
    assert_eq!((d.texture, d.edge_length), (FloatTex::Const(0.1), 0.5));
    assert!(d.edge_loc.is_some());
    let (f, unused) = read(r#"Shape "plymesh" "string filename" "t.ply" "float edgelength" 2"#);
    assert!(f.value.expect("kept").displacement.is_none());
    assert_eq!(
        f.warnings,
        ["\"edgelength\" only matters with \"displacement\"; ignored"]
    );
    assert!(unused.is_empty());
    let empty = dir.join("empty.ply");
    let (f, _) = read(r#"Shape "plymesh" "string filename" "empty.ply""#);
    assert!(f.value.is_none());
    assert_eq!(
        f.warnings,
        [format!(
            "{} has no faces; the shape is skipped",
            empty.display()
        )]
    );
    let obj = dir.join("t.obj");
    let (f, _) = read(r#"Shape "objmesh" "string filename" "t.obj""#);
    assert_eq!(
        f.warnings,
        [format!(
            "{}: 1 faces with fewer than 3 vertices skipped",
            obj.display()
        )]
    );
    assert_eq!(mesh(f.value.expect("kept").geometry).indices, [0, 1, 2]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn mesh_file_errors_are_at_the_shape() {
    assert_eq!(
        error(r#"Shape "plymesh""#),
        "t.pbrt:1:1: a \"plymesh\" needs the name of its PLY file, \"string filename\""
    );
    assert_eq!(
        error(r#"Shape "objmesh""#),
        "t.pbrt:1:1: an \"objmesh\" needs the name of its OBJ file, \"string filename\""
    );
    let missing = error(r#"Shape "plymesh" "string filename" "no-such-file.ply""#);
    assert!(
        missing.starts_with("t.pbrt:1:1: ") && missing.contains("no-such-file.ply"),
        "{missing}"
    );
}
