//! A `plymesh` with `"texture displacement"`: refined by `edgelength` ×
//! `--displacement-edge-scale` in render space, moved along its normals, its triangles
//! counted in a note; an absurd edge length refused at its place.

use crate::common::ScratchDir;
use lancer::scene::desc::Geometry;
use lancer::shape::TriangleMesh;
use lancer_scene::{LoadOptions, LoadedScene, load_pbrt_str_with};
use std::sync::Arc;

/// The unit square [0, 1]² at z = 0 as one quad (two triangles when displaced), normals +z,
/// (u, v) = (x, y).
const SQUARE_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n\
property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
property float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\n\
end_header\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n";

fn scene(dir: &ScratchDir, body: &str, options: &LoadOptions) -> Result<LoadedScene, String> {
    std::fs::write(dir.join("square.ply"), SQUARE_PLY).unwrap();
    let text = format!("LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n{body}");
    load_pbrt_str_with(&text, "d.pbrt", dir, options).map_err(|e| e.to_string())
}

fn mesh(l: &LoadedScene) -> Arc<TriangleMesh> {
    match &l.desc.shapes[0].geometry {
        Geometry::TriangleMesh(m) => m.clone(),
        g => panic!("{g:?}"),
    }
}

fn longest_edge(m: &TriangleMesh) -> f32 {
    m.indices
        .chunks_exact(3)
        .flat_map(|t| (0..3).map(move |k| (t[k], t[(k + 1) % 3])))
        .map(|(a, b)| (m.position(a as usize) - m.position(b as usize)).length())
        .fold(0.0, f32::max)
}

#[test]
fn a_displaced_plymesh_is_refined_in_render_space_and_moved_along_its_normals() {
    let dir = ScratchDir::new("displaced");
    let body = "Texture \"h\" \"float\" \"constant\" \"float value\" 0.25\n\
                Scale 2 2 2\n\
                Shape \"plymesh\" \"string filename\" \"square.ply\" \"texture displacement\" \"h\" \"float edgelength\" 0.1\n";
    let l = scene(&dir, body, &LoadOptions::default()).unwrap();
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    let m = mesh(&l);
    // Edges under 0.1 in render space are under 0.05 in object space, the scale being 2.
    assert!(longest_edge(&m) < 0.05, "{}", longest_edge(&m));
    assert!(m.face_count() > 2 * 20 * 20, "{}", m.face_count());
    // Every vertex moved by 0.25 along +z; the normals, recomputed, are still +z.
    assert!(m.positions.iter().all(|p| p.z == 0.25));
    assert!(m.normals.iter().all(|n| (n.z - 1.0).abs() < 1e-6));
    assert_eq!(l.notes.len(), 1);
    let note = l.notes[0].to_string();
    assert!(
        note.starts_with("d.pbrt:6:1: ")
            && note.contains(&format!("2 triangles refined to {}", m.face_count())),
        "{note}"
    );
    // --displacement-edge-scale 2: edges under 0.2, about a quarter of the triangles.
    let coarse = LoadOptions {
        displacement_edge_scale: 2.0,
        ..LoadOptions::default()
    };
    let c = mesh(&scene(&dir, body, &coarse).unwrap());
    assert!(longest_edge(&c) < 0.1 && longest_edge(&c) >= 0.05 / 4.0);
    let ratio = m.face_count() as f64 / c.face_count() as f64;
    assert!((3.0..5.0).contains(&ratio), "{ratio}");
}

