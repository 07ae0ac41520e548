//! The rules the reader shares with lancer's descriptions: each checked once, by lancer, and
//! reported by the reader with lancer's message at the parameter's place.

use super::*;
use lancer::shape::{
    BoxDesc, ConeDesc, HyperboloidDesc, ParaboloidDesc, PlaneDesc, SdfDesc, SphereDesc,
};

/// The description `geometry` as an area light.
fn glowing_desc(geometry: Geometry) -> lancer::scene::desc::ShapeDesc {
    lancer::scene::desc::ShapeDesc {
        medium_interface: None,
        geometry,
        object_to_world: lancer::math::Transform::IDENTITY,
        reverse_orientation: false,
        material: 0,
        area_light: Some(lancer::scene::desc::AreaLightDesc {
            l: Rgb::ONE,
            two_sided: false,
            spectrum: None,
            power: None,
            image: None,
        }),
        alpha: None,
    }
}

/// Each rule the reader and lancer both know is checked once, by lancer: the reader's error
/// is lancer's message for the same description, after the parameter's location (the
/// directive's when the rule is about the whole shape).
#[test]
fn the_readers_errors_are_lancers_rules() {
    let three = vec![v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0), v3(0.0, 1.0, 0.0)];
    let triangles = |indices: Vec<u32>, normals: Vec<PackedVec3>, uvs: Vec<Vec2>| {
        Geometry::TriangleMesh(Arc::new(TriangleMesh {
            positions: three.clone(),
            normals,
            uvs,
            indices,
            flip_normal: false,
        }))
    };
    let bezier = r#"Shape "curve" "point3 P" [0 0 0 1 0 0 2 0 0 3 0 0]"#;
    let four: Vec<PackedVec3> = (0..4).map(|i| v3(i as f32, 0.0, 0.0)).collect();
    let curve = |points, kind, width0, width1, normals| {
        Geometry::Curve(Arc::new(CurveDesc {
            points,
            basis: CurveBasis::Bezier,
            degree: 3,
            kind,
            width0,
            width1,
            normals,
            split_depth: 3,
        }))
    };
    let shapes = [
        (
            "Shape \"sphere\"\n  \"float radius\" -1".to_string(),
            "t.pbrt:2:3",
            Geometry::Sphere(SphereDesc {
                radius: -1.0,
                z_min: 1.0,
                z_max: -1.0,
                phi_max: 360.0,
            }),
        ),
        (
            "Shape \"cone\"\n  \"float height\" 0".into(),
            "t.pbrt:2:3",
            Geometry::Cone(ConeDesc {
                radius: 1.0,
                height: 0.0,
                phi_max: 360.0,
            }),
        ),
        (
            "Shape \"paraboloid\"\n  \"float zmax\" -1".into(),
            "t.pbrt:2:3",
            Geometry::Paraboloid(ParaboloidDesc {
                radius: 1.0,
                z_min: 0.0,
                z_max: -1.0,
                phi_max: 360.0,
            }),
        ),
        (
            // Both ends given: at the second.
            "Shape \"hyperboloid\" \"point3 p1\" [1 0 2]\n  \"point3 p2\" [0 1 2]".into(),
            "t.pbrt:2:3",
            Geometry::Hyperboloid(HyperboloidDesc {
                p1: Vec3::new(1.0, 0.0, 2.0),
                p2: Vec3::new(0.0, 1.0, 2.0),
                phi_max: 360.0,
            }),
        ),
        (
            // Only "min" given: at it.
            "Shape \"box\"\n  \"point3 min\" [0 0 1]".into(),
            "t.pbrt:2:3",
            Geometry::Box(BoxDesc {
                min: Vec3::new(0.0, 0.0, 1.0),
                max: Vec3::ONE,
            }),
        ),
        (
            "Shape \"plane\"\n  \"normal n\" [0 0 0]".into(),
            "t.pbrt:2:3",
            Geometry::Plane(PlaneDesc {
                p: Vec3::ZERO,
                n: Vec3::ZERO,
            }),
        ),
        // trianglemesh's inconsistent arrays are warnings, as in pbrt-v4 (trianglemesh.rs).
        (
            // A control mesh is checked before it is subdivided.
            "Shape \"loopsubdiv\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n  \"integer indices\" [0 1 5]"
                .into(),
            "t.pbrt:2:3",
            triangles(vec![0, 1, 5], vec![], vec![]),
        ),
        (
            "Shape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n  \"point2 uv\" [0 0]"
                .into(),
            "t.pbrt:2:3",
            Geometry::BilinearMesh(Arc::new(BilinearMesh {
                positions: vec![
                    v3(0.0, 0.0, 0.0),
                    v3(1.0, 0.0, 0.0),
                    v3(0.0, 1.0, 0.0),
                    v3(1.0, 1.0, 0.0),
                ],
                normals: vec![],
                uvs: vec![Vec2::ZERO],
                indices: vec![0, 1, 2, 3],
                flip_normal: false,
            })),
        ),
        (
            "Shape \"sdf\"\n  \"string expr\" \"plane([0, 1, 0], 0)\"".into(),
            "t.pbrt:2:3",
            Geometry::Sdf(SdfDesc {
                function: Arc::new(lancer::shape::SdfFunction::parse("plane([0, 1, 0], 0)").unwrap()),
                bounds: None,
            }),
        ),
        (
            // The box misses the sphere: at its "max".
            "Shape \"sdf\" \"string expr\" \"sphere(1)\" \"point3 min\" [5 5 5]\n  \"point3 max\" [6 6 6]"
                .into(),
            "t.pbrt:2:3",
            Geometry::Sdf(SdfDesc {
                function: Arc::new(lancer::shape::SdfFunction::parse("sphere(1)").unwrap()),
                bounds: Some((Vec3::splat(5.0), Vec3::splat(6.0))),
            }),
        ),
        (
            format!("{bezier}\n  \"float width0\" -1"),
            "t.pbrt:2:3",
            curve(four.clone(), CurveType::Flat, -1.0, 1.0, vec![]),
        ),
        (
            // Only "width" given: at it.
            format!("{bezier}\n  \"float width\" -2"),
            "t.pbrt:2:3",
            curve(four.clone(), CurveType::Flat, -2.0, -2.0, vec![]),
        ),
        (
            "Shape \"curve\"\n  \"point3 P\" [0 0 0 1 0 0 2 0 0 3 0 0 4 0 0]".into(),
            "t.pbrt:2:3",
            curve(
                [four.clone(), vec![v3(4.0, 0.0, 0.0)]].concat(),
                CurveType::Flat,
                1.0,
                1.0,
                vec![],
            ),
        ),
        (
            format!("{bezier} \"string type\" \"ribbon\"\n  \"normal N\" [0 0 1]"),
            "t.pbrt:2:3",
            curve(four.clone(), CurveType::Ribbon, 1.0, 1.0, vec![v3(0.0, 0.0, 1.0)]),
        ),
    ];
    for (text, at, g) in shapes {
        let rule = g.validate().expect_err(&text).message;
        assert_eq!(error(&text), format!("{at}: {rule}"), "{text}");
    }
    // Shapes that cannot be area lights: at the directive.
    let glowing =
        |text: &str| err(convert_full(text, Path::new("."), &TextureNames::default(), true).0);
    let sdf = Geometry::Sdf(SdfDesc {
        function: Arc::new(lancer::shape::SdfFunction::parse("sphere(1)").unwrap()),
        bounds: None,
    });
    let curve = geometry(r#"Shape "curve" "point3 P" [0 0 0 1 0 0 2 0 0 3 0 0]"#);
    let voxels = Geometry::Voxels(Arc::new(
        VoxelGrid::new([1, 1, 1], vec![1], linear_palette(&default_palette())).unwrap(),
    ));
    for (text, g) in [
        (r#"Shape "sdf" "string expr" "sphere(1)""#, sdf),
        (
            r#"Shape "curve" "point3 P" [0 0 0 1 0 0 2 0 0 3 0 0]"#,
            curve,
        ),
        (
            r#"Shape "voxels" "integer dims" [1 1 1] "integer indices" [1]"#,
            voxels,
        ),
    ] {
        let rule = glowing_desc(g).validate().expect_err(text).message;
        assert_eq!(glowing(text), format!("t.pbrt:1:1: {rule}"), "{text}");
    }
}
