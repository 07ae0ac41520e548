//! The rendering options: `Film`, `Sampler`, `PixelFilter`, `Integrator` and `Option`, with
//! pbrt-v4's defaults. Kinds lancer does not have fall back to its nearest one, with a warning.

use super::convert::{Fallback, MAX_RESOLUTION};
use super::params::ParamList;
use crate::error::SceneError;
use lancer::sampling::SamplerKind;
use lancer::scene::desc::{FilmDesc, FilterDesc, IntegratorDesc};

/// What `Film` sets: the film, and the sensor's ISO (the imaging ratio is exposure time ×
/// ISO / 100, known once the camera's shutter is).
#[derive(Clone, Debug)]
pub struct FilmOptions {
    /// The film (its `scale` is left for the builder to set).
    pub film: FilmDesc,
    /// `iso`.
    pub iso: f32,
}

/// The film `ty`, over `film` (what earlier directives set).
pub fn film(
    params: &ParamList,
    ty: &str,
    mut film: FilmDesc,
) -> Result<Fallback<FilmOptions>, SceneError> {
    let mut warnings = Vec::new();
    if ty != "rgb" {
        warnings.push(format!(
            "film \"{ty}\" is not supported yet; lancer uses an \"rgb\" film"
        ));
    }
    film.xresolution = params.int_in("xresolution", 1280, 1..=MAX_RESOLUTION)? as u32;
    film.yresolution = params.int_in("yresolution", 720, 1..=MAX_RESOLUTION)? as u32;
    film.filename = params.string("filename")?;
    if let Some(c) = params.floats("cropwindow")? {
        let ok =
            c.len() == 4 && c.iter().all(|v| (0.0..=1.0).contains(v)) && c[0] < c[1] && c[2] < c[3];
        if !ok {
            return Err(params.error_at(
                "cropwindow",
                "\"float cropwindow\" needs 4 numbers in [0, 1]: xmin xmax ymin ymax, with min < max",
            ));
        }
        film.crop_window = [c[0], c[1], c[2], c[3]];
    }
    if let Some((b, bloc)) = params.ints("pixelbounds")? {
        if b.len() != 4 || b[0] >= b[1] || b[2] >= b[3] {
            return Err(SceneError::at(
                bloc,
                "\"integer pixelbounds\" needs 4 numbers: x0 x1 y0 y1, with x0 < x1 and y0 < y1",
            ));
        }
        film.pixel_bounds = Some([b[0], b[1], b[2], b[3]]);
    }
    let iso = params.float_checked("iso", 100.0, "positive", |v| v > 0.0)?;
    film.max_component_value =
        params.float_checked("maxcomponentvalue", f32::INFINITY, "positive", |v| v > 0.0)?;
    film.save_fp16 = params.bool("savefp16", false)?;
    // Only the realistic camera uses the sensor's diagonal.
    let _ = params.float("diagonal", 35.0)?;
    let sensor = params.string("sensor")?.unwrap_or_else(|| "cie1931".into());
    let white_balance = params.float("whitebalance", 0.0)?;
    if sensor != "cie1931" || white_balance != 0.0 {
        warnings.push(
            "camera sensors and white balance are not supported yet; lancer uses the CIE 1931 observer without white balance".into(),
        );
    }
    Ok(Fallback {
        value: FilmOptions { film, iso },
        warnings,
    })
}

/// A `seed` (of `Option` or `Sampler`), if given; pbrt-v4 reads it as a 32-bit integer.
pub fn seed(params: &ParamList) -> Result<Option<u64>, SceneError> {
    if !params.has("seed") {
        return Ok(None);
    }
    Ok(Some(params.int("seed", 0)? as u32 as u64))
}

/// What `Sampler` sets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplerOptions {
    /// The point set.
    pub kind: SamplerKind,
    /// Samples per pixel.
    pub spp: u32,
    /// `seed`, if given (it overrides `Option "seed"`).
    pub seed: Option<u64>,
}

