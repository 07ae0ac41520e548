//! `Texture`: pbrt-v4's float and spectrum textures (`constant`, `scale`, `mix`,
//! `checkerboard`, `imagemap`) as lancer's [`FloatTexture`] and [`SpectrumTexture`].

use super::convert::{Fallback, Reader, locate};
use crate::error::{Location, SceneError};
use lancer::math::Rgb;
use lancer::spectrum::SpectrumKind;
use lancer::texture::{FloatTexture, ImageTexture, SpectrumTexture, UvMapping, WrapMode};

/// The float texture of class `class` at `loc`; an unknown class becomes the constant 1.
pub fn float_texture(
    r: &Reader,
    class: &str,
    loc: &Location,
) -> Result<Fallback<FloatTexture>, SceneError> {
    float(r, class).map_err(|e| locate(e, loc))
}

/// The spectrum texture of class `class` at `loc`; an unknown class becomes a constant grey.
pub fn spectrum_texture(
    r: &Reader,
    class: &str,
    loc: &Location,
) -> Result<Fallback<SpectrumTexture>, SceneError> {
    spectrum(r, class).map_err(|e| locate(e, loc))
}

fn float(r: &Reader, class: &str) -> Result<Fallback<FloatTexture>, SceneError> {
    let p = r.params;
    let t = match class {
        "constant" => FloatTexture::Constant(p.float("value", 1.0)?),
        "scale" => FloatTexture::Scale {
            tex: r.float_tex("tex", 1.0)?,
            scale: r.float_tex("scale", 1.0)?,
        },
        "mix" => FloatTexture::Mix {
            tex1: r.float_tex("tex1", 0.0)?,
            tex2: r.float_tex("tex2", 1.0)?,
            amount: r.float_tex("amount", 0.5)?,
        },
        "checkerboard" => {
            let t = FloatTexture::Checkerboard {
                mapping: uv_mapping(r)?,
                tex1: r.float_tex("tex1", 1.0)?,
                tex2: r.float_tex("tex2", 0.0)?,
            };
            return Ok(Fallback::noted(t, checkerboard_notes(r)?));
        }
        "imagemap" => return Ok(image_texture(r, true)?.map(FloatTexture::Image)),
        _ => {
            return Ok(Fallback::instead(
                FloatTexture::Constant(1.0),
                format!(
                    "float texture \"{class}\" is not supported yet; lancer uses the constant 1"
                ),
            ));
        }
    };
    Ok(Fallback::done(t))
}

fn spectrum(r: &Reader, class: &str) -> Result<Fallback<SpectrumTexture>, SceneError> {
    use SpectrumKind::Albedo;
    let t = match class {
        "constant" => {
            SpectrumTexture::Constant(r.params.color("value", Albedo, r.dir)?.unwrap_or(Rgb::ONE))
        }
        "scale" => SpectrumTexture::Scale {
            tex: r.spectrum_tex("tex", Rgb::ONE, Albedo)?,
            scale: r.float_tex("scale", 1.0)?,
        },
        "mix" => SpectrumTexture::Mix {
            tex1: r.spectrum_tex("tex1", Rgb::ZERO, Albedo)?,
            tex2: r.spectrum_tex("tex2", Rgb::ONE, Albedo)?,
            amount: r.float_tex("amount", 0.5)?,
        },
        "checkerboard" => {
            let t = SpectrumTexture::Checkerboard {
                mapping: uv_mapping(r)?,
                tex1: r.spectrum_tex("tex1", Rgb::ONE, Albedo)?,
                tex2: r.spectrum_tex("tex2", Rgb::ZERO, Albedo)?,
            };
            return Ok(Fallback::noted(t, checkerboard_notes(r)?));
        }
        "imagemap" => return Ok(image_texture(r, false)?.map(SpectrumTexture::Image)),
        _ => {
            return Ok(Fallback::instead(
                SpectrumTexture::Constant(Rgb::splat(0.5)),
                format!(
                    "spectrum texture \"{class}\" is not supported yet; lancer uses a constant grey 0.5"
                ),
            ));
        }
    };
    Ok(Fallback::done(t))
}

/// `mapping`: lancer has only pbrt's `uv`; another is noted.
fn mapping_note(r: &Reader) -> Result<Option<String>, SceneError> {
    let kind = r
        .params
        .string("mapping")?
        .unwrap_or_else(|| "uv".to_string());
    Ok((kind != "uv")
        .then(|| format!("texture mapping \"{kind}\" is not supported yet; lancer uses \"uv\"")))
}

