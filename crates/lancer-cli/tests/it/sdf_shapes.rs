//! `Shape "sdf"` from a scene file to an image: the team's shapes scene (whose last shape is a
//! signed-distance object) renders, and the SDF object is where it must be, in its colour.

use crate::common::*;

/// Mean colour of the pixels in the rectangle [x0, x1) × [y0, y1) (rows from the top).
fn mean(img: &Img, x0: usize, x1: usize, y0: usize, y1: usize) -> [f64; 3] {
    let mut s = [0.0; 3];
    for y in y0..y1 {
        for x in x0..x1 {
            let p = img.rgb[y * img.width + x];
            for c in 0..3 {
                s[c] += p[c];
            }
        }
    }
    s.map(|v| v / ((x1 - x0) * (y1 - y0)) as f64)
}

#[test]
fn shapes_scene_renders_its_sdf_object() {
    let Some(shared) = shared() else {
        println!("note: ../shared is absent; the shapes scene test is skipped");
        return;
    };
    let scene = shared.join("scenes/shapes/lancer-shapes.pbrt");
    let dir = ScratchDir::new("sdf-shapes");
    let out = dir.join("shapes.exr");
    render_ok(
        &dir,
        &scene,
        &out,
        &["--spp", "16", "--resolution", "280x160", "--seed", "1"],
    );
    let img = read_exr(&out);
    assert_eq!((img.width, img.height), (280, 160));
    // The blended sphere and torus (reflectance 0.8, 0.3, 0.6) at the right of the frame:
    // magenta, red and blue well above green. The sphere's lit body spans about x 225–255,
    // y 70–95 at this size.
    let body = mean(&img, 228, 250, 75, 90);
    assert!(
        body[0] > 1.8 * body[1] && body[2] > 1.3 * body[1],
        "sdf body colour {body:?}"
    );
    // Beyond it, on the right edge at the same height, only the grey floor.
    let floor = mean(&img, 270, 278, 75, 90);
    assert!(
        (floor[0] / floor[1] - 1.0).abs() < 0.15,
        "floor colour {floor:?}"
    );
}
