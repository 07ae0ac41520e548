//! `Texture`: pbrt-v4's float and spectrum textures as lancer's [`FloatTextureDesc`] and
//! [`SpectrumTextureDesc`]: `constant`, `scale`, `mix`, `directionmix`, `checkerboard` (2D and 3D),
//! `bilerp`, `dots`, `imagemap`, `fbm`, `wrinkled`, `windy` and `marble`, with the 2D mappings
//! `uv`, `spherical`, `cylindrical` and `planar`. Texture space is the CTM at the directive.

use super::convert::{Fallback, Reader, TextureNames, locate};
use super::params::{ColorParam, ParamList, ParamType, Values};
use crate::error::{Location, SceneError};
use lancer::math::{Rgb, Transform, Vec3};
use lancer::spectrum::SpectrumKind;
use lancer::texture::{
    BilerpTexture, Checkerboard3DTexture, CheckerboardTexture, DirectionMixTexture, DotsTexture,
    FbmTexture, FloatTex, FloatTextureDesc, ImageFilter, ImageTextureDesc, Mapping2D, Mapping3D,
    MarbleTexture, MixTexture, ScaleTexture, SpectrumTex, SpectrumTextureDesc, UvMapping,
    WindyTexture, WrapMode, WrinkledTexture,
};

/// The float texture of class `class` at `loc`, with texture space `ctm` (world from texture);
/// an unknown class becomes the constant 1.
pub fn float_texture(
    r: &Reader,
    class: &str,
    ctm: &Transform,
    loc: &Location,
) -> Result<Fallback<FloatTextureDesc>, SceneError> {
    float(r, class, ctm).map_err(|e| locate(e, loc))
}

/// The spectrum texture of class `class` at `loc`, with texture space `ctm` (world from
/// texture); an unknown class becomes a constant grey.
pub fn spectrum_texture(
    r: &Reader,
    class: &str,
    ctm: &Transform,
    loc: &Location,
) -> Result<Fallback<SpectrumTextureDesc>, SceneError> {
    spectrum_texture_as(r, class, ctm, loc, SpectrumKind::Albedo)
}

/// [`spectrum_texture`] with its spectrum-valued parameters (and the textures it refers to)
/// read as `kind`: pbrt-v4 makes each spectrum texture once per spectrum type
/// (`SpectrumType::Albedo`, clamped to [0, 1], and `Unbounded`), and a material reads the one
/// its parameter's type asks for (a conductor's `eta` and `k`: unbounded).
pub fn spectrum_texture_as(
    r: &Reader,
    class: &str,
    ctm: &Transform,
    loc: &Location,
    kind: SpectrumKind,
) -> Result<Fallback<SpectrumTextureDesc>, SceneError> {
    spectrum(r, class, ctm, kind).map_err(|e| locate(e, loc))
}

/// Whether a spectrum texture with `params` reads differently as an unbounded spectrum than
/// as an albedo: it has a `spectrum` or `blackbody` parameter (an albedo clamps those to
/// [0, 1]) or refers to a texture that does. RGB values and images are clamped only where a
/// material reads them as albedos, so they need no variant.
pub fn needs_unbounded_variant(params: &ParamList, names: &TextureNames) -> bool {
    params.iter().any(|p| match (p.ty, &p.values) {
        (ParamType::Spectrum | ParamType::Blackbody, _) => true,
        (ParamType::Texture, Values::Strings(v)) => {
            v.iter().any(|n| names.unbounded.contains_key(n))
        }
        _ => false,
    })
}

/// pbrt-v4's 3D mapping: texture space is the CTM at the `Texture` directive.
fn mapping_3d(ctm: &Transform) -> Mapping3D {
    Mapping3D {
        texture_from_world: ctm.inverse(),
    }
}

/// `octaves` (default 8) and `roughness` (default 0.5) of the noise textures.
fn octaves_roughness(r: &Reader) -> Result<(u32, f32), SceneError> {
    Ok((
        r.params.int_in("octaves", 8, 0..=64)? as u32,
        r.params.float("roughness", 0.5)?,
    ))
}

