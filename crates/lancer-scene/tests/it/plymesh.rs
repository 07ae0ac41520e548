//! pbrt-v4's `Shape "plymesh"`: PLY files found next to the scene, their errors placed at the
//! Shape directive, and (when the shared scene folder is there) the real scenes that use them.

use crate::common::ScratchDir;
use lancer::scene::desc::{Geometry, SceneDesc};
use lancer::shape::TriangleMesh;
use lancer_scene::load;
use lancer_scene::ply::read_ply;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A binary little-endian PLY of `quads` unit squares side by side along x, each one quad.
fn quads_ply(quads: u32) -> Vec<u8> {
    let verts = 2 * (quads + 1);
    let mut d = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex {verts}\nproperty float x\n\
         property float y\nproperty float z\nelement face {quads}\n\
         property list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    for i in 0..=quads {
        for y in [0.0f32, 1.0] {
            for c in [i as f32, y, 0.0] {
                d.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    for q in 0..quads as i32 {
        d.push(4);
        for v in [2 * q, 2 * q + 2, 2 * q + 3, 2 * q + 1] {
            d.extend_from_slice(&v.to_le_bytes());
        }
    }
    d
}

/// Every triangle mesh of the scene, top-level and in object definitions.
fn meshes(d: &SceneDesc) -> Vec<&Arc<TriangleMesh>> {
    let objects = d.objects.iter().flat_map(|o| o.shapes.iter());
    d.shapes
        .iter()
        .chain(objects)
        .filter_map(|s| match &s.geometry {
            Geometry::TriangleMesh(m) => Some(m),
            _ => None,
        })
        .collect()
}

#[test]
fn plymesh_reads_the_file_beside_the_scene() {
    let dir = ScratchDir::new("load");
    std::fs::create_dir_all(dir.join("models")).unwrap();
    std::fs::write(dir.join("models/strip.ply"), quads_ply(3)).unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nAttributeBegin\nReverseOrientation\nTranslate 0 0 5\n\
         Shape \"plymesh\" \"string filename\" \"models/strip.ply\"\nAttributeEnd\n",
    )
    .unwrap();
    let loaded = load(&dir.join("scene.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.desc;
    assert_eq!(d.shapes.len(), 1);
    let s = &d.shapes[0];
    // Like a trianglemesh: object space in the mesh, orientation and transform on the shape.
    assert!(s.reverse_orientation);
    assert_eq!(
        s.object_to_world.point(lancer::math::Vec3::ZERO),
        lancer::math::Vec3::Z * 5.0
    );
    // Quads are bilinear patches, as pbrt-v4's: face (v₀, v₁, v₂, v₃) is (p₀₀, p₁₀, p₀₁, p₁₁)
    // = (v₀, v₁, v₃, v₂).
    let Geometry::BilinearMesh(m) = &s.geometry else {
        panic!("not a bilinear mesh: {:?}", s.geometry)
    };
    assert_eq!(m.patch_count(), 3);
    assert_eq!(m.positions.len(), 8);
    assert_eq!(&m.indices[..8], &[0, 2, 1, 3, 2, 4, 3, 5]);
    assert!(!m.flip_normal);
}

/// A PLY of triangles and quads makes two shapes under the same attributes, as pbrt-v4 makes
/// a triangle mesh and a bilinear patch mesh.
#[test]
fn plymesh_of_triangles_and_quads_makes_both() {
    let dir = ScratchDir::new("mixed");
    let ply = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
               property float z\nelement face 2\nproperty list uchar int vertex_indices\n\
               end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n3 1 4 2\n";
    std::fs::write(dir.join("mixed.ply"), ply).unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nMaterial \"conductor\"\nTranslate 0 0 5\n\
         Shape \"plymesh\" \"string filename\" \"mixed.ply\"\n",
    )
    .unwrap();
    let loaded = load(&dir.join("scene.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.desc;
    assert_eq!(d.shapes.len(), 2);
    let Geometry::TriangleMesh(t) = &d.shapes[0].geometry else {
        panic!("first the triangles: {:?}", d.shapes[0].geometry)
    };
    assert_eq!(t.indices, vec![1, 4, 2]);
    let Geometry::BilinearMesh(b) = &d.shapes[1].geometry else {
        panic!("then the patches: {:?}", d.shapes[1].geometry)
    };
    assert_eq!(b.indices, vec![0, 1, 3, 2]);
    assert_eq!(d.shapes[0].material, d.shapes[1].material);
    assert_eq!(d.shapes[0].object_to_world, d.shapes[1].object_to_world);
}

/// A plymesh of triangles and quads is one directive: under a transformation that flattens
/// space, its two geometries are flattened alike, with one warning about the normals dropped
/// (not one per geometry).
#[test]
fn a_flattened_plymesh_of_triangles_and_quads_warns_once() {
    let dir = ScratchDir::new("mixed-flat");
    let ply = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
               property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
               element face 2\nproperty list uchar int vertex_indices\nend_header\n\
               0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n2 0 0 0 0 1\n\
               4 0 1 2 3\n3 1 4 2\n";
    std::fs::write(dir.join("mixed.ply"), ply).unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nScale 1 1 0\nShape \"plymesh\" \"string filename\" \"mixed.ply\"\n",
    )
    .unwrap();
    let loaded = load(&dir.join("scene.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    let d = &loaded.desc;
    assert_eq!(d.shapes.len(), 2);
    assert!(matches!(d.shapes[0].geometry, Geometry::TriangleMesh(_)));
    assert!(matches!(d.shapes[1].geometry, Geometry::BilinearMesh(_)));
    let w: Vec<_> = loaded.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("normals \"N\" cannot follow it"), "{w:?}");
}

#[test]
fn plymesh_errors_are_placed_at_the_shape() {
    let dir = ScratchDir::new("errors");
    let mut bad = quads_ply(2);
    // The last index of the last face: 9000, with 6 vertices.
    let n = bad.len();
    bad[n - 4..].copy_from_slice(&9000i32.to_le_bytes());
    std::fs::write(dir.join("bad.ply"), bad).unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\n\n  Shape \"plymesh\" \"string filename\" \"bad.ply\"\n",
    )
    .unwrap();
    let e = load(&dir.join("scene.pbrt")).unwrap_err();
    let loc = e.location.clone().expect("placed");
    assert_eq!((loc.line, loc.col), (3, 3));
    assert!(
        e.message
            .ends_with("bad.ply: face 1 refers to vertex 9000 but there are 6 vertices"),
        "{e}"
    );
    assert_eq!(
        e.source_line.as_deref(),
        Some("  Shape \"plymesh\" \"string filename\" \"bad.ply\"")
    );

    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nShape \"plymesh\" \"string filename\" \"missing.ply\"\n",
    )
    .unwrap();
    let e = load(&dir.join("scene.pbrt")).unwrap_err();
    assert_eq!(e.location.map(|l| l.line), Some(2));
    assert!(
        e.message.contains("missing.ply: cannot read the file"),
        "{}",
        e.message
    );

    std::fs::write(dir.join("scene.pbrt"), "WorldBegin\nShape \"plymesh\"\n").unwrap();
    let e = load(&dir.join("scene.pbrt")).unwrap_err();
    assert_eq!(e.location.map(|l| l.line), Some(2));
    assert!(e.message.contains("\"string filename\""), "{}", e.message);
}

#[test]
fn displacement_needs_uvs_as_in_pbrt_v4_and_edgelength_alone_is_warned_about() {
    let dir = ScratchDir::new("displacement");
    std::fs::write(dir.join("q.ply"), quads_ply(1)).unwrap();
    let scene = |shape: &str| {
        std::fs::write(
            dir.join("scene.pbrt"),
            format!(
                "WorldBegin\nTexture \"bump\" \"float\" \"constant\" \"float value\" 0.1\n{shape}"
            ),
        )
        .unwrap();
        load(&dir.join("scene.pbrt"))
    };
    // pbrt-v4's `Displace` refuses a mesh without (u, v) too.
    let e = scene(
        "Shape \"plymesh\" \"string filename\" \"q.ply\" \"texture displacement\" \"bump\" \
         \"float edgelength\" 0.5\n",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(":3:") && e.contains("has no per-vertex (u, v), which displacement needs"),
        "{e}"
    );
    // Without a displacement the quad is a bilinear patch, and `edgelength` does nothing.
    let loaded =
        scene("Shape \"plymesh\" \"string filename\" \"q.ply\" \"float edgelength\" 0.5\n")
            .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(
        loaded.desc.shapes[0].geometry,
        Geometry::BilinearMesh(_)
    ));
    let w: Vec<_> = loaded.warnings.iter().map(|w| w.message.as_str()).collect();
    assert_eq!(
        w,
        ["\"edgelength\" only matters with \"displacement\"; ignored"]
    );
    assert_eq!(loaded.warnings[0].location.line, 3);
}

#[test]
fn a_ply_without_faces_is_skipped_with_a_warning() {
    let dir = ScratchDir::new("points");
    std::fs::write(
        dir.join("points.ply"),
        "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
         property float z\nend_header\n0 0 0\n1 1 1\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("scene.pbrt"),
        "WorldBegin\nShape \"plymesh\" \"string filename\" \"points.ply\"\n",
    )
    .unwrap();
    let loaded = load(&dir.join("scene.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.desc.shapes.is_empty());
    assert_eq!(loaded.warnings.len(), 1);
    assert!(loaded.warnings[0].message.contains("has no faces"));
}

/// The shared scene folder beside the worktree, if it is there.
fn shared() -> Option<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes");
    if dir.is_dir() {
        Some(dir)
    } else {
        println!("note: {} is absent; test skipped", dir.display());
        None
    }
}

#[test]
fn bitterli_coffee_loads_its_ply_meshes() {
    let Some(shared) = shared() else { return };
    let loaded =
        load(&shared.join("real/bitterli-coffee/scene-v4.pbrt")).unwrap_or_else(|e| panic!("{e}"));
    let with_triangles = meshes(&loaded.desc)
        .into_iter()
        .filter(|m| m.triangle_count() > 0)
        .count();
    // The scene has 20 plymesh shapes (Mesh000–Mesh019) and 3 trianglemesh shapes.
    assert_eq!(with_triangles, 23);
    let ply_warnings: Vec<_> = loaded
        .warnings
        .iter()
        .filter(|w| w.message.contains("plymesh") || w.message.contains(".ply"))
        .collect();
    assert!(ply_warnings.is_empty(), "{ply_warnings:?}");
}

#[test]
fn shared_ply_files_read_whole() {
    let Some(shared) = shared() else { return };
    // (file, vertices, triangles) as their headers say; igea is one triangle strip.
    for (file, vertices, triangles) in [
        ("meshes/bunny.ply", 35947, Some(69451)),
        ("meshes/bunny-dense.ply", 557164, Some(1111216)),
        ("real/stanford-bunny/bun_zipper.ply", 35947, Some(69451)),
        ("meshes/igea.ply", 134345, None),
    ] {
        let path = shared.join(file);
        let start = std::time::Instant::now();
        let m = read_ply(&path).unwrap_or_else(|e| panic!("{e}")).mesh;
        println!(
            "{file}: {} triangles in {:.3} s",
            m.triangle_count(),
            start.elapsed().as_secs_f64()
        );
        assert_eq!(m.positions.len(), vertices, "{file}");
        match triangles {
            Some(t) => assert_eq!(m.triangle_count(), t, "{file}"),
            // A closed surface has about twice as many triangles as vertices.
            None => assert!(m.triangle_count() > vertices, "{file}"),
        }
        assert!(m.positions.iter().all(|p| p.is_finite()));
    }
}
