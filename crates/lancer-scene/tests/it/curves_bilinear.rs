//! pbrt-v4's `curve` and `bilinearmesh` directives: parameters and defaults as pbrt reads
//! them, and errors at the line and column where the bad parameter is written.

use lancer::Scene;
use lancer::math::Vec3;
use lancer::scene::desc::Geometry;
use lancer::shape::{CurveBasis, CurveType, Shape};
use lancer_scene::{LoadedScene, load_pbrt_str};
use std::path::Path;

fn load(text: &str) -> Result<LoadedScene, String> {
    load_pbrt_str(&format!("WorldBegin\n{text}"), "t.pbrt", Path::new("."))
        .map_err(|e| e.to_string())
}

#[test]
fn curves_take_pbrts_parameters_and_defaults() {
    let loaded = load(
        r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0  4 -1 0  5 -1 0  6 0 0]
        Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0  4 -1 0] "string basis" "bspline"
            "string type" "cylinder" "float width" [0.5] "float width1" [0.1] "integer splitdepth" [2]
        Shape "curve" "point3 P" [0 0 0  1 1 0  2 0 0] "integer degree" [2] "string type" "ribbon"
            "normal N" [0 0 1  0 1 0]"#,
    )
    .unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let curves: Vec<_> = loaded
        .desc
        .shapes
        .iter()
        .map(|s| match &s.geometry {
            Geometry::Curve(c) => c.clone(),
            g => panic!("{g:?}"),
        })
        .collect();
    let c = &curves[0];
    assert_eq!(c.segment_count(), Ok(2));
    assert_eq!(
        (c.kind, c.basis, c.degree),
        (CurveType::Flat, CurveBasis::Bezier, 3)
    );
    assert_eq!((c.width0, c.width1, c.split_depth), (1.0, 1.0, 3));
    let c = &curves[1];
    assert_eq!(c.segment_count(), Ok(2));
    assert_eq!(
        (c.kind, c.basis),
        (CurveType::Cylinder, CurveBasis::BSpline)
    );
    assert_eq!((c.width0, c.width1, c.split_depth), (0.5, 0.1, 2));
    let c = &curves[2];
    assert_eq!(
        (c.kind, c.degree, c.normals.len()),
        (CurveType::Ribbon, 2, 2)
    );

    // Built: 2 segments × 2³ pieces, 2 × 2², 1 × 2³; widths per segment as pbrt's lerp.
    let scene = Scene::build(&loaded.desc).unwrap();
    let pieces: Vec<_> = scene
        .shapes()
        .iter()
        .filter_map(|s| match s {
            Shape::Curve(c) => Some(c),
            _ => None,
        })
        .collect();
    assert_eq!(pieces.len(), 16 + 8 + 8);
    let mut widths: Vec<[f32; 2]> = pieces.iter().map(|c| c.common.width).collect();
    widths.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    widths.dedup();
    assert!(
        widths.contains(&[0.5, 0.3]) && widths.contains(&[0.3, 0.1]),
        "{widths:?}"
    );
}

#[test]
fn normals_on_a_flat_curve_are_ignored_with_a_warning() {
    let loaded =
        load(r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0] "normal N" [0 0 1  0 0 1]"#)
            .unwrap();
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    assert!(loaded.warnings[0].to_string().contains("ribbon"));
}

#[test]
fn bad_curves_are_errors_where_they_are_written() {
    for (text, col, words) in [
        (
            r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0  4 0 0]"#,
            "t.pbrt:2:15",
            "control points",
        ),
        (
            r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0] "string type" "ribbon""#,
            "t.pbrt:2:15",
            "normals",
        ),
        (
            r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0] "string type" "ribbon" "normal N" [0 0 1]"#,
            "t.pbrt:2:78",
            "2 normals",
        ),
        (
            r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0] "string type" "tube""#,
            "t.pbrt:2:55",
            "unknown curve type",
        ),
        (
            r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0] "string basis" "nurbs""#,
            "t.pbrt:2:55",
            "unknown curve basis",
        ),
        (
            r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0] "integer degree" [4]"#,
            "t.pbrt:2:55",
            "between 2 and 3",
        ),
        (
            r#"Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0] "float width0" [-1]"#,
            "t.pbrt:2:55",
            "at least 0",
        ),
        (
            r#"AreaLightSource "diffuse"
Shape "curve" "point3 P" [0 0 0  1 1 0  2 1 0  3 0 0]"#,
            "t.pbrt:3:1",
            "area light",
        ),
    ] {
        let msg = load(text).expect_err(text);
        assert!(msg.contains(col) && msg.contains(words), "{text}: {msg}");
    }
}

#[test]
fn bilinear_meshes_take_pbrts_parameters() {
    let loaded = load(
        r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1]
        AreaLightSource "diffuse" "rgb L" [1 1 1]
        Shape "bilinearmesh" "point3 P" [0 0 2  1 0 2  0 1 2  1 1 2  2 0 2  2 1 2]
            "integer indices" [0 1 2 3  1 4 3 5] "point2 uv" [0 0 1 0 0 1 1 1 2 0 2 1]
            "normal N" [0 0 1  0 0 1  0 0 1  0 0 1  0 0 1  0 0 1]"#,
    )
    .unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let Geometry::BilinearMesh(m) = &loaded.desc.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(m.indices, vec![0, 1, 2, 3]);
    let Geometry::BilinearMesh(m) = &loaded.desc.shapes[1].geometry else {
        panic!()
    };
    assert_eq!((m.patch_count(), m.uvs.len(), m.normals.len()), (2, 6, 6));
    // The emitting mesh: one area light per patch, each of area 1.
    let scene = Scene::build(&loaded.desc).unwrap();
    assert_eq!(scene.lights().len(), 2);
    for (s, info) in scene
        .shapes()
        .iter()
        .enumerate()
        .map(|(i, s)| (s, scene.prim(i as u32)))
    {
        if info.emission.is_some() {
            assert!((s.area() - 1.0).abs() < 1e-5);
        }
    }
    // A ray down onto the emitting mesh finds its uv and its normal +z.
    let hit = scene
        .intersect(&lancer::ray::Ray::new(Vec3::new(1.5, 0.25, 5.0), -Vec3::Z))
        .unwrap();
    assert!(
        (hit.si.uv - glam::Vec2::new(1.5, 0.25)).length() < 1e-5,
        "{}",
        hit.si.uv
    );
    assert!((hit.si.n - Vec3::Z).length() < 1e-5);
}

#[test]
fn bad_bilinear_meshes_are_errors_where_they_are_written() {
    for (text, col, words) in [
        (
            r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1  2 2 2]"#,
            "t.pbrt:2:22",
            "indices",
        ),
        (
            r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1] "integer indices" [0 1 2]"#,
            "t.pbrt:2:62",
            "multiple of 4",
        ),
        (
            r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1] "integer indices" [0 1 2 4]"#,
            "t.pbrt:2:62",
            "out of range",
        ),
        (
            r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1] "normal N" [0 0 1]"#,
            "t.pbrt:2:62",
            "1 normals for 4 vertices",
        ),
        (
            r#"Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 1] "point2 uv" [0 0 1 1]"#,
            "t.pbrt:2:62",
            "2 uvs for 4 vertices",
        ),
        (
            r#"Shape "bilinearmesh" "integer indices" [0 1 2 3]"#,
            "t.pbrt",
            "point3 P",
        ),
    ] {
        let msg = load(text).expect_err(text);
        assert!(msg.contains(col) && msg.contains(words), "{text}: {msg}");
    }
}