/// `dir` (default +y) of `directionmix`, moved to world space by the CTM and normalised.
fn direction(r: &Reader, ctm: &Transform) -> Result<Vec3, SceneError> {
    let d = ctm.vector(r.params.vector3("dir", Vec3::Y)?);
    if d.length_squared() == 0.0 || !d.is_finite() {
        return Err(r
            .params
            .error_at("dir", "\"dir\" of a directionmix must not be zero"));
    }
    Ok(lancer::math::normalize(d))
}

/// The `dimension` of a checkerboard: 2 or 3.
fn dimension(r: &Reader) -> Result<i32, SceneError> {
    let dim = r.params.int("dimension", 2)?;
    if dim != 2 && dim != 3 {
        return Err(r.params.error_at(
            "dimension",
            format!("a {dim}-dimensional checkerboard is not supported (pbrt-v4 has 2 and 3)"),
        ));
    }
    Ok(dim)
}

fn float(
    r: &Reader,
    class: &str,
    ctm: &Transform,
) -> Result<Fallback<FloatTextureDesc>, SceneError> {
    let p = r.params;
    let t = match class {
        "constant" => FloatTextureDesc::Constant(p.float("value", 1.0)?),
        "scale" => FloatTextureDesc::Scale(ScaleTexture {
            tex: r.float_tex("tex", 1.0)?,
            scale: r.float_tex("scale", 1.0)?,
        }),
        "mix" => FloatTextureDesc::Mix(MixTexture {
            tex1: r.float_tex("tex1", 0.0)?,
            tex2: r.float_tex("tex2", 1.0)?,
            amount: r.float_tex("amount", 0.5)?,
        }),
        "directionmix" => FloatTextureDesc::DirectionMix(DirectionMixTexture {
            tex1: r.float_tex("tex1", 0.0)?,
            tex2: r.float_tex("tex2", 1.0)?,
            dir: direction(r, ctm)?,
        }),
        "checkerboard" => {
            let (tex1, tex2) = (r.float_tex("tex1", 1.0)?, r.float_tex("tex2", 0.0)?);
            if dimension(r)? == 3 {
                FloatTextureDesc::Checkerboard3D(Checkerboard3DTexture {
                    mapping: mapping_3d(ctm),
                    tex1,
                    tex2,
                })
            } else {
                FloatTextureDesc::Checkerboard(CheckerboardTexture {
                    mapping: mapping_2d(r, ctm)?,
                    tex1,
                    tex2,
                })
            }
        }
        "bilerp" => FloatTextureDesc::Bilerp(BilerpTexture {
            mapping: mapping_2d(r, ctm)?,
            v: [
                p.float("v00", 0.0)?,
                p.float("v01", 1.0)?,
                p.float("v10", 0.0)?,
                p.float("v11", 1.0)?,
            ],
        }),
        // pbrt-v4's Create passes (inside, outside) to a constructor declared (outsideDot,
        // insideDot): `inside` colours the background, `outside` the dots.
        "dots" => FloatTextureDesc::Dots(DotsTexture {
            mapping: mapping_2d(r, ctm)?,
            background: r.float_tex("inside", 1.0)?,
            dot: r.float_tex("outside", 0.0)?,
        }),
        "fbm" => {
            let (octaves, omega) = octaves_roughness(r)?;
            FloatTextureDesc::Fbm(FbmTexture {
                mapping: mapping_3d(ctm),
                octaves,
                omega,
            })
        }
        "wrinkled" => {
            let (octaves, omega) = octaves_roughness(r)?;
            FloatTextureDesc::Wrinkled(WrinkledTexture {
                mapping: mapping_3d(ctm),
                octaves,
                omega,
            })
        }
        "windy" => FloatTextureDesc::Windy(WindyTexture {
            mapping: mapping_3d(ctm),
        }),
        "imagemap" => return Ok(image_texture(r, ctm, true)?.map(FloatTextureDesc::Image)),
        _ => {
            return Ok(Fallback::instead(
                FloatTextureDesc::Constant(1.0),
                format!(
                    "float texture \"{class}\" is not supported yet; lancer uses the constant 1"
                ),
            ));
        }
    };
    Ok(Fallback::done(t))
}

