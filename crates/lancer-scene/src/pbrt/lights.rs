//! `LightSource` and `AreaLightSource`: pbrt-v4's `point`, `spot`, `distant` and `infinite`
//! lights, placed by the current transformation, and the `diffuse` area light, with pbrt-v4's
//! normalisation by `power` and `illuminance`.

use super::convert::{Fallback, Reader, locate};
use super::params::ParamList;
use super::search_path::SearchPath;
use crate::error::{Location, SceneError};
use crate::image_read::Encoding;
use lancer::light::EnvMapping;
use lancer::math::{Rgb, Transform, Vec3};
use lancer::scene::desc::{AreaLightDesc, LightDesc};
use lancer::spectrum::SpectrumKind;
use std::f32::consts::PI;

/// A light's emission: its colour (RGB passes through; spectra are normalised to luminance 1,
/// as pbrt-v4 divides `scale` by the spectrum's photometric value) times `scale`.
fn emission(params: &ParamList, name: &str, dir: &SearchPath) -> Result<Rgb, SceneError> {
    let c = params
        .color(name, SpectrumKind::Illuminant, dir)?
        .unwrap_or(Rgb::ONE);
    Ok(c * params.float("scale", 1.0)?)
}

/// The light `ty` at `loc`, placed by `ctm`; `None` for the kinds lancer skips (with their
/// warning).
pub fn light(
    r: &Reader,
    ty: &str,
    ctm: Transform,
    loc: &Location,
) -> Result<Fallback<Option<LightDesc>>, SceneError> {
    let params = r.params;
    let power = params.float("power", -1.0)?;
    let same_points = |what: &str| {
        SceneError::at(
            loc.clone(),
            format!("{what} light with \"from\" equal to \"to\""),
        )
    };
    let light = match ty {
        "point" => {
            let mut i = emission(params, "I", r.dir)?;
            if power > 0.0 {
                // Φ = 4π·I for an isotropic point light.
                i *= power / (4.0 * PI);
            }
            LightDesc::Point {
                from: ctm.point(params.point3("from", Vec3::ZERO)?),
                intensity: i,
            }
        }
        "spot" => {
            let mut i = emission(params, "I", r.dir)?;
            let cone_angle = params
                .float_checked("coneangle", 30.0, "in (0, 180]", |v| v > 0.0 && v <= 180.0)?;
            let cone_delta_angle = params.float_checked(
                "conedeltaangle",
                5.0,
                "between 0 and the cone angle",
                |v| (0.0..=cone_angle).contains(&v),
            )?;
            if power > 0.0 {
                // Φ = 2π·I·((1 − cos θ_start) + (cos θ_start − cos θ_end)/2): the smoothstep
                // falloff integrates to half its width.
                let c_end = cone_angle.to_radians().cos();
                let c_start = (cone_angle - cone_delta_angle).to_radians().cos();
                let k = 2.0 * PI * ((1.0 - c_start) + (c_start - c_end) / 2.0);
                i *= power / k;
            }
            let from = ctm.point(params.point3("from", Vec3::ZERO)?);
            let to = ctm.point(params.point3("to", Vec3::Z)?);
            if from == to {
                return Err(same_points("spot"));
            }
            LightDesc::Spot {
                from,
                to,
                intensity: i,
                cone_angle,
                cone_delta_angle,
            }
        }
        "distant" => {
            let mut l = emission(params, "L", r.dir)?;
            let w = params.point3("from", Vec3::ZERO)? - params.point3("to", Vec3::Z)?;
            let illuminance = params.float("illuminance", -1.0)?;
            if illuminance > 0.0 {
                // pbrt-v4 measures illuminance on an upward-facing patch: E = L·cos θ.
                let k = w.normalize_or_zero().y;
                if k > 0.0 {
                    l *= illuminance / k;
                }
            }
            let direction = ctm.vector(w);
            if direction == Vec3::ZERO {
                return Err(same_points("distant"));
            }
            LightDesc::Distant { direction, l }
        }
        "infinite" => return Ok(infinite(r, ctm, loc)?.map(Some)),
        "goniometric" | "projection" => {
            return Ok(Fallback::instead(
                None,
                format!("light \"{ty}\" is not supported yet; skipped"),
            ));
        }
        _ => {
            return Err(SceneError::at(
                loc.clone(),
                format!(
                    "unknown light \"{ty}\" (expected point, spot, distant, infinite, goniometric or projection)"
                ),
            ));
        }
    };
    Ok(Fallback::done(Some(light)))
}

