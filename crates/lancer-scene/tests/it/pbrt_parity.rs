//! Reader parity with pbrt-v4, checked on the `SceneDesc` a scene builds: gzip-compressed
//! scenes, `Import` (a copy of the graphics state that does not flow back), parameters given
//! twice, singular transformations and inconsistent `trianglemesh` arrays.

use crate::common::ScratchDir;
use lancer::material::DiffuseMaterial;
use lancer::material::MaterialDesc;
use lancer::math::Vec3;
use lancer::scene::desc::{Geometry, SceneDesc};
use lancer::shape::SphereDesc;
use lancer::texture::SpectrumTex;
use lancer_scene::{LoadedScene, load, load_pbrt_str};
use std::io::Write;
use std::path::Path;

fn loaded(text: &str) -> LoadedScene {
    load_pbrt_str(text, "t.pbrt", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

fn warnings(l: &LoadedScene) -> Vec<String> {
    l.warnings.iter().map(|w| w.to_string()).collect()
}

fn error_in(dir: &Path, main: &str) -> String {
    load(&dir.join(main)).unwrap_err().to_string()
}

fn gzip(text: &str) -> Vec<u8> {
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(text.as_bytes()).unwrap();
    enc.finish().unwrap()
}

fn diffuse_red(d: &SceneDesc, material: u32) -> f32 {
    match &d.materials[material as usize] {
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: SpectrumTex::Const(c),
        }) => c.x,
        other => panic!("not diffuse: {other:?}"),
    }
}

#[test]
fn a_gzip_compressed_scene_file_is_read() {
    let dir = ScratchDir::new("gz-scene");
    let path = dir.join("s.pbrt.gz");
    std::fs::write(
        &path,
        gzip("WorldBegin\nShape \"sphere\" \"float radius\" 2\n"),
    )
    .unwrap();
    let l = load(&path).unwrap();
    assert!(matches!(
        l.desc.shapes[0].geometry,
        Geometry::Sphere(SphereDesc { radius: 2.0, .. })
    ));
    assert_eq!(l.files, [std::fs::canonicalize(&path).unwrap()]);
}

#[test]
fn an_import_starts_from_the_graphics_state_and_does_not_change_it() {
    let dir = ScratchDir::new("import");
    std::fs::write(
        dir.join("geom.pbrt"),
        "Shape \"sphere\"\nMakeNamedMaterial \"gold\" \"string type\" \"conductor\"\n\
         Material \"diffuse\" \"rgb reflectance\" [0.9 0 0.9]\nTranslate 0 1 0\n\
         ReverseOrientation\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("main.pbrt"),
        "WorldBegin\nAttributeBegin\n  Translate 5 0 0\n  \
         Material \"diffuse\" \"rgb reflectance\" [0.2 0.3 0.8]\n  Import \"geom.pbrt\"\n  \
         Shape \"sphere\"\n  NamedMaterial \"gold\"\n  Shape \"disk\"\nAttributeEnd\n",
    )
    .unwrap();
    let d = load(&dir.join("main.pbrt")).unwrap().desc;
    assert_eq!(d.shapes.len(), 3);
    // The imported sphere and the one after the Import share the parent's CTM and material.
    for s in &d.shapes[..2] {
        assert_eq!(
            s.object_to_world.point(Vec3::ZERO),
            Vec3::new(5.0, 0.0, 0.0)
        );
        assert!(!s.reverse_orientation);
        assert_eq!(diffuse_red(&d, s.material), 0.2);
    }
    // Named materials are the scene's: defined in the import, usable after it.
    assert!(matches!(
        d.materials[d.shapes[2].material as usize],
        MaterialDesc::Conductor(_)
    ));
}