fn spectrum(
    r: &Reader,
    class: &str,
    ctm: &Transform,
    kind: SpectrumKind,
) -> Result<Fallback<SpectrumTextureDesc>, SceneError> {
    // Every spectrum-valued parameter is read as `kind` (see `spectrum_texture_as`).
    let t = match class {
        // A value given as a spectrum stays one (spectral mode samples its table): lancer's
        // constant texture holds RGB, so it is the spectrum scaled by 1.
        "constant" => match r.params.color_or_texture("value", kind, r.dir)? {
            Some(ColorParam::Measured(m)) => SpectrumTextureDesc::Scale(ScaleTexture {
                tex: SpectrumTex::Measured(m),
                scale: FloatTex::Const(1.0),
            }),
            _ => SpectrumTextureDesc::Constant(
                r.params.color("value", kind, r.dir)?.unwrap_or(Rgb::ONE),
            ),
        },
        "scale" => SpectrumTextureDesc::Scale(ScaleTexture {
            tex: r.spectrum_tex("tex", Rgb::ONE, kind)?,
            scale: r.float_tex("scale", 1.0)?,
        }),
        "mix" => SpectrumTextureDesc::Mix(MixTexture {
            tex1: r.spectrum_tex("tex1", Rgb::ZERO, kind)?,
            tex2: r.spectrum_tex("tex2", Rgb::ONE, kind)?,
            amount: r.float_tex("amount", 0.5)?,
        }),
        "directionmix" => SpectrumTextureDesc::DirectionMix(DirectionMixTexture {
            tex1: r.spectrum_tex("tex1", Rgb::ZERO, kind)?,
            tex2: r.spectrum_tex("tex2", Rgb::ONE, kind)?,
            dir: direction(r, ctm)?,
        }),
        "checkerboard" => {
            let tex1 = r.spectrum_tex("tex1", Rgb::ONE, kind)?;
            let tex2 = r.spectrum_tex("tex2", Rgb::ZERO, kind)?;
            if dimension(r)? == 3 {
                SpectrumTextureDesc::Checkerboard3D(Checkerboard3DTexture {
                    mapping: mapping_3d(ctm),
                    tex1,
                    tex2,
                })
            } else {
                SpectrumTextureDesc::Checkerboard(CheckerboardTexture {
                    mapping: mapping_2d(r, ctm)?,
                    tex1,
                    tex2,
                })
            }
        }
        "bilerp" => {
            let c = |name, default| -> Result<Rgb, SceneError> {
                Ok(r.params.color(name, kind, r.dir)?.unwrap_or(default))
            };
            SpectrumTextureDesc::Bilerp(BilerpTexture {
                mapping: mapping_2d(r, ctm)?,
                v: [
                    c("v00", Rgb::ZERO)?,
                    c("v01", Rgb::ONE)?,
                    c("v10", Rgb::ZERO)?,
                    c("v11", Rgb::ONE)?,
                ],
            })
        }
        // pbrt-v4 swaps them (see the float `dots`).
        "dots" => SpectrumTextureDesc::Dots(DotsTexture {
            mapping: mapping_2d(r, ctm)?,
            background: r.spectrum_tex("inside", Rgb::ONE, kind)?,
            dot: r.spectrum_tex("outside", Rgb::ZERO, kind)?,
        }),
        "marble" => {
            let (octaves, omega) = octaves_roughness(r)?;
            SpectrumTextureDesc::Marble(MarbleTexture {
                mapping: mapping_3d(ctm),
                octaves,
                omega,
                scale: r.params.float("scale", 1.0)?,
                variation: r.params.float("variation", 0.2)?,
            })
        }
        "imagemap" => return Ok(image_texture(r, ctm, false)?.map(SpectrumTextureDesc::Image)),
        _ => {
            return Ok(Fallback::instead(
                SpectrumTextureDesc::Constant(Rgb::splat(0.5)),
                format!(
                    "spectrum texture \"{class}\" is not supported yet; lancer uses a constant grey 0.5"
                ),
            ));
        }
    };
    Ok(Fallback::done(t))
}