/// pbrt-v4's `infinite` light: a uniform sky of radiance `L`, or the image `filename`
/// (equal-area octahedral, or, as a lancer extension, 2:1 latitude-longitude) times `scale`.
/// With `illuminance` E, a sky is scaled so that an upward patch receives E (L·π = E); an
/// image is scaled by E over the illuminance pbrt-v4 computes for it, which is half the
/// physical one (see `EnvMapping::pbrt_illuminance`), so that lancer matches pbrt-v4's images.
fn infinite(r: &Reader, ctm: Transform, loc: &Location) -> Result<Fallback<LightDesc>, SceneError> {
    let params = r.params;
    let illuminance = params.float("illuminance", -1.0)?;
    if !params.has("filename") {
        let mut l = emission(params, "L", r.dir)?;
        if illuminance > 0.0 {
            // A uniform sky of radiance L gives an illuminance of π·L.
            l *= illuminance / PI;
        }
        return Ok(Fallback::done(LightDesc::Infinite {
            light_to_world: ctm,
            l,
            image: None,
        }));
    }
    let at = |message: String| SceneError::at(loc.clone(), message);
    if params.has("L") {
        return Err(at(
            "an \"infinite\" light takes either \"L\" or \"filename\", not both".into(),
        ));
    }
    let mut scale = params.float("scale", 1.0)?;
    // pbrt-v4 reads environment images with their default encoding (sRGB for PNG).
    let (path, _) = r
        .image_file("an \"infinite\" light with an image")
        .map_err(|e| locate(e, loc))?;
    let image = r
        .images
        .rgb(&path, Encoding::Srgb)
        .map_err(|e| at(e.to_string()))?;
    let mapping = EnvMapping::of_size(image.width, image.height).ok_or_else(|| {
        at(format!(
            "{}: an environment image must be square (pbrt-v4's equal-area octahedral layout) or twice as wide as high (latitude-longitude), not {}×{}",
            path.display(),
            image.width,
            image.height
        ))
    })?;
    if image.texels.iter().any(|c| !c.is_finite()) {
        return Err(at(format!(
            "{}: the image has infinite or NaN values and cannot be a light",
            path.display()
        )));
    }
    let mut warnings = Vec::new();
    if illuminance > 0.0 {
        let e = mapping.pbrt_illuminance(&image);
        if e > 0.0 {
            scale *= illuminance / e;
        } else {
            warnings.push(format!(
                "{} is black above the horizon, so \"illuminance\" cannot scale it; ignored",
                path.display()
            ));
        }
    }
    if params.point3s("portal")?.is_some() {
        warnings.push(
            "infinite light portals are not supported yet; lancer samples the whole image".into(),
        );
    }
    Ok(Fallback {
        value: LightDesc::Infinite {
            light_to_world: ctm,
            l: Rgb::splat(scale),
            image: Some(image),
        },
        warnings,
    })
}

/// `AreaLightSource "diffuse"`: radiance `L` times `scale`, from one side or both
/// (`twosided`).
pub fn area_light(
    params: &ParamList,
    ty: &str,
    dir: &SearchPath,
    loc: &Location,
) -> Result<AreaLightDesc, SceneError> {
    if ty != "diffuse" {
        return Err(SceneError::at(
            loc.clone(),
            format!("unknown area light \"{ty}\" (expected \"diffuse\")"),
        ));
    }
    Ok(AreaLightDesc {
        l: emission(params, "L", dir)?,
        two_sided: params.bool("twosided", false)?,
    })
}

#[cfg(test)]
mod tests {}
