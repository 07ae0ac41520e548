//! The course's scenes rendered by `lancer render` agree with pbrt-v4's renders, and the same
//! scene and seed give the same bytes whatever the thread count.

use crate::common::*;

/// Each course scene at 64 spp against pbrt-v4 (references shrunk 4× for the repository): the
/// channel means within 2 %, the pixels within an RMSE of 5 % of the mean after the same 4×
/// box filter (which averages most of the noise away; a misplaced object or shadow fails).
#[test]
fn course_scenes_agree_with_pbrt() {
    let dir = ScratchDir::new("course");
    for name in [
        "01-sphere",
        "02-plane",
        "03-objects",
        "04-shadows",
        "05-lights",
    ] {
        let scene = data(&format!("course/{name}.pbrt"));
        let out = dir.join(format!("{name}.exr"));
        render_ok(&dir, &scene, &out, &["--spp", "64"]);
        let img = read_exr(&out).shrink(4);
        let reference = read_exr(&data(&format!("references/course/{name}.exr")));
        compare(name, &img, &reference, 0.02, 0.05);
    }
}

#[test]
fn thread_count_does_not_change_a_single_byte() {
    let dir = ScratchDir::new("threads");
    let scene = data("course/04-shadows.pbrt");
    let mut outputs = Vec::new();
    for threads in ["1", "2", "3"] {
        for ext in ["exr", "png"] {
            let out = dir.join(format!("t{threads}.{ext}"));
            render_ok(
                &dir,
                &scene,
                &out,
                &["--spp", "4", "--seed", "3", "--threads", threads],
            );
            outputs.push((ext, std::fs::read(&out).unwrap()));
        }
    }
    for ext in ["exr", "png"] {
        let files: Vec<_> = outputs
            .iter()
            .filter(|(e, _)| *e == ext)
            .map(|(_, b)| b)
            .collect();
        assert!(
            files.windows(2).all(|w| w[0] == w[1]),
            "{ext} outputs differ between thread counts"
        );
    }
}

#[test]
fn default_scene_renders_a_sensible_png() {
    let dir = ScratchDir::new("default");
    let o = run_in(&dir, &["render", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let png =
        std::fs::read(dir.join("lancer.png")).expect("lancer.png written in the working folder");
    assert_eq!(&png[1..4], b"PNG");
    // Not black, not blown out: check the EXR of the same scene.
    let o = run_in(
        &dir,
        &[
            "render",
            "--quiet",
            "-o",
            "d.exr",
            "--resolution",
            "160x100",
            "--spp",
            "4",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m = read_exr(&dir.join("d.exr")).means();
    assert!(
        m.iter().all(|&v| v > 0.05 && v < 1.0),
        "default scene means {m:?}"
    );
}
