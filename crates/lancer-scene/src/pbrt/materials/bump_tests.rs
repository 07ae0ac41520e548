//! Tests of the bump and normal maps every material reads (`displacement`, `normalmap`).

use super::*;
use crate::pbrt::convert::TextureNames;
use crate::pbrt::convert::testing::{err, typed_in, unused, with_textures};
use std::path::{Path, PathBuf};

/// A fresh folder holding `n.png`, a 1×1 8-bit PNG of colour (128, 128, 255).
fn folder_with_normal_map(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lancer-bump-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = std::fs::File::create(dir.join("n.png")).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), 1, 1);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()
        .unwrap()
        .write_image_data(&[128, 128, 255])
        .unwrap();
    dir
}

type Converted = (Result<Fallback<MaterialWithNames>, SceneError>, Vec<String>);

fn convert_in(text: &str, dir: &Path, textures: &TextureNames) -> Converted {
    let (ty, params, loc) = typed_in(text, dir);
    let out = with_textures(&params, dir, textures, |r| material(r, &ty, &loc));
    (out, unused(&params))
}

#[test]
fn displacement_and_normalmap_are_read_on_every_material() {
    let dir = folder_with_normal_map("read");
    let mut names = TextureNames::default();
    names.floats.insert("h".into(), 2);
    for ty in ["diffuse", "conductor", "dielectric", "coateddiffuse"] {
        let (out, unused) = convert_in(
            &format!(r#"Material "{ty}" "texture displacement" "h" "string normalmap" "n.png""#),
            &dir,
            &names,
        );
        let m = out.unwrap();
        assert!(
            m.warnings.is_empty() && unused.is_empty(),
            "{ty}: {unused:?}"
        );
        let b = m.value.bump.expect("bump maps");
        assert_eq!(b.displacement, Some(FloatTex::Tex(2)));
        // Read linear, whatever the PNG's default: 128/255, not its sRGB decoding.
        let t = b.normal_map.expect("normal map");
        assert!((t.image.texels[0].x - 128.0 / 255.0).abs() < 1e-6);
        // pbrt-v4 reads normal maps bilinearly, without a pyramid.
        assert!(!t.mip);
        assert!(
            (t.wrap, t.filter, t.scale)
                == (
                    WrapMode::Repeat,
                    lancer::texture::ImageFilter::Bilinear,
                    1.0
                )
        );
    }
    // Without either: no wrapper.
    let (out, _) = convert_in(r#"Material "diffuse""#, &dir, &names);
    assert!(out.unwrap().value.bump.is_none());
    // A mix has none of its own (pbrt-v4 reports them unused).
    let (out, unused) = convert_in(
        r#"Material "mix" "string materials" ["a" "b"] "texture displacement" "h""#,
        &dir,
        &names,
    );
    assert!(out.unwrap().value.bump.is_none());
    assert_eq!(unused.len(), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_missing_normal_map_is_an_error_at_its_parameter() {
    let dir = folder_with_normal_map("missing");
    let (out, _) = convert_in(
        "Material \"diffuse\"\n  \"string normalmap\" \"nope.png\"",
        &dir,
        &TextureNames::default(),
    );
    let e = err(out);
    assert!(
        e.starts_with("t.pbrt:2:3: ") && e.contains("nope.png"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
