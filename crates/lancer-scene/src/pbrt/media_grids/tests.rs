//! The four grid media from parameter lists as scenes write them, and their errors.

use super::*;
use crate::pbrt::parser::{Directive, Parser};
use std::path::Path;

/// Converts the first directive of `text` (a `MakeNamedMedium`), read from `dir`.
fn convert_in(text: &str, dir: &Path) -> Result<Option<GridMediumDesc>, SceneError> {
    let mut p = Parser::from_str(text, "m.pbrt", dir);
    let located = p.next_directive()?.expect("a directive");
    let Directive::MakeNamedMedium(_, params) = &located.directive else {
        panic!("not MakeNamedMedium")
    };
    let ty = params.string("type")?.unwrap_or_default();
    let scale = Transform::scale(Vec3::splat(0.5)).unwrap();
    grid_medium(params, &ty, scale, &located.dir, &located.loc)
}

fn convert(text: &str) -> Result<Option<GridMediumDesc>, SceneError> {
    convert_in(text, Path::new("."))
}

#[test]
fn uniformgrid_reads_density_and_coefficients() {
    let d = convert(
        "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [0 1 2 3]\n\
         \"integer nx\" 2 \"integer ny\" 2 \"point3 p0\" [-1 -1 -1] \"point3 p1\" [1 1 1]\n\
         \"spectrum sigma_a\" [400 0 800 0] \"spectrum sigma_s\" [400 1 800 1] \"float g\" 0.5",
    )
    .unwrap()
    .unwrap();
    let GridMediumDesc::Uniform(u) = d else {
        panic!("{d:?}")
    };
    assert_eq!(u.density.resolution(), [2, 2, 1]);
    assert_eq!(u.density.values(), [0.0, 1.0, 2.0, 3.0]);
    assert_eq!(u.bounds, Bounds3::new(Vec3::splat(-1.0), Vec3::ONE));
    assert_eq!(u.sigma_a, Rgb::ZERO);
    assert!(
        (u.sigma_s - Rgb::ONE).abs().max_element() < 1e-2,
        "{}",
        u.sigma_s
    );
    assert_eq!((u.g, u.scale), (0.5, 1.0));
    assert_eq!(u.le_scale.values(), [1.0]);
    assert!(u.temperature.is_none());
    assert_eq!(u.medium_to_render.point(Vec3::ONE), Vec3::splat(0.5));
}

#[test]
fn uniformgrid_temperature_and_lescale() {
    let d = convert(
        "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1 1]\n\
         \"integer nx\" 2 \"float temperature\" [1000 2000] \"float Lescale\" [2 3]\n\
         \"float temperaturecutoff\" 100 \"float temperaturescale\" 2",
    )
    .unwrap()
    .unwrap();
    let GridMediumDesc::Uniform(u) = d else {
        panic!()
    };
    assert_eq!(u.temperature.unwrap().values(), [1000.0, 2000.0]);
    assert_eq!(u.le_scale.values(), [2.0, 3.0]);
    assert_eq!((u.temperature_offset, u.temperature_scale), (100.0, 2.0));
}

#[test]
fn uniformgrid_errors_have_places() {
    let e = |t: &str| convert(t).unwrap_err().to_string();
    assert_eq!(
        e("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\""),
        "m.pbrt:1:1: no \"density\" value provided for grid medium"
    );
    assert_eq!(
        e(
            "MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1 2 3] \"integer nx\" 2"
        ),
        "m.pbrt:1:49: grid medium has 3 density values; expected nx·ny·nz = 2"
    );
    assert!(e("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1] \"integer nx\" 0")
        .starts_with("m.pbrt:1:69: \"integer nx\" must be at least 1"));
    assert!(e("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1] \"integer nx\" 100000 \"integer ny\" 100000")
        .contains("too large"));
    assert!(e("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1] \"float temperature\" [1] \"rgb Le\" [1 1 1]")
        .contains("both \"Le\" and \"temperature\""));
    assert!(e("MakeNamedMedium \"m\" \"string type\" \"uniformgrid\" \"float density\" [1 1] \"integer nx\" 2 \"float Lescale\" [1 2 3]")
        .contains("\"Lescale\""));
}

#[test]
fn rgbgrid_reads_colour_grids() {
    let d = convert(
        "MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"integer nx\" 2\n\
         \"rgb sigma_a\" [0 0 0 0.125 0 0] \"rgb sigma_s\" [1 1 1 1 1 1] \"float scale\" 4",
    )
    .unwrap()
    .unwrap();
    let GridMediumDesc::Rgb(g) = d else { panic!() };
    assert_eq!(
        g.sigma_a.unwrap().values(),
        [Rgb::ZERO, Rgb::new(0.125, 0.0, 0.0)]
    );
    assert_eq!(g.sigma_s.unwrap().resolution(), [2, 1, 1]);
    assert!(g.le.is_none());
    assert_eq!((g.scale, g.le_scale), (4.0, 1.0));
}

