//! Issue 5's mesh scene against pbrt-v4: `meshes/bunny.pbrt` (a `plymesh`) and the same scene
//! with the bunny read from `stanford-bunny.obj` through `objmesh` agree with pbrt-v4's
//! reference on channel means within 3 %. Needs the shared folder (the meshes are large);
//! skipped with a note without it.

mod common;
use common::*;

#[test]
fn bunny_as_plymesh_and_as_objmesh_agree_with_pbrt() {
    let Some(shared) = shared() else {
        println!("note: ../shared is absent; the bunny comparison is skipped");
        return;
    };
    let scene = shared.join("scenes/meshes/bunny.pbrt");
    let reference = read_exr(&shared.join("references/meshes/bunny.exr"));
    let dir = temp_dir("bunny");
    let text = std::fs::read_to_string(&scene).unwrap();
    let ply_line = "\"plymesh\" \"string filename\" \"bunny.ply\"";
    assert!(
        text.contains(ply_line),
        "the scene names its mesh as expected"
    );
    let obj = shared.join("scenes/meshes/stanford-bunny.obj");
    let obj_scene = dir.join("bunny-obj.pbrt");
    std::fs::write(
        &obj_scene,
        text.replace(
            ply_line,
            &format!("\"objmesh\" \"string filename\" \"{}\"", obj.display()),
        ),
    )
    .unwrap();
    for (name, s) in [("plymesh", scene), ("objmesh", obj_scene)] {
        let out = dir.join(format!("{name}.exr"));
        // 16 of the scene's 64 samples: the means are still within a fraction of a percent.
        render_ok(&dir, &s, &out, &["--spp", "16"]);
        // Noise at 16 spp bounds the pixel-wise error, not the means.
        compare(name, &read_exr(&out), &reference, 0.03, 0.8);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