/// pbrt-v4's `TextureMapping2D::Create`: `mapping` (default `uv`) and its parameters; the
/// others map through texture space, the inverse of the CTM at the directive.
fn mapping_2d(r: &Reader, ctm: &Transform) -> Result<Mapping2D, SceneError> {
    let p = r.params;
    let kind = p.string("mapping")?.unwrap_or_else(|| "uv".to_string());
    let texture_from_world = ctm.inverse();
    Ok(match kind.as_str() {
        "uv" => Mapping2D::Uv(UvMapping {
            su: p.float("uscale", 1.0)?,
            sv: p.float("vscale", 1.0)?,
            du: p.float("udelta", 0.0)?,
            dv: p.float("vdelta", 0.0)?,
        }),
        "spherical" => Mapping2D::Spherical { texture_from_world },
        "cylindrical" => Mapping2D::Cylindrical { texture_from_world },
        "planar" => Mapping2D::Planar {
            texture_from_world,
            vs: p.vector3("v1", Vec3::X)?,
            vt: p.vector3("v2", Vec3::Y)?,
            ds: p.float("udelta", 0.0)?,
            dt: p.float("vdelta", 0.0)?,
        },
        other => {
            return Err(p.error_at(
                "mapping",
                format!(
                    "unknown texture mapping \"{other}\" (expected \"uv\", \"spherical\", \"cylindrical\" or \"planar\")"
                ),
            ));
        }
    })
}

/// pbrt-v4's `imagemap`: the image's texels (which the scene build makes a MIP pyramid of),
/// its wrap mode and filter (`filter`, default `bilinear` as in pbrt-v4; `maxanisotropy` for
/// `ewa`), `scale`, `invert` and the 2D mapping. Float textures read the value pbrt-v4's
/// MIPMap gives (see [`crate::image_read::DecodedImage::float_image`]).
fn image_texture(
    r: &Reader,
    ctm: &Transform,
    float: bool,
) -> Result<Fallback<ImageTextureDesc>, SceneError> {
    let p = r.params;
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
    let filter = match p.string("filter")?.as_deref().unwrap_or("bilinear") {
        "point" => ImageFilter::Point,
        "bilinear" => ImageFilter::Bilinear,
        "trilinear" => ImageFilter::Trilinear,
        "ewa" | "EWA" => ImageFilter::Ewa {
            max_anisotropy: p.float("maxanisotropy", 8.0)?,
        },
        other => {
            return Err(p.error_at(
                "filter",
                format!(
                    "unknown texture filter \"{other}\" (expected \"point\", \"bilinear\", \"trilinear\" or \"ewa\")"
                ),
            ));
        }
    };
    // pbrt-v4 reads `maxanisotropy` whatever the filter.
    p.float("maxanisotropy", 8.0)?;
    // A float texture of a colour image: pbrt-v4's point and EWA lookups read the first
    // channel (`MIPMap::Texel<Float>`), bilinear and trilinear the average of R, G, B (alpha
    // if there is one, `MIPMap::Bilerp<Float>`).
    let first_channel = matches!(filter, ImageFilter::Point | ImageFilter::Ewa { .. });
    let read = |e: crate::image_read::ImageReadError| SceneError::general(e.to_string());
    // The texels the texture reads, shared with every texture of the same file; an RGB
    // image's colour space goes with them (its pyramid clamps in it), a float image's pyramid
    // clamps its one value at 0 as it is.
    let (image, to_srgb) = if float {
        let image = r
            .images
            .float(&path, encoding, first_channel)
            .map_err(read)?;
        (image, None)
    } else {
        let decoded = r.images.decoded(&path, encoding).map_err(read)?;
        (decoded.rgb.clone(), decoded.to_srgb)
    };
    let t = ImageTextureDesc {
        image,
        to_srgb,
        mip: true,
        mapping: mapping_2d(r, ctm)?,
        wrap,
        scale: p.float("scale", 1.0)?,
        invert: p.bool("invert", false)?,
        filter,
    };
    Ok(Fallback::done(t))
}

#[cfg(test)]
mod tests;
