//! pbrt-v4's `Shape "objmesh"`: OBJ files found next to the scene, merged into one mesh, their
//! errors placed at the Shape directive.

use crate::common::ScratchDir;
use lancer::scene::desc::Geometry;
use lancer_scene::load;

/// A unit quad in two groups with two materials, and a triangle using negative indices.
const TWO_GROUPS: &str = "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
    vn 0 0 1\ng a\nusemtl red\nf 1//1 2//1 3//1 4//1\ng b\nusemtl blue\n\
    v 0 0 1\nv 1 0 1\nv 0 1 1\nf -3//1 -2//1 -1//1\n";

#[test]
fn objmesh_reads_the_file_beside_the_scene_as_one_mesh() {
    let dir = ScratchDir::new("load");
    std::fs::create_dir_all(dir.join("models")).unwrap();
    std::fs::write(dir.join("models/two.obj"), TWO_GROUPS).unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nAttributeBegin\nTranslate 0 0 5\n\
         Shape \"objmesh\" \"string filename\" \"models/two.obj\"\nAttributeEnd\n",
    )
    .unwrap();
    let loaded = load(&dir.join("scene.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.desc;
    assert_eq!(d.shapes.len(), 1, "groups and materials merged");
    let s = &d.shapes[0];
    assert_eq!(
        s.object_to_world.point(lancer::math::Vec3::ZERO),
        lancer::math::Vec3::Z * 5.0
    );
    let Geometry::TriangleMesh(m) = &s.geometry else {
        panic!("not a triangle mesh: {:?}", s.geometry)
    };
    assert_eq!(m.triangle_count(), 3);
    assert_eq!(m.positions.len(), 7);
    assert_eq!(m.normals.len(), 7);
    assert_eq!(
        m.positions[m.indices[6] as usize],
        glam::Vec3::new(0.0, 0.0, 1.0)
    );
    assert!(m.validate().is_ok());
}

#[test]
fn objmesh_errors_are_placed_at_the_shape() {
    let dir = ScratchDir::new("errors");
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\n\n  Shape \"objmesh\" \"string filename\" \"bad.obj\"\n",
    )
    .unwrap();
    let e = load(&dir.join("scene.pbrt")).unwrap_err();
    let loc = e.location.clone().expect("placed");
    assert_eq!((loc.line, loc.col), (3, 3));
    assert!(
        e.message
            .contains("bad.obj:4: position index 7 is out of range"),
        "{e}"
    );
    assert_eq!(
        e.source_line.as_deref(),
        Some("  Shape \"objmesh\" \"string filename\" \"bad.obj\"")
    );

    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nShape \"objmesh\" \"string filename\" \"missing.obj\"\n",
    )
    .unwrap();
    let e = load(&dir.join("scene.pbrt")).unwrap_err();
    assert_eq!(e.location.map(|l| l.line), Some(2));
    assert!(
        e.message.contains("missing.obj: cannot read the file"),
        "{}",
        e.message
    );

    std::fs::write(dir.join("scene.pbrt"), "WorldBegin\nShape \"objmesh\"\n").unwrap();
    let e = load(&dir.join("scene.pbrt")).unwrap_err();
    assert_eq!(e.location.map(|l| l.line), Some(2));
    assert!(e.message.contains("string filename"), "{}", e.message);

    std::fs::write(dir.join("empty.obj"), "v 0 0 0\n").unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nShape \"objmesh\" \"string filename\" \"empty.obj\"\n",
    )
    .unwrap();
    let loaded = load(&dir.join("scene.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.desc.shapes.is_empty());
    assert!(loaded.warnings[0].message.contains("has no faces"));
}
