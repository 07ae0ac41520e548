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
mod tests {}
