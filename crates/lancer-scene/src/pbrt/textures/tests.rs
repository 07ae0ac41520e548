//! Tests of the `Texture` reader.
use super::*;
use crate::pbrt::convert::TextureNames;
use crate::pbrt::convert::testing::{err, typed_in, unused, with_textures};
use lancer::image_io::srgb_to_linear;
use lancer::texture::Mapping2D;
use lancer::texture::{FloatTex, SpectrumTex};
use std::path::{Path, PathBuf};

type Converted<T> = (Result<Fallback<T>, SceneError>, Vec<String>);

/// The float texture of the one `Texture` of `text`, and its unread parameters.
fn float_in(text: &str, dir: &Path, textures: &TextureNames) -> Converted<FloatTextureDesc> {
    let (class, params, loc) = typed_in(text, dir);
    let out = with_textures(&params, dir, textures, |r| {
        float_texture(r, &class, &Transform::IDENTITY, &loc)
    });
    (out, unused(&params))
}

/// The spectrum texture of the one `Texture` of `text`, and its unread parameters.
fn spectrum_in(text: &str, dir: &Path, textures: &TextureNames) -> Converted<SpectrumTextureDesc> {
    let (class, params, loc) = typed_in(text, dir);
    let out = with_textures(&params, dir, textures, |r| {
        spectrum_texture(r, &class, &Transform::IDENTITY, &loc)
    });
    (out, unused(&params))
}

/// A texture that converts without warnings and reads every parameter.
#[track_caller]
fn clean<T>((out, unused): Converted<T>) -> T {
    let f = out.unwrap_or_else(|e| panic!("{e}"));
    assert!(f.warnings.is_empty(), "{:?}", f.warnings);
    assert!(unused.is_empty(), "{unused:?}");
    f.value
}

fn float(text: &str) -> FloatTextureDesc {
    clean(float_in(text, Path::new("."), &TextureNames::default()))
}

fn spectrum(text: &str) -> SpectrumTextureDesc {
    clean(spectrum_in(text, Path::new("."), &TextureNames::default()))
}

const fn c(v: f32) -> FloatTex {
    FloatTex::Const(v)
}

fn grey(v: f32) -> SpectrumTex {
    SpectrumTex::Const(Rgb::splat(v))
}