#[test]
fn a_3d_displacement_texture_sees_the_object_point_from_pbrt_v4s_render_space() {
    // pbrt-v4 looks the texture up at the object-space point as if it were in render space,
    // whose origin is the camera: a 3D checkerboard (unit cells, tex1 where ⌊x⌋ + ⌊y⌋ + ⌊z⌋
    // is even) on a square inside one cell sees the cell the camera's position moves it to.
    let dir = ScratchDir::new("displaced-3d");
    let small = SQUARE_PLY
        .replace("\n0 0 0 ", "\n0.25 0.25 0 ")
        .replace("\n1 0 0 ", "\n0.75 0.25 0 ")
        .replace("\n1 1 0 ", "\n0.75 0.75 0 ")
        .replace("\n0 1 0 ", "\n0.25 0.75 0 ");
    std::fs::write(dir.join("small.ply"), small).unwrap();
    let shape = "Texture \"c\" \"float\" \"checkerboard\" \"integer dimension\" 3 \
                 \"float tex1\" 0.1 \"float tex2\" 0.3\n\
                 Shape \"plymesh\" \"string filename\" \"small.ply\" \"texture displacement\" \"c\"\n";
    // Camera at (0, 0, 5): cell (0, 0, 5), odd; at (1, 0, 5): cell (1, 0, 5), even.
    for (eye, want) in [(0.0, 0.3), (1.0, 0.1)] {
        let text = format!(
            "LookAt {eye} 0 5  {eye} 0 0  0 1 0\nCamera \"perspective\"\nWorldBegin\n{shape}"
        );
        let l = load_pbrt_str_with(&text, "c.pbrt", &dir, &LoadOptions::default()).unwrap();
        let m = mesh(&l);
        assert_eq!(m.positions.len(), 4);
        assert!(
            m.positions.iter().all(|p| p.z == want),
            "camera at x = {eye}: {:?}",
            m.positions.iter().map(|p| p.z).collect::<Vec<_>>()
        );
    }
}

#[test]
fn too_many_triangles_is_an_error_at_the_edge_length_naming_the_option() {
    let dir = ScratchDir::new("displaced-absurd");
    let body = "Texture \"h\" \"float\" \"constant\" \"float value\" 0\n\
                Shape \"plymesh\" \"string filename\" \"square.ply\" \"texture displacement\" \"h\" \"float edgelength\" 1e-7\n";
    let e = scene(&dir, body, &LoadOptions::default()).unwrap_err();
    assert!(e.starts_with("d.pbrt:5:75: displacing"), "{e}");
    assert!(
        e.contains("at least") && e.contains("--max-displaced-triangles raises that limit"),
        "{e}"
    );
    // The limit is on the scene's displaced meshes in all: two meshes of 2 × 4 triangles
    // (edge length 0.8) pass a limit of 16, a third does not.
    let body = "Texture \"h\" \"float\" \"constant\" \"float value\" 0\n\
                Shape \"plymesh\" \"string filename\" \"square.ply\" \"texture displacement\" \"h\" \"float edgelength\" 0.8\n";
    let small = LoadOptions {
        max_displaced_triangles: 16,
        ..LoadOptions::default()
    };
    let two = format!("{body}{body}");
    let l = scene(&dir, &two, &small).unwrap();
    assert_eq!(mesh(&l).face_count(), 8);
    let e = scene(&dir, &format!("{two}{body}"), &small).unwrap_err();
    assert!(
        e.contains("(16 of them made by the displaced meshes before it)"),
        "{e}"
    );
}

#[test]
fn each_displaced_mesh_sees_the_textures_defined_before_it() {
    // The textures are built once for the scene's displaced meshes and extended as the file
    // defines more: the second mesh's "h", defined again after the first mesh, is the new one.
    let dir = ScratchDir::new("displaced-two");
    let shape = "Shape \"plymesh\" \"string filename\" \"square.ply\" \"texture displacement\" \"h\" \"float edgelength\" 2\n";
    let body = format!(
        "Texture \"h\" \"float\" \"constant\" \"float value\" 0.25\n{shape}\
         Texture \"h\" \"float\" \"constant\" \"float value\" 0.5\n{shape}"
    );
    let l = scene(&dir, &body, &LoadOptions::default()).unwrap();
    let z = |i: usize| match &l.desc.shapes[i].geometry {
        Geometry::TriangleMesh(m) => m.positions.iter().map(|p| p.z).collect::<Vec<_>>(),
        g => panic!("{g:?}"),
    };
    assert_eq!((z(0), z(1)), (vec![0.25; 4], vec![0.5; 4]));
}
