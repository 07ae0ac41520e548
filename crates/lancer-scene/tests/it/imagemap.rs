//! pbrt-v4's `Texture … "imagemap"`: the image found next to the scene, decoded once however
//! many textures name it, looked up with pbrt's (u, v) conventions; errors placed at the
//! directive and naming the file.

use crate::common::ScratchDir;
use lancer::image_io::srgb_to_linear;
use lancer::math::{Vec2, Vec3};
use lancer::texture::{
    FloatTex, FloatTexture, FloatTextureDesc, ImageFilter, Pyramids, SpectrumTex, SpectrumTexture,
    SpectrumTextureDesc, TexCoord, TextureEval, WrapMode,
};
use lancer_scene::load;
use std::path::Path;
use std::sync::Arc;

/// A 2×2 8-bit RGB PNG: top row red, green; bottom row blue, white (values 200 where lit).
fn quad_png(path: &Path) {
    let data = [
        200u8, 0, 0, 0, 200, 0, //
        0, 0, 200, 200, 200, 200,
    ];
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), 2, 2);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header().unwrap().write_image_data(&data).unwrap();
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-5
}

#[test]
fn imagemap_textures_read_the_png_beside_the_scene() {
    let dir = ScratchDir::new("load");
    std::fs::create_dir_all(dir.join("tex")).unwrap();
    quad_png(&dir.join("tex/quad.png"));
    let scene = dir.join("s.pbrt");
    std::fs::write(
        &scene,
        r#"WorldBegin
Texture "c" "spectrum" "imagemap" "string filename" "tex/quad.png"
Texture "lin" "spectrum" "imagemap" "string filename" "tex/quad.png"
    "string encoding" "linear" "string wrap" "clamp" "float scale" 2 "bool invert" true
Texture "f" "float" "imagemap" "string filename" "tex/quad.png" "string filter" "point"
    "float uscale" 2 "float vdelta" 0.5
Texture "again" "spectrum" "imagemap" "string filename" "tex/quad.png"
Material "diffuse" "texture reflectance" "c"
Shape "sphere"
"#,
    )
    .unwrap();
    let loaded = load(&scene).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.desc;
    let (
        SpectrumTextureDesc::Image(c),
        SpectrumTextureDesc::Image(lin),
        SpectrumTextureDesc::Image(again),
    ) = (
        &d.spectrum_textures[0],
        &d.spectrum_textures[1],
        &d.spectrum_textures[2],
    )
    else {
        panic!("not image textures: {:?}", d.spectrum_textures)
    };
    // The file is decoded once for both textures with the same encoding.
    assert!(Arc::ptr_eq(&c.image, &again.image));
    assert!(!Arc::ptr_eq(&c.image, &lin.image));
    assert_eq!(c.wrap, WrapMode::Repeat);
    assert!(c.filter == ImageFilter::Bilinear && !c.invert && c.scale == 1.0);

    // Built as the scene build does: the two textures of the same image and settings share
    // one pyramid.
    let mut pyramids = Pyramids::default();
    let floats: Vec<FloatTexture> = d
        .float_textures
        .iter()
        .map(|t| t.build(&mut pyramids))
        .collect();
    let spectra: Vec<SpectrumTexture> = d
        .spectrum_textures
        .iter()
        .map(|t| t.build(&mut pyramids))
        .collect();
    let (SpectrumTexture::Image(c), SpectrumTexture::Image(again)) = (&spectra[0], &spectra[2])
    else {
        panic!("not image textures")
    };
    assert!(Arc::ptr_eq(&c.mipmap, &again.mipmap));
    // Three images (sRGB, linear, the float's first channel), one pyramid each.
    assert_eq!(pyramids.len(), 3);
    let eval = TextureEval {
        floats: &floats,
        spectra: &spectra,
    };
    // No footprint: every filter reads the finest level.
    let at = |u: f32, v: f32| TexCoord {
        uv: Vec2::new(u, v),
        p: Vec3::ZERO,
        n: Vec3::Z,
        ..TexCoord::default()
    };
    let lit = srgb_to_linear(200.0 / 255.0);
    // pbrt flips v: (u, v) = (0.25, 0.75) is the centre of the top-left texel (red), and
    // (0.75, 0.25) the bottom-right one (white).
    let red = eval.spectrum(SpectrumTex::Tex(0), &at(0.25, 0.75));
    assert!(close(red, Vec3::new(lit, 0.0, 0.0)), "{red}");
    let white = eval.spectrum(SpectrumTex::Tex(0), &at(0.75, 0.25));
    assert!(close(white, Vec3::splat(lit)), "{white}");
    // Half-way between red and green on the top row: bilinear.
    let mid = eval.spectrum(SpectrumTex::Tex(0), &at(0.5, 0.75));
    assert!(close(mid, Vec3::new(lit / 2.0, lit / 2.0, 0.0)), "{mid}");
    // Repeat wraps around.
    let wrapped = eval.spectrum(SpectrumTex::Tex(0), &at(1.25, -0.25));
    assert!(close(wrapped, red), "{wrapped}");

    // Linear encoding, scale 2, inverted: max(0, 1 − 2·c).
    let l = 200.0 / 255.0;
    let inv = eval.spectrum(SpectrumTex::Tex(1), &at(0.25, 0.75));
    assert!(
        close(inv, Vec3::new(0.0, 1.0, 1.0)),
        "{inv} (1 − 2·{l} clamps to 0)"
    );

    // The float texture, point-sampled, reads the first channel; u is scaled by 2 and v
    // shifted by ½: (0.125, 0.25) maps to (0.25, 0.75), the red texel.
    let FloatTextureDesc::Image(f) = &d.float_textures[0] else {
        panic!("not an image")
    };
    assert_eq!(f.filter, ImageFilter::Point);
    assert!((eval.float(FloatTex::Tex(0), &at(0.125, 0.25)) - lit).abs() < 1e-6);
    // (0.375, 0.25) → (0.75, 0.75): green, whose R is 0.
    assert_eq!(eval.float(FloatTex::Tex(0), &at(0.375, 0.25)), 0.0);
}

#[test]
fn imagemap_errors_name_the_file_and_the_directive() {
    let dir = ScratchDir::new("errors");
    let scene = dir.join("s.pbrt");
    std::fs::write(
        &scene,
        "WorldBegin\n\nTexture \"c\" \"spectrum\" \"imagemap\" \"string filename\" \"missing.png\"\n",
    )
    .unwrap();
    let e = load(&scene).unwrap_err();
    let text = e.to_string();
    assert!(text.contains("missing.png"), "{text}");
    assert_eq!(e.location.as_ref().map(|l| l.line), Some(3), "{text}");

    quad_png(&dir.join("q.png"));
    std::fs::write(
        &scene,
        "WorldBegin\nTexture \"c\" \"float\" \"imagemap\" \"string filename\" \"q.png\"\n  \"string encoding\" \"gamma\"\n",
    )
    .unwrap();
    let e = load(&scene).unwrap_err();
    assert!(e.message.contains("unknown encoding"), "{e}");
    assert_eq!(e.location.as_ref().map(|l| l.line), Some(3), "{e}");

    std::fs::write(
        &scene,
        "WorldBegin\nTexture \"c\" \"float\" \"imagemap\" \"string filename\" \"q.png\" \"string filter\" \"ewa\"\n",
    )
    .unwrap();
    // pbrt-v4's default filter is read without a warning (a zero footprint makes it the
    // finest level's bilinear lookup).
    let loaded = load(&scene).unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert!(matches!(
        loaded.desc.float_textures[0],
        FloatTextureDesc::Image(_)
    ));
}