#[test]
fn import_errors_are_located() {
    let dir = ScratchDir::new("import-errors");
    std::fs::write(
        dir.join("open.pbrt"),
        "Shape \"sphere\"\n  AttributeBegin\n",
    )
    .unwrap();
    std::fs::write(dir.join("a.pbrt"), "WorldBegin\nImport \"open.pbrt\"\n").unwrap();
    let e = error_in(&dir, "a.pbrt");
    assert!(
        e.ends_with(
            "open.pbrt:2:3: this AttributeBegin is never closed: the imported file ends first"
        ),
        "{e}"
    );
    std::fs::write(dir.join("close.pbrt"), "AttributeEnd\n").unwrap();
    std::fs::write(
        dir.join("b.pbrt"),
        "WorldBegin\nAttributeBegin\nImport \"close.pbrt\"\nAttributeEnd\n",
    )
    .unwrap();
    let e = error_in(&dir, "b.pbrt");
    assert!(
        e.ends_with("close.pbrt:1:1: AttributeEnd closes the Import at line 3"),
        "{e}"
    );
    std::fs::write(dir.join("c.pbrt"), "Import \"close.pbrt\"\nWorldBegin\n").unwrap();
    let e = error_in(&dir, "c.pbrt");
    assert!(
        e.ends_with("c.pbrt:1:1: Import is only allowed after WorldBegin"),
        "{e}"
    );
}

#[test]
fn the_last_of_duplicate_parameters_and_attributes_counts() {
    let l = loaded(
        "WorldBegin\nAttribute \"shape\" \"float radius\" 3\nAttribute \"shape\" \"float radius\" 4\n\
         Shape \"sphere\"\nShape \"sphere\" \"float radius\" 0.25 \"float radius\" 0.5\n",
    );
    assert!(matches!(
        l.desc.shapes[0].geometry,
        Geometry::Sphere(SphereDesc { radius: 4.0, .. })
    ));
    assert!(matches!(
        l.desc.shapes[1].geometry,
        Geometry::Sphere(SphereDesc { radius: 0.5, .. })
    ));
    assert_eq!(
        warnings(&l),
        [
            "t.pbrt:5:16: parameter \"float radius\" of Shape \"sphere\" is given again at 5:36; \
          this earlier value is ignored (as pbrt-v4, the last one counts)"
        ]
    );
}

#[test]
fn a_mesh_under_a_singular_transformation_collapses_onto_a_plane() {
    // The x column is zero: every point lands on the plane x = 1 (the translation).
    let l = loaded(
        "WorldBegin\nTranslate 1 0 0\nConcatTransform [0 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1]\n\
         Translate 7 0 0\n\
         Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 1] \"normal N\" [1 0 0 1 0 0 1 0 0]\n\
         Shape \"sphere\"\nLightSource \"point\"\nShape \"bilinearmesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0]\n",
    );
    let d = &l.desc;
    assert_eq!(d.shapes.len(), 2);
    assert!(d.lights.is_empty());
    let Geometry::TriangleMesh(m) = &d.shapes[0].geometry else {
        panic!("a mesh")
    };
    assert!(d.shapes[0].object_to_world.is_identity());
    let p: Vec<Vec3> = m.positions.iter().map(|&p| Vec3::from(p)).collect();
    assert_eq!(
        p,
        [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 1.0)
        ]
    );
    assert!(m.normals.is_empty());
    let Geometry::BilinearMesh(b) = &d.shapes[1].geometry else {
        panic!("a bilinear mesh")
    };
    assert!(b.positions.iter().all(|&p| Vec3::from(p).x == 1.0));
    let w = warnings(&l);
    assert_eq!(w.len(), 3, "{w:?}");
    assert!(
        w[0].starts_with("t.pbrt:5:1: the transformation is singular"),
        "{}",
        w[0]
    );
    assert_eq!(
        w[1],
        "t.pbrt:6:1: Shape \"sphere\" is under a singular transformation (it flattens space), \
         which cannot place it; skipped"
    );
    assert!(
        w[2].starts_with("t.pbrt:7:1: LightSource \"point\" is under"),
        "{}",
        w[2]
    );
    // Scale 0 is singular too; a block restores an invertible CTM.
    let l = loaded(
        "WorldBegin\nAttributeBegin\nScale 1 0 1\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]\n\
         AttributeEnd\nShape \"sphere\"\n",
    );
    assert!(l.warnings.is_empty());
    assert!(matches!(l.desc.shapes[1].geometry, Geometry::Sphere(_)));
    let e = load_pbrt_str(
        "Scale 0 1 1\nCamera \"perspective\"\nWorldBegin\n",
        "t.pbrt",
        Path::new("."),
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.pbrt:2:1: the camera's transformation is singular (it flattens space)"
    );
}