/// pbrt's `uv` mapping: (u, v) ↦ (su·u + du, sv·v + dv).
fn uv_mapping(r: &Reader) -> Result<UvMapping, SceneError> {
    let p = r.params;
    Ok(UvMapping {
        su: p.float("uscale", 1.0)?,
        sv: p.float("vscale", 1.0)?,
        du: p.float("udelta", 0.0)?,
        dv: p.float("vdelta", 0.0)?,
    })
}

/// A checkerboard's `dimension` (lancer has the 2D one) and mapping: the first one lancer
/// replaces, if any.
fn checkerboard_notes(r: &Reader) -> Result<Vec<String>, SceneError> {
    let dim = r.params.int("dimension", 2)?;
    if dim != 2 {
        return Ok(vec![format!(
            "a {dim}D checkerboard is not supported yet; lancer uses the 2D one"
        )]);
    }
    Ok(mapping_note(r)?.into_iter().collect())
}

/// pbrt-v4's `imagemap`: the image, its wrap mode and filter, `scale`, `invert` and the (u, v)
/// mapping. Float textures read the value pbrt-v4's MIPMap gives (see
/// [`crate::image_read::DecodedImage::float_image`]).
fn image_texture(r: &Reader, float: bool) -> Result<Fallback<ImageTexture>, SceneError> {
    let p = r.params;
    let mut notes = Vec::new();
    let (path, encoding) = r.image_file("an \"imagemap\" texture")?;
    let wrap = match p.string("wrap")?.as_deref().unwrap_or("repeat") {
        "repeat" => WrapMode::Repeat,
        "black" => WrapMode::Black,
        "clamp" => WrapMode::Clamp,
        "octahedralsphere" => WrapMode::OctahedralSphere,
        other => {
            return Err(p.error_at(
                "wrap",
                format!(
                    "unknown wrap mode \"{other}\" (expected \"repeat\", \"black\", \"clamp\" or \"octahedralsphere\")"
                ),
            ));
        }
    };
    let nearest = match p.string("filter")?.as_deref().unwrap_or("bilinear") {
        "bilinear" => false,
        "point" => true,
        f @ ("trilinear" | "ewa" | "EWA") => {
            notes.push(format!(
                "texture filter \"{f}\" is not supported yet (lancer has no ray differentials); lancer uses \"bilinear\""
            ));
            false
        }
        other => {
            notes.push(format!(
                "unknown texture filter \"{other}\"; lancer uses \"bilinear\""
            ));
            false
        }
    };
    // Only matters for the EWA filter.
    p.float("maxanisotropy", 8.0)?;
    let image = if float {
        r.images.float(&path, encoding, nearest)
    } else {
        r.images.rgb(&path, encoding)
    }
    .map_err(|e| SceneError::general(e.to_string()))?;
    notes.extend(mapping_note(r)?);
    let t = ImageTexture {
        image,
        mapping: uv_mapping(r)?,
        wrap,
        scale: p.float("scale", 1.0)?,
        invert: p.bool("invert", false)?,
        nearest,
    };
    Ok(Fallback::noted(t, notes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::convert::TextureNames;
    use crate::pbrt::convert::testing::{err, typed_in, unused, with_textures};
    use lancer::image_io::srgb_to_linear;
    use lancer::texture::{FloatTex, SpectrumTex};
    use std::path::{Path, PathBuf};

    type Converted<T> = (Result<Fallback<T>, SceneError>, Vec<String>);

    /// The float texture of the one `Texture` of `text`, and its unread parameters.
    fn float_in(text: &str, dir: &Path, textures: &TextureNames) -> Converted<FloatTexture> {
        let (class, params, loc) = typed_in(text, dir);
        let out = with_textures(&params, dir, textures, |r| float_texture(r, &class, &loc));
        (out, unused(&params))
    }

    /// The spectrum texture of the one `Texture` of `text`, and its unread parameters.
    fn spectrum_in(text: &str, dir: &Path, textures: &TextureNames) -> Converted<SpectrumTexture> {
        let (class, params, loc) = typed_in(text, dir);
        let out = with_textures(&params, dir, textures, |r| {
            spectrum_texture(r, &class, &loc)
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

    fn float(text: &str) -> FloatTexture {
        clean(float_in(text, Path::new("."), &TextureNames::default()))
    }

    fn spectrum(text: &str) -> SpectrumTexture {
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
            FloatTexture::Constant(1.0)
        ));
        let FloatTexture::Scale { tex, scale } = float(r#"Texture "t" "float" "scale""#) else {
            panic!("scale")
        };
        assert_eq!((tex, scale), (c(1.0), c(1.0)));
        let FloatTexture::Mix { tex1, tex2, amount } = float(r#"Texture "t" "float" "mix""#) else {
            panic!("mix")
        };
        assert_eq!((tex1, tex2, amount), (c(0.0), c(1.0), c(0.5)));
        let FloatTexture::Checkerboard {
            mapping,
            tex1,
            tex2,
        } = float(r#"Texture "t" "float" "checkerboard""#)
        else {
            panic!("checkerboard")
        };
        assert_eq!(
            (mapping, tex1, tex2),
            (UvMapping::default(), c(1.0), c(0.0))
        );
    }

    #[test]
    fn float_textures_read_every_parameter() {
        assert!(matches!(
            float(r#"Texture "t" "float" "constant" "float value" 0.25"#),
            FloatTexture::Constant(0.25)
        ));
        let mut names = TextureNames::default();
        names.floats.insert("a".into(), 3);
        let FloatTexture::Scale { tex, scale } = clean(float_in(
            r#"Texture "t" "float" "scale" "texture tex" "a" "float scale" 2"#,
            Path::new("."),
            &names,
        )) else {
            panic!("scale")
        };
        assert_eq!((tex, scale), (FloatTex::Tex(3), c(2.0)));
        let FloatTexture::Mix { tex1, tex2, amount } = float(
            r#"Texture "t" "float" "mix" "float tex1" 0.1 "float tex2" 0.2 "float amount" 0.3"#,
        ) else {
            panic!("mix")
        };
        assert_eq!((tex1, tex2, amount), (c(0.1), c(0.2), c(0.3)));
        let FloatTexture::Checkerboard {
            mapping,
            tex1,
            tex2,
        } = float(
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
        assert_eq!((mapping, tex1, tex2), (expected, c(0.7), c(0.2)));
    }

    #[test]
    fn spectrum_textures_take_pbrt_defaults_and_every_parameter() {
        let SpectrumTexture::Constant(v) = spectrum(r#"Texture "t" "spectrum" "constant""#) else {
            panic!("constant")
        };
        assert_eq!(v, Rgb::ONE);
        let SpectrumTexture::Constant(v) =
            spectrum(r#"Texture "t" "spectrum" "constant" "rgb value" [0.1 0.2 0.3]"#)
        else {
            panic!("constant")
        };
        assert_eq!(v, Rgb::new(0.1, 0.2, 0.3));
        let SpectrumTexture::Scale { tex, scale } = spectrum(r#"Texture "t" "spectrum" "scale""#)
        else {
            panic!("scale")
        };
        assert_eq!((tex, scale), (grey(1.0), c(1.0)));
        let SpectrumTexture::Scale { tex, scale } =
            spectrum(r#"Texture "t" "spectrum" "scale" "rgb tex" [0.5 0.5 0.5] "float scale" 3"#)
        else {
            panic!("scale")
        };
        assert_eq!((tex, scale), (grey(0.5), c(3.0)));
        let SpectrumTexture::Mix { tex1, tex2, amount } =
            spectrum(r#"Texture "t" "spectrum" "mix""#)
        else {
            panic!("mix")
        };
        assert_eq!((tex1, tex2, amount), (grey(0.0), grey(1.0), c(0.5)));
        let SpectrumTexture::Mix { tex1, tex2, amount } = spectrum(
            r#"Texture "t" "spectrum" "mix" "rgb tex1" [0.2 0.2 0.2] "rgb tex2" [0.4 0.4 0.4]
               "float amount" 0.9"#,
        ) else {
            panic!("mix")
        };
        assert_eq!((tex1, tex2, amount), (grey(0.2), grey(0.4), c(0.9)));
        let SpectrumTexture::Checkerboard {
            mapping,
            tex1,
            tex2,
        } = spectrum(r#"Texture "t" "spectrum" "checkerboard" "float uscale" 2"#)
        else {
            panic!("checkerboard")
        };
        assert_eq!(mapping.su, 2.0);
        assert_eq!((tex1, tex2), (grey(1.0), grey(0.0)));
    }

    #[test]
    fn what_lancer_lacks_falls_back_with_a_warning() {
        let (out, unused) = float_in(
            r#"Texture "t" "float" "wrinkled" "float roughness" 0.5"#,
            Path::new("."),
            &TextureNames::default(),
        );
        let f = out.unwrap();
        assert!(matches!(f.value, FloatTexture::Constant(1.0)));
        assert_eq!(
            f.warnings,
            ["float texture \"wrinkled\" is not supported yet; lancer uses the constant 1"]
        );
        assert_eq!(unused.len(), 1);
        let (out, _) = spectrum_in(
            r#"Texture "t" "spectrum" "marble""#,
            Path::new("."),
            &TextureNames::default(),
        );
        let f = out.unwrap();
        assert!(matches!(f.value, SpectrumTexture::Constant(v) if v == Rgb::splat(0.5)));
        assert_eq!(
            f.warnings,
            ["spectrum texture \"marble\" is not supported yet; lancer uses a constant grey 0.5"]
        );
        // A 3D checkerboard is drawn as the 2D one; then its mapping is not even looked at.
        let (out, unused) = float_in(
            r#"Texture "t" "float" "checkerboard" "integer dimension" 3 "string mapping" "spherical""#,
            Path::new("."),
            &TextureNames::default(),
        );
        assert_eq!(
            out.unwrap().warnings,
            ["a 3D checkerboard is not supported yet; lancer uses the 2D one"]
        );
        assert_eq!(unused.len(), 1);
        let (out, _) = spectrum_in(
            r#"Texture "t" "spectrum" "checkerboard" "string mapping" "spherical""#,
            Path::new("."),
            &TextureNames::default(),
        );
        assert_eq!(
            out.unwrap().warnings,
            ["texture mapping \"spherical\" is not supported yet; lancer uses \"uv\""]
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
        let dir =
            std::env::temp_dir().join(format!("lancer-textures-{test}-{}", std::process::id()));
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
            let SpectrumTexture::Image(t) = clean(spectrum_in(text, &dir, &names)) else {
                panic!("an image")
            };
            t
        };
        // PNG defaults to sRGB: 128/255 is decoded to linear.
        let t = image(r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png""#);
        let srgb = srgb_to_linear(128.0 / 255.0);
        assert!(
            (t.image.texels[0].x - srgb).abs() < 1e-6,
            "{:?}",
            t.image.texels[0]
        );
        assert_eq!(
            (t.wrap, t.scale, t.invert, t.nearest),
            (WrapMode::Repeat, 1.0, false, false)
        );
        assert_eq!(t.mapping, UvMapping::default());
        let t = image(
            r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png"
               "string encoding" "linear" "string wrap" "clamp" "string filter" "point"
               "float maxanisotropy" 4 "float scale" 2 "bool invert" true "float uscale" 3
               "string mapping" "uv""#,
        );
        assert!((t.image.texels[0].x - 128.0 / 255.0).abs() < 1e-6);
        assert_eq!(
            (t.wrap, t.scale, t.invert, t.nearest),
            (WrapMode::Clamp, 2.0, true, true)
        );
        assert_eq!(t.mapping.su, 3.0);
        let FloatTexture::Image(t) = clean(float_in(
            r#"Texture "t" "float" "imagemap" "string filename" "grey.png" "string wrap" "black""#,
            &dir,
            &names,
        )) else {
            panic!("an image")
        };
        assert_eq!(t.wrap, WrapMode::Black);
        // Filters lancer lacks and another mapping are noted in one warning.
        let (out, _) = spectrum_in(
            r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png" "string filter" "ewa"
               "string mapping" "planar""#,
            &dir,
            &names,
        );
        assert_eq!(
            out.unwrap().warnings,
            [
                "texture filter \"ewa\" is not supported yet (lancer has no ray differentials); lancer uses \"bilinear\"; \
              texture mapping \"planar\" is not supported yet; lancer uses \"uv\""
            ]
        );
        let (out, _) = spectrum_in(
            r#"Texture "t" "spectrum" "imagemap" "string filename" "grey.png" "string filter" "fancy""#,
            &dir,
            &names,
        );
        assert_eq!(
            out.unwrap().warnings,
            ["unknown texture filter \"fancy\"; lancer uses \"bilinear\""]
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
}
