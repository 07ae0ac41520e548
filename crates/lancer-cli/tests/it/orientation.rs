//! The image is oriented exactly as pbrt-v4 orients it: with `LookAt` towards −z, world +x is
//! on the image's left (pbrt's camera space is left-handed) and +y at the top; a
//! `Scale -1 1 1` before `LookAt` (as Blender exports write) puts +x on the right, as the
//! camera lancer makes for a bare mesh file does.

use crate::common::*;

/// Renders a red sphere at world +x and a blue one at world +y, seen from +z, and returns the
/// image.
fn render(dir: &std::path::Path, name: &str, pre_camera: &str) -> Img {
    let scene = format!(
        r#"{pre_camera}
LookAt 0 0 6  0 0 0  0 1 0
Camera "perspective" "float fov" [50]
Film "rgb" "integer xresolution" [48] "integer yresolution" [32] "string filename" "{name}.exr"
Sampler "independent" "integer pixelsamples" [4]
Integrator "whitted"
WorldBegin
LightSource "distant" "point3 from" [0 0 10] "point3 to" [0 0 0] "rgb L" [3 3 3]
AttributeBegin
  Material "diffuse" "rgb reflectance" [0.8 0 0]
  Translate 1.5 0 0
  Shape "sphere" "float radius" [0.6]
AttributeEnd
AttributeBegin
  Material "diffuse" "rgb reflectance" [0 0 0.8]
  Translate 0 1.2 0
  Shape "sphere" "float radius" [0.4]
AttributeEnd
"#
    );
    let file = dir.join(format!("{name}.pbrt"));
    std::fs::write(&file, scene).unwrap();
    let out = dir.join(format!("{name}.exr"));
    // In RGB: a pure red or blue stays exactly zero in the other channels, which the
    // assertions rely on (a spectral render spreads a little into them).
    render_ok(dir, &file, &out, &["--rgb"]);
    read_exr(&out)
}

/// Sum of channel `c` over the pixels with `keep(x, y)`.
fn sum(img: &Img, c: usize, keep: impl Fn(usize, usize) -> bool) -> f64 {
    let mut s = 0.0;
    for y in 0..img.height {
        for x in 0..img.width {
            if keep(x, y) {
                s += img.rgb[y * img.width + x][c];
            }
        }
    }
    s
}

#[test]
fn world_x_is_on_the_left_and_y_on_top_as_in_pbrt() {
    let dir = ScratchDir::new("orientation");
    let img = render(&dir, "pbrt", "");
    let w = img.width;
    let (red_left, red_right) = (
        sum(&img, 0, |x, _| x < w / 2),
        sum(&img, 0, |x, _| x >= w / 2),
    );
    assert!(
        red_left > 1.0 && red_right == 0.0,
        "red: left {red_left}, right {red_right}"
    );
    let h = img.height;
    let (blue_top, blue_bottom) = (
        sum(&img, 2, |_, y| y < h / 2),
        sum(&img, 2, |_, y| y >= h / 2),
    );
    assert!(
        blue_top > 1.0 && blue_bottom == 0.0,
        "blue: top {blue_top}, bottom {blue_bottom}"
    );

    let img = render(&dir, "mirrored", "Scale -1 1 1");
    let (red_left, red_right) = (
        sum(&img, 0, |x, _| x < w / 2),
        sum(&img, 0, |x, _| x >= w / 2),
    );
    assert!(
        red_right > 1.0 && red_left == 0.0,
        "mirrored red: left {red_left}, right {red_right}"
    );
    let blue_top = sum(&img, 2, |_, y| y < h / 2);
    assert!(blue_top > 1.0, "mirrored blue stays on top");
}

/// A quad of side `s` centred at (x, y, 0), facing +z, as OBJ lines (vertices counted back).
fn quad(x: f32, y: f32, s: f32, material: &str) -> String {
    let h = s / 2.0;
    format!(
        "usemtl {material}\nv {} {} 0\nv {} {} 0\nv {} {} 0\nv {} {} 0\nf -4 -3 -2 -1\n",
        x - h,
        y - h,
        x + h,
        y - h,
        x + h,
        y + h,
        x - h,
        y + h
    )
}

#[test]
fn a_bare_obj_is_framed_with_x_on_the_right_and_y_on_top() {
    let dir = ScratchDir::new("bare-obj");
    std::fs::write(
        dir.join("m.mtl"),
        "newmtl red\nKd 0.9 0 0\nnewmtl blue\nKd 0 0 0.9\n",
    )
    .unwrap();
    let obj = format!(
        "mtllib m.mtl\n{}{}",
        quad(1.5, 0.0, 0.8, "red"),
        quad(0.0, 1.2, 0.6, "blue")
    );
    std::fs::write(dir.join("m.obj"), obj).unwrap();
    let out = dir.join("m.exr");
    render_ok(
        &dir,
        &dir.join("m.obj"),
        &out,
        // In RGB, where the grey sky has no colour noise to count as red or blue.
        &["--resolution", "48x32", "--spp", "4", "--rgb"],
    );
    let img = read_exr(&out);
    let (w, h) = (img.width, img.height);
    // The grey sky has r = g = b: only the patches are "red" or "blue".
    let redness = |keep: &dyn Fn(usize, usize) -> bool| {
        let mut s = 0.0;
        for y in 0..h {
            for x in 0..w {
                let [r, g, b] = img.rgb[y * w + x];
                if keep(x, y) {
                    s += (r - g.max(b)).max(0.0);
                }
            }
        }
        s
    };
    let blueness = |keep: &dyn Fn(usize, usize) -> bool| {
        let mut s = 0.0;
        for y in 0..h {
            for x in 0..w {
                let [r, g, b] = img.rgb[y * w + x];
                if keep(x, y) {
                    s += (b - g.max(r)).max(0.0);
                }
            }
        }
        s
    };
    let (red_left, red_right) = (redness(&|x, _| x < w / 2), redness(&|x, _| x >= w / 2));
    assert!(
        red_right > 1.0 && red_left < 0.01 * red_right,
        "red: left {red_left}, right {red_right}"
    );
    let (blue_top, blue_bottom) = (blueness(&|_, y| y < h / 2), blueness(&|_, y| y >= h / 2));
    assert!(
        blue_top > 1.0 && blue_bottom < 0.01 * blue_top,
        "blue: top {blue_top}, bottom {blue_bottom}"
    );
}