#[test]
fn float_textures_take_pbrt_defaults() {
    assert!(matches!(
        float(r#"Texture "t" "float" "constant""#),
        FloatTextureDesc::Constant(1.0)
    ));
    let FloatTextureDesc::Scale(ScaleTexture { tex, scale }) =
        float(r#"Texture "t" "float" "scale""#)
    else {
        panic!("scale")
    };
    assert_eq!((tex, scale), (c(1.0), c(1.0)));
    let FloatTextureDesc::Mix(MixTexture { tex1, tex2, amount }) =
        float(r#"Texture "t" "float" "mix""#)
    else {
        panic!("mix")
    };
    assert_eq!((tex1, tex2, amount), (c(0.0), c(1.0), c(0.5)));
    let FloatTextureDesc::Checkerboard(CheckerboardTexture {
        mapping,
        tex1,
        tex2,
    }) = float(r#"Texture "t" "float" "checkerboard""#)
    else {
        panic!("checkerboard")
    };
    assert_eq!(
        (mapping, tex1, tex2),
        (Mapping2D::default(), c(1.0), c(0.0))
    );
}

#[test]
fn float_textures_read_every_parameter() {
    assert!(matches!(
        float(r#"Texture "t" "float" "constant" "float value" 0.25"#),
        FloatTextureDesc::Constant(0.25)
    ));
    let mut names = TextureNames::default();
    names.floats.insert("a".into(), 3);
    let FloatTextureDesc::Scale(ScaleTexture { tex, scale }) = clean(float_in(
        r#"Texture "t" "float" "scale" "texture tex" "a" "float scale" 2"#,
        Path::new("."),
        &names,
    )) else {
        panic!("scale")
    };
    assert_eq!((tex, scale), (FloatTex::Tex(3), c(2.0)));
    let FloatTextureDesc::Mix(MixTexture { tex1, tex2, amount }) =
        float(r#"Texture "t" "float" "mix" "float tex1" 0.1 "float tex2" 0.2 "float amount" 0.3"#)
    else {
        panic!("mix")
    };
    assert_eq!((tex1, tex2, amount), (c(0.1), c(0.2), c(0.3)));
    let FloatTextureDesc::Checkerboard(CheckerboardTexture {
        mapping,
        tex1,
        tex2,
    }) = float(
        r#"Texture "t" "float" "checkerboard" "float uscale" 4 "float vscale" 8
           "float udelta" 0.5 "float vdelta" 0.25 "float tex1" 0.7 "float tex2" 0.2
           "integer dimension" 2 "string mapping" "uv""#,
    )
    else {
        panic!("checkerboard")
    };
    let expected = UvMapping {
        su: 4.0,
        sv: 8.0,
        du: 0.5,
        dv: 0.25,
    };
    assert_eq!((mapping, tex1, tex2), (expected.into(), c(0.7), c(0.2)));
}

#[test]
fn spectrum_textures_take_pbrt_defaults_and_every_parameter() {
    let SpectrumTextureDesc::Constant(v) = spectrum(r#"Texture "t" "spectrum" "constant""#) else {
        panic!("constant")
    };
    assert_eq!(v, Rgb::ONE);
    let SpectrumTextureDesc::Constant(v) =
        spectrum(r#"Texture "t" "spectrum" "constant" "rgb value" [0.1 0.2 0.3]"#)
    else {
        panic!("constant")
    };
    assert_eq!(v, Rgb::new(0.1, 0.2, 0.3));
    let SpectrumTextureDesc::Scale(ScaleTexture { tex, scale }) =
        spectrum(r#"Texture "t" "spectrum" "scale""#)
    else {
        panic!("scale")
    };
    assert_eq!((tex, scale), (grey(1.0), c(1.0)));
    let SpectrumTextureDesc::Scale(ScaleTexture { tex, scale }) =
        spectrum(r#"Texture "t" "spectrum" "scale" "rgb tex" [0.5 0.5 0.5] "float scale" 3"#)
    else {
        panic!("scale")
    };
    assert_eq!((tex, scale), (grey(0.5), c(3.0)));
    let SpectrumTextureDesc::Mix(MixTexture { tex1, tex2, amount }) =
        spectrum(r#"Texture "t" "spectrum" "mix""#)
    else {
        panic!("mix")
    };
    assert_eq!((tex1, tex2, amount), (grey(0.0), grey(1.0), c(0.5)));
    let SpectrumTextureDesc::Mix(MixTexture { tex1, tex2, amount }) = spectrum(
        r#"Texture "t" "spectrum" "mix" "rgb tex1" [0.2 0.2 0.2] "rgb tex2" [0.4 0.4 0.4]
           "float amount" 0.9"#,
    ) else {
        panic!("mix")
    };
    assert_eq!((tex1, tex2, amount), (grey(0.2), grey(0.4), c(0.9)));
    let SpectrumTextureDesc::Checkerboard(CheckerboardTexture {
        mapping,
        tex1,
        tex2,
    }) = spectrum(r#"Texture "t" "spectrum" "checkerboard" "float uscale" 2"#)
    else {
        panic!("checkerboard")
    };
    assert!(matches!(mapping, Mapping2D::Uv(m) if m.su == 2.0));
    assert_eq!((tex1, tex2), (grey(1.0), grey(0.0)));
}

#[test]
fn what_lancer_lacks_falls_back_with_a_warning() {
    let (out, unused) = float_in(
        r#"Texture "t" "float" "ptex" "string filename" "a.ptx""#,
        Path::new("."),
        &TextureNames::default(),
    );
    let f = out.unwrap();
    assert!(matches!(f.value, FloatTextureDesc::Constant(1.0)));
    assert_eq!(
        f.warnings,
        ["float texture \"ptex\" is not supported yet; lancer uses the constant 1"]
    );
    assert_eq!(unused.len(), 1);
    let (out, _) = spectrum_in(
        r#"Texture "t" "spectrum" "ptex""#,
        Path::new("."),
        &TextureNames::default(),
    );
    let f = out.unwrap();
    assert!(matches!(f.value, SpectrumTextureDesc::Constant(v) if v == Rgb::splat(0.5)));
    assert_eq!(
        f.warnings,
        ["spectrum texture \"ptex\" is not supported yet; lancer uses a constant grey 0.5"]
    );
}

/// The texture of `text` converted with texture space `ctm`, checked clean.
fn float_at(text: &str, ctm: &Transform) -> FloatTextureDesc {
    let (class, params, loc) = typed_in(text, Path::new("."));
    let names = TextureNames::default();
    let out = with_textures(&params, Path::new("."), &names, |r| {
        float_texture(r, &class, ctm, &loc)
    });
    clean((out, unused(&params)))
}

#[test]
fn noise_textures_take_pbrt_defaults_and_texture_space_from_the_ctm() {
    let ctm = Transform::scale(Vec3::splat(0.5)).unwrap();
    let FloatTextureDesc::Wrinkled(WrinkledTexture {
        mapping,
        octaves,
        omega,
    }) = float_at(r#"Texture "t" "float" "wrinkled""#, &ctm)
    else {
        panic!("wrinkled")
    };
    assert_eq!((octaves, omega), (8, 0.5));
    // Texture space is half the size: the world point (1, 0, 0) is texture (2, 0, 0).
    let tc = lancer::texture::TexCoord {
        p: Vec3::X,
        ..Default::default()
    };
    assert!((mapping.map(&tc) - Vec3::new(2.0, 0.0, 0.0)).length() < 1e-6);
    let FloatTextureDesc::Fbm(FbmTexture { octaves, omega, .. }) = float_at(
        r#"Texture "t" "float" "fbm" "integer octaves" 5 "float roughness" 0.6"#,
        &ctm,
    ) else {
        panic!("fbm")
    };
    assert_eq!((octaves, omega), (5, 0.6));
    assert!(matches!(
        float_at(r#"Texture "t" "float" "windy""#, &ctm),
        FloatTextureDesc::Windy(WindyTexture { .. })
    ));
    let SpectrumTextureDesc::Marble(MarbleTexture {
        octaves,
        omega,
        scale,
        variation,
        ..
    }) = spectrum(
        r#"Texture "t" "spectrum" "marble" "float scale" 9 "float variation" 0.8 "integer octaves" 5"#,
    )
    else {
        panic!("marble")
    };
    assert_eq!((octaves, omega, scale, variation), (5, 0.5, 9.0, 0.8));
}

#[test]
fn dots_swap_inside_and_outside_as_pbrt_v4_does() {
    let SpectrumTextureDesc::Dots(DotsTexture {
        dot, background, ..
    }) = spectrum(
        r#"Texture "t" "spectrum" "dots" "float uscale" 8 "rgb inside" [0.85 0.1 0.1]
           "rgb outside" [0.9 0.9 0.8]"#,
    )
    else {
        panic!("dots")
    };
    assert_eq!(
        (dot, background),
        (
            SpectrumTex::Const(Rgb::new(0.9, 0.9, 0.8)),
            SpectrumTex::Const(Rgb::new(0.85, 0.1, 0.1))
        )
    );
    let FloatTextureDesc::Dots(DotsTexture {
        dot, background, ..
    }) = float(r#"Texture "t" "float" "dots""#)
    else {
        panic!("dots")
    };
    // Defaults inside 1, outside 0: the dots are 0.
    assert_eq!((dot, background), (c(0.0), c(1.0)));
}

#[test]
fn bilerp_directionmix_and_the_3d_checkerboard() {
    let FloatTextureDesc::Bilerp(BilerpTexture { v, .. }) =
        float(r#"Texture "t" "float" "bilerp" "float v01" 0.5"#)
    else {
        panic!("bilerp")
    };
    assert_eq!(v, [0.0, 0.5, 0.0, 1.0]);
    let SpectrumTextureDesc::Bilerp(BilerpTexture { v, .. }) =
        spectrum(r#"Texture "t" "spectrum" "bilerp" "rgb v11" [0.9 0.9 0.1]"#)
    else {
        panic!("bilerp")
    };
    assert_eq!(v, [Rgb::ZERO, Rgb::ONE, Rgb::ZERO, Rgb::new(0.9, 0.9, 0.1)]);
    // dir is a texture-space vector: rotated 90° about z, +y becomes −x.
    let rot = Transform::rotate(90.0, Vec3::Z).unwrap();
    let FloatTextureDesc::DirectionMix(DirectionMixTexture { dir, tex1, tex2 }) = float_at(
        r#"Texture "t" "float" "directionmix" "vector3 dir" [0 2 0]"#,
        &rot,
    ) else {
        panic!("directionmix")
    };
    assert!((dir - Vec3::new(-1.0, 0.0, 0.0)).length() < 1e-6, "{dir}");
    assert_eq!((tex1, tex2), (c(0.0), c(1.0)));
    assert!(matches!(
        float(r#"Texture "t" "float" "checkerboard" "integer dimension" 3"#),
        FloatTextureDesc::Checkerboard3D(Checkerboard3DTexture { .. })
    ));
    // pbrt-v4 reports a 3D checkerboard's "mapping" as unused.
    let (out, unused) = float_in(
        r#"Texture "t" "float" "checkerboard" "integer dimension" 3 "string mapping" "uv""#,
        Path::new("."),
        &TextureNames::default(),
    );
    assert!(out.unwrap().warnings.is_empty());
    assert_eq!(unused.len(), 1);
    assert_eq!(
        err(float_in(
            "Texture \"t\" \"float\" \"checkerboard\"\n  \"integer dimension\" 4",
            Path::new("."),
            &TextureNames::default()
        )
        .0),
        "t.pbrt:2:3: a 4-dimensional checkerboard is not supported (pbrt-v4 has 2 and 3)"
    );
}

#[test]
fn mappings_read_their_parameters_in_texture_space() {
    let ctm = Transform::translate(Vec3::new(0.0, 0.5, 0.0));
    let FloatTextureDesc::Checkerboard(CheckerboardTexture { mapping, .. }) = float_at(
        r#"Texture "t" "float" "checkerboard" "string mapping" "planar" "vector3 v1" [2 0 0]
           "vector3 v2" [0 0 2] "float udelta" 0.25 "float vdelta" 0.5"#,
        &ctm,
    ) else {
        panic!("checkerboard")
    };
    let Mapping2D::Planar {
        texture_from_world,
        vs,
        vt,
        ds,
        dt,
    } = mapping
    else {
        panic!("planar")
    };
    assert_eq!(
        (vs, vt, ds, dt),
        (
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 2.0),
            0.25,
            0.5
        )
    );
    assert_eq!(texture_from_world, ctm.inverse());
    for (kind, want) in [("spherical", 1), ("cylindrical", 2)] {
        let FloatTextureDesc::Checkerboard(CheckerboardTexture { mapping, .. }) = float_at(
            &format!(r#"Texture "t" "float" "checkerboard" "string mapping" "{kind}""#),
            &ctm,
        ) else {
            panic!("checkerboard")
        };
        let got = match mapping {
            Mapping2D::Spherical { texture_from_world } if texture_from_world == ctm.inverse() => 1,
            Mapping2D::Cylindrical { texture_from_world }
                if texture_from_world == ctm.inverse() =>
            {
                2
            }
            _ => 0,
        };
        assert_eq!(got, want, "{kind}");
    }
    assert_eq!(
        err(float_in(
            "Texture \"t\" \"float\" \"bilerp\"\n  \"string mapping\" \"cubic\"",
            Path::new("."),
            &TextureNames::default()
        )
        .0),
        "t.pbrt:2:3: unknown texture mapping \"cubic\" (expected \"uv\", \"spherical\", \"cylindrical\" or \"planar\")"
    );
}

#[test]
fn texture_names_are_checked_by_kind() {
    let mut names = TextureNames::default();
    names.spectra.insert("rgb".into(), 0);
    let (out, _) = float_in(
        "Texture \"t\" \"float\" \"scale\"\n  \"texture tex\" \"rgb\"",
        Path::new("."),
        &names,
    );
    assert_eq!(
        err(out),
        "t.pbrt:2:3: no float texture named \"rgb\" (there is a spectrum texture of that name)"
    );
    let (out, _) = spectrum_in(
        "Texture \"t\" \"spectrum\" \"mix\"\n  \"texture tex2\" \"none\"",
        Path::new("."),
        &names,
    );
    assert_eq!(err(out), "t.pbrt:2:3: no spectrum texture named \"none\"");
}

/// A fresh folder with a 1×1 8-bit PNG of value 128 in every channel, `grey.png`.
fn folder_with_png(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lancer-textures-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = std::fs::File::create(dir.join("grey.png")).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), 1, 1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()
        .unwrap()
        .write_image_data(&[128, 128, 128])
        .unwrap();
    dir
}

#[test]
fn imagemaps_read_the_image_and_every_parameter() {
    let dir = folder_with_png("imagemap");
    let names = TextureNames::default();
    let image = |text: &str| {
        let SpectrumTextureDesc::Image(t) = clean(spectrum_in(text, &dir, &names)) else {
            panic!("an image")
        };
        t
    };
    // PNG defaults to sRGB: 128/255 is decoded to linear.
    let t = image(r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png""#);
    let srgb = srgb_to_linear(128.0 / 255.0);
    let texel = t.image.texels[0];
    assert!((texel.x - srgb).abs() < 1e-6, "{texel:?}");
    // pbrt-v4's default filter is bilinear (over a MIP pyramid).
    assert_eq!(
        (t.wrap, t.scale, t.invert, t.filter),
        (WrapMode::Repeat, 1.0, false, ImageFilter::Bilinear)
    );
    // Filtered over a pyramid (the scene build makes it) of the 1×1 image, in sRGB.
    assert!(t.mip && t.to_srgb.is_none());
    assert_eq!((t.image.width, t.image.height), (1, 1));
    assert_eq!(t.mapping, Mapping2D::default());
    let t = image(
        r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png"
           "string encoding" "linear" "string wrap" "clamp" "string filter" "point"
           "float maxanisotropy" 4 "float scale" 2 "bool invert" true "float uscale" 3
           "string mapping" "uv""#,
    );
    assert!((t.image.texels[0].x - 128.0 / 255.0).abs() < 1e-6);
    assert_eq!(
        (t.wrap, t.scale, t.invert, t.filter),
        (WrapMode::Clamp, 2.0, true, ImageFilter::Point)
    );
    assert!(matches!(t.mapping, Mapping2D::Uv(m) if m.su == 3.0));
    let FloatTextureDesc::Image(t) = clean(float_in(
        r#"Texture "t" "float" "imagemap" "string filename" "grey.png" "string wrap" "black""#,
        &dir,
        &names,
    )) else {
        panic!("an image")
    };
    assert_eq!(t.wrap, WrapMode::Black);
    // Every pbrt-v4 filter is read, `maxanisotropy` (default 8) with `ewa`.
    for (f, want) in [
        ("bilinear", ImageFilter::Bilinear),
        ("trilinear", ImageFilter::Trilinear),
        (
            "ewa",
            ImageFilter::Ewa {
                max_anisotropy: 8.0,
            },
        ),
    ] {
        let t = image(&format!(
            r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png" "string filter" "{f}""#
        ));
        assert_eq!(t.filter, want);
    }
    let t = image(
        r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png" "string filter" "ewa"
           "float maxanisotropy" 3"#,
    );
    assert_eq!(
        t.filter,
        ImageFilter::Ewa {
            max_anisotropy: 3.0
        }
    );
    let t = image(
        r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png" "string mapping" "planar""#,
    );
    assert!(matches!(t.mapping, Mapping2D::Planar { .. }));
    let (out, _) = spectrum_in(
        "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"grey.png\"\n  \"string filter\" \"fancy\"",
        &dir,
        &names,
    );
    assert_eq!(
        err(out),
        "t.pbrt:2:3: unknown texture filter \"fancy\" (expected \"point\", \"bilinear\", \"trilinear\" or \"ewa\")"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn imagemap_errors_are_at_their_parameter_or_the_directive() {
    let dir = folder_with_png("errors");
    let names = TextureNames::default();
    let error = |text: &str| err(spectrum_in(text, &dir, &names).0);
    assert_eq!(
        error(r#"Texture "t" "spectrum" "imagemap""#),
        "t.pbrt:1:1: an \"imagemap\" texture needs the name of its image, \"string filename\""
    );
    assert_eq!(
        error(
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"grey.png\"\n  \"string wrap\" \"mirror\""
        ),
        "t.pbrt:2:3: unknown wrap mode \"mirror\" (expected \"repeat\", \"black\", \"clamp\" or \"octahedralsphere\")"
    );
    assert_eq!(
        error(
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"grey.png\"\n  \"string encoding\" \"log\""
        ),
        "t.pbrt:2:3: unknown encoding \"log\" (expected \"sRGB\", \"linear\" or \"gamma G\")"
    );
    let missing = error(r#"Texture "t" "spectrum" "imagemap" "string filename" "nope.png""#);
    assert!(
        missing.starts_with("t.pbrt:1:1: ") && missing.contains("nope.png"),
        "{missing}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