/// The sampler `ty`: its point set, samples per pixel and seed.
pub fn sampler(params: &ParamList, ty: &str) -> Result<Fallback<SamplerOptions>, SceneError> {
    let p = params;
    let spp =
        || -> Result<u32, SceneError> { Ok(p.int_in("pixelsamples", 16, 1..=1 << 24)? as u32) };
    let (kind, spp, warning) = match ty {
        "independent" => (SamplerKind::Independent, spp()?, None),
        "stratified" => {
            let x = p.int_in("xsamples", 4, 1..=4096)? as u32;
            let y = p.int_in("ysamples", 4, 1..=4096)? as u32;
            let jitter = p.bool("jitter", true)?;
            let kind = SamplerKind::Stratified {
                xsamples: x,
                ysamples: y,
                jitter,
            };
            (kind, x * y, None)
        }
        "sobol" | "zsobol" | "paddedsobol" => {
            let _ = p.string("randomization")?;
            (SamplerKind::Sobol, spp()?, None)
        }
        "halton" | "pmj02bn" => {
            let _ = p.string("randomization")?;
            let w = format!("sampler \"{ty}\" is not supported yet; lancer uses \"zsobol\"");
            (SamplerKind::Sobol, spp()?, Some(w))
        }
        _ => {
            let w = format!("unknown sampler \"{ty}\"; lancer uses \"zsobol\"");
            (SamplerKind::Sobol, spp()?, Some(w))
        }
    };
    let options = SamplerOptions {
        kind,
        spp,
        seed: seed(p)?,
    };
    Ok(match warning {
        None => Fallback::done(options),
        Some(w) => Fallback::instead(options, w),
    })
}

/// The pixel filter `ty`, with pbrt-v4's default radii.
pub fn filter(params: &ParamList, ty: &str) -> Result<Fallback<FilterDesc>, SceneError> {
    let p = params;
    let radius = |d: f32| -> Result<[f32; 2], SceneError> {
        let ok = |v: f32| v > 0.0 && v <= 64.0;
        Ok([
            p.float_checked("xradius", d, "in (0, 64]", ok)?,
            p.float_checked("yradius", d, "in (0, 64]", ok)?,
        ])
    };
    let f = match ty {
        "box" => FilterDesc::Box {
            radius: radius(0.5)?,
        },
        "gaussian" => FilterDesc::Gaussian {
            radius: radius(1.5)?,
            sigma: p.float_checked("sigma", 0.5, "positive", |v| v > 0.0)?,
        },
        "triangle" => FilterDesc::Triangle {
            radius: radius(2.0)?,
        },
        "mitchell" => FilterDesc::Mitchell {
            radius: radius(2.0)?,
            b: p.float("B", 1.0 / 3.0)?,
            c: p.float("C", 1.0 / 3.0)?,
        },
        "sinc" | "lanczos" => FilterDesc::Lanczos {
            radius: radius(4.0)?,
            tau: p.float_checked("tau", 3.0, "positive", |v| v > 0.0)?,
        },
        _ => {
            return Ok(Fallback::instead(
                FilterDesc::default(),
                format!("unknown pixel filter \"{ty}\"; lancer uses \"gaussian\""),
            ));
        }
    };
    Ok(Fallback::done(f))
}

/// The integrator `ty`, with pbrt-v4's defaults (`maxdepth` 5); the others fall back to
/// `path`.
pub fn integrator(params: &ParamList, ty: &str) -> Result<Fallback<IntegratorDesc>, SceneError> {
    let p = params;
    let max_depth = p.int_in("maxdepth", 5, 0..=100_000)? as u32;
    let path = || -> Result<IntegratorDesc, SceneError> {
        Ok(IntegratorDesc::Path {
            max_depth,
            regularize: p.bool("regularize", false)?,
        })
    };
    let i = match ty {
        "whitted" => IntegratorDesc::Whitted { max_depth },
        "path" | "volpath" => {
            // The light sampler is lancer's own; pbrt's choice needs no warning.
            let _ = p.string("lightsampler")?;
            path()?
        }
        "ambientocclusion" => IntegratorDesc::AmbientOcclusion {
            cos_sample: p.bool("cossample", true)?,
            max_distance: p.float("maxdistance", f32::INFINITY)?,
        },
        "normals" => IntegratorDesc::Normals,
        "depth" => IntegratorDesc::Depth,
        "bdpt" | "mlt" | "sppm" | "lightpath" | "randomwalk" | "simplepath" | "simplevolpath"
        | "aov" => {
            return Ok(Fallback::instead(
                path()?,
                format!(
                    "integrator \"{ty}\" is not supported yet; lancer uses \"path\" with maxdepth {max_depth}"
                ),
            ));
        }
        _ => {
            return Ok(Fallback::instead(
                path()?,
                format!("unknown integrator \"{ty}\"; lancer uses \"path\""),
            ));
        }
    };
    Ok(Fallback::done(i))
}

#[cfg(test)]
mod tests {}