#[test]
fn rgbgrid_errors_have_places() {
    let e = |t: &str| convert(t).unwrap_err().to_string();
    assert_eq!(
        e("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\""),
        "m.pbrt:1:1: RGB grid requires \"sigma_a\" and/or \"sigma_s\" parameter values"
    );
    assert_eq!(
        e("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb sigma_a\" [1 1 1 2 2 2]"),
        "m.pbrt:1:45: RGB grid medium has 2 density values; expected nx·ny·nz = 1"
    );
    assert!(e("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb sigma_s\" [1 1 1] \"rgb Le\" [1 1 1]")
        .contains("requires \"sigma_a\" if \"Le\""));
    assert!(e("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [1 1 1 2 2 2]")
        .contains("different number of samples (1 vs 2)"));
    // Not whole triples: refused when read.
    assert!(
        e("MakeNamedMedium \"m\" \"string type\" \"rgbgrid\" \"rgb sigma_a\" [1 1 1 2]")
            .contains("triples")
    );
}

#[test]
fn cloud_defaults_as_pbrt() {
    let d = convert("MakeNamedMedium \"m\" \"string type\" \"cloud\" \"float density\" 10 \"point3 p0\" [-1 -1 -1]")
        .unwrap()
        .unwrap();
    let GridMediumDesc::Cloud(c) = d else {
        panic!()
    };
    assert_eq!(
        (c.density, c.wispiness, c.frequency, c.g),
        (10.0, 1.0, 5.0, 0.0)
    );
    assert_eq!(c.bounds, Bounds3::new(Vec3::splat(-1.0), Vec3::ONE));
    assert_eq!((c.sigma_a, c.sigma_s), (Rgb::ONE, Rgb::ONE));
}

#[test]
fn other_types_are_not_grids() {
    assert_eq!(
        convert("MakeNamedMedium \"m\" \"string type\" \"homogeneous\"").unwrap(),
        None
    );
}

#[test]
fn nanovdb_reads_the_named_grids() {
    let dir = std::env::temp_dir().join(format!("lancer-media-grids-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let leaf: [f32; 512] = std::array::from_fn(|n| n as f32);
    let f =
        crate::nanovdb::tests::write_v19("density", &[([0, 0, 0], leaf)], ([8, 8, 8], 2.0), true);
    std::fs::write(dir.join("g.nvdb"), f).unwrap();
    let d = convert_in(
        "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"g.nvdb\" \"rgb sigma_s\" [0.9 1.2 1.5]",
        &dir,
    )
    .unwrap()
    .unwrap();
    let GridMediumDesc::NanoVdb(n) = d else {
        panic!()
    };
    // The description holds the grid as read (voxel (1, 2, 3) of the leaf at the origin is
    // sample 1·64 + 2·8 + 3); the scene build makes it ready for lookups.
    let parts = n.density.parts();
    assert_eq!(parts.leaf_origins, [[0, 0, 0]]);
    assert_eq!(parts.leaf_values[64 + 2 * 8 + 3], 83.0);
    let grid = lancer::medium::vdb::VdbGrid::new(n.density.clone());
    assert_eq!(grid.value(1, 2, 3), 83.0);
    assert!(n.temperature.is_none());
    assert_eq!(n.sigma_s, Rgb::new(0.9, 1.2, 1.5));
    let e = convert_in(
        "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"g.nvdb\" \"string gridname\" \"smoke\"",
        &dir,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.starts_with("m.pbrt:1:45: ") && e.ends_with("didn't find \"smoke\" grid"),
        "{e}"
    );
    let e = convert_in(
        "MakeNamedMedium \"m\" \"string type\" \"nanovdb\" \"string filename\" \"nope.nvdb\"",
        &dir,
    )
    .unwrap_err()
    .to_string();
    assert!(e.starts_with("m.pbrt:1:45: cannot read"), "{e}");
    assert_eq!(
        convert("MakeNamedMedium \"m\" \"string type\" \"nanovdb\"")
            .unwrap_err()
            .to_string(),
        "m.pbrt:1:1: must supply \"filename\" to \"nanovdb\" medium"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The Houdini test scenes' media convert (their grids, as pbrt-v4 reads them).
#[test]
fn houdini_scenes_media_convert() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/scenes/real/houdini-media-tests/tests/scenes");
    for (file, kind) in [
        ("TestShapes/test_volume.pbrt", "uniformgrid"),
        ("TestShapes/test_volume_sigma.pbrt", "rgbgrid"),
        ("TestMediums/test_interior_cloud.pbrt", "cloud"),
        ("TestMediums/test_interior_nanovdb.pbrt", "nanovdb"),
    ] {
        let path = root.join(file);
        let Ok(mut p) = Parser::from_file(&path) else {
            eprintln!("skipped: {} not found", path.display());
            continue;
        };
        let mut found = false;
        while let Some(l) = p.next_directive().unwrap() {
            if let Directive::MakeNamedMedium(_, params) = &l.directive {
                let ty = params.string("type").unwrap().unwrap();
                let d = grid_medium(params, &ty, Transform::IDENTITY, &l.dir, &l.loc)
                    .unwrap()
                    .unwrap();
                assert_eq!(d.kind(), kind);
                if let GridMediumDesc::Rgb(g) = &d {
                    assert_eq!(g.sigma_a.as_ref().unwrap().resolution(), [8, 8, 8]);
                }
                found = true;
            }
        }
        assert!(found, "{file}");
    }
}
