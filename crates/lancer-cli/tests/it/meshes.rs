//! Issue 5's mesh scene against pbrt-v4: `meshes/bunny.pbrt` (a `plymesh`) and the same scene
//! with the bunny read from `stanford-bunny.obj` through `objmesh` agree with pbrt-v4's
//! reference on channel means within 3 %. Needs the shared folder (the meshes are large);
//! skipped with a note without it.

use crate::common::*;

#[test]
fn bunny_as_plymesh_and_as_objmesh_agree_with_pbrt() {
    let Some(shared) = shared() else {
        println!("note: ../shared is absent; the bunny comparison is skipped");
        return;
    };
    let scene = shared.join("scenes/meshes/bunny.pbrt");
    let reference = read_exr(&shared.join("references/meshes/bunny.exr"));
    let dir = ScratchDir::new("bunny");
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
        // Means within 3 %. Pixel by pixel, noise at 16 spp hides the picture (a flat grey at
        // the reference's means scores better than a right render), so shapes are compared on
        // 10 × 10 blocks: a right render scores about 0.05 there, a flat grey 0.34.
        compare(
            name,
            &read_exr(&out).shrink(10),
            &reference.shrink(10),
            0.03,
            0.1,
        );
    }
}
