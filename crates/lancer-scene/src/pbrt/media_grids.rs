//! pbrt-v4's heterogeneous media from `MakeNamedMedium` parameters: `uniformgrid`, `rgbgrid`,
//! `cloud` and `nanovdb` (pbrt-v4's `GridMedium::Create`, `RGBGridMedium::Create`,
//! `CloudMedium::Create` and `NanoVDBMedium::Create`), placed by the CTM at the directive.
//!
//! Coefficients given as spectra are reduced to RGB here (σ as unbounded quantities, `Le` as an
//! illuminant of luminance 1, pbrt-v4's photometric normalisation); the renderer turns them
//! back into spectra at each path's wavelengths.

use super::convert::locate;
use super::params::ParamList;
use super::search_path::SearchPath;
use crate::error::{Location, SceneError};
use lancer::math::{Bounds3, Rgb, Transform, Vec3};
use lancer::medium::cloud::CloudDesc;
use lancer::medium::grid::SampledGrid;
use lancer::medium::grids::GridMediumDesc;
use lancer::medium::nanovdb::NanoVdbDesc;
use lancer::medium::rgb_grid::RgbGridDesc;
use lancer::medium::uniform_grid::UniformGridDesc;
use lancer::spectrum::SpectrumKind;

/// The medium types this file converts.
pub const GRID_MEDIA: [&str; 4] = ["uniformgrid", "rgbgrid", "cloud", "nanovdb"];

/// Most samples a grid given in a scene file may have (2²⁸).
const MAX_SAMPLES: i64 = 1 << 28;

/// The medium of type `ty` made by the directive at `loc` with `params`, placed by `ctm`
/// (medium space → render space); `Ok(None)` if `ty` is not a grid medium. Relative file names
/// resolve through `dir`.
pub fn grid_medium(
    params: &ParamList,
    ty: &str,
    ctm: Transform,
    dir: &SearchPath,
    loc: &Location,
) -> Result<Option<GridMediumDesc>, SceneError> {
    let desc = match ty {
        "uniformgrid" => uniform_grid(params, ctm, dir),
        "rgbgrid" => rgb_grid(params, ctm),
        "cloud" => cloud(params, ctm, dir),
        "nanovdb" => nanovdb(params, ctm, dir),
        _ => return Ok(None),
    };
    desc.map(Some).map_err(|e| locate(e, loc))
}

/// σ_a or σ_s: a colour or spectrum reduced as unbounded, 1 when absent.
fn sigma(params: &ParamList, name: &str, dir: &SearchPath) -> Result<Rgb, SceneError> {
    Ok(params
        .color(name, SpectrumKind::Unbounded, dir)?
        .unwrap_or(Rgb::ONE))
}

/// The box `p0`–`p1` (default the unit cube).
fn bounds(params: &ParamList) -> Result<Bounds3, SceneError> {
    let p0 = params.point3("p0", Vec3::ZERO)?;
    let p1 = params.point3("p1", Vec3::ONE)?;
    Ok(Bounds3::new(p0, p1))
}

/// `nx`, `ny`, `nz` (default 1 each), checked: positive, at most [`MAX_SAMPLES`] in all.
fn resolution(params: &ParamList) -> Result<(i32, i32, i32, usize), SceneError> {
    let mut n = [0i32; 3];
    for (v, name) in n.iter_mut().zip(["nx", "ny", "nz"]) {
        *v = params.int(name, 1)?;
        if *v < 1 {
            return Err(params.error_at(
                name,
                format!("\"integer {name}\" must be at least 1, not {v}"),
            ));
        }
    }
    let total = n.iter().map(|&v| v as i64).product::<i64>();
    if total > MAX_SAMPLES {
        return Err(params.error_at(
            "nx",
            format!(
                "a grid of {} × {} × {} samples is too large (at most {MAX_SAMPLES})",
                n[0], n[1], n[2]
            ),
        ));
    }
    Ok((n[0], n[1], n[2], total as usize))
}

/// `temperatureoffset`, or pbrt-v4's older name `temperaturecutoff`, default 0.
fn temperature_offset(params: &ParamList) -> Result<f32, SceneError> {
    let cutoff = params.float("temperaturecutoff", 0.0)?;
    params.float("temperatureoffset", cutoff)
}

fn uniform_grid(
    params: &ParamList,
    ctm: Transform,
    dir: &SearchPath,
) -> Result<GridMediumDesc, SceneError> {
    let Some(density) = params.floats("density")? else {
        return Err(SceneError::general(
            "no \"density\" value provided for grid medium",
        ));
    };
    let (nx, ny, nz, n) = resolution(params)?;
    if density.len() != n {
        return Err(params.error_at(
            "density",
            format!(
                "grid medium has {} density values; expected nx·ny·nz = {n}",
                density.len()
            ),
        ));
    }
    let temperature = params.floats("temperature")?;
    if let Some(t) = &temperature
        && t.len() != density.len()
    {
        return Err(params.error_at(
            "temperature",
            format!(
                "different number of samples ({} vs {}) provided for \"density\" and \"temperature\"",
                density.len(),
                t.len()
            ),
        ));
    }
    let le = params.color("Le", SpectrumKind::Illuminant, dir)?;
    if le.is_some() && temperature.is_some() {
        return Err(params.error_at("Le", "both \"Le\" and \"temperature\" values were provided"));
    }
    let le_scale = match params.floats("Lescale")? {
        None => vec![1.0],
        Some(v) if v.len() == n => v,
        Some(v) => {
            return Err(params.error_at(
                "Lescale",
                format!(
                    "expected {nx} × {ny} × {nz} = {n} values for \"Lescale\" but were given {}",
                    v.len()
                ),
            ));
        }
    };
    let (lx, ly, lz) = if le_scale.len() == 1 && n != 1 {
        (1, 1, 1)
    } else {
        (nx, ny, nz)
    };
    let grid = |v: Vec<f32>, x, y, z| SampledGrid::new(v, x, y, z).expect("sizes checked");
    Ok(GridMediumDesc::Uniform(UniformGridDesc {
        medium_to_render: ctm,
        bounds: bounds(params)?,
        sigma_a: sigma(params, "sigma_a", dir)?,
        sigma_s: sigma(params, "sigma_s", dir)?,
        scale: params.float("scale", 1.0)?,
        g: params.float("g", 0.0)?,
        density: grid(density, nx, ny, nz),
        temperature: temperature.map(|t| grid(t, nx, ny, nz)),
        temperature_scale: params.float("temperaturescale", 1.0)?,
        temperature_offset: temperature_offset(params)?,
        le: le.unwrap_or(Rgb::ZERO),
        le_scale: grid(le_scale, lx, ly, lz),
    }))
}

fn rgb_grid(params: &ParamList, ctm: Transform) -> Result<GridMediumDesc, SceneError> {
    let sigma_a = params.rgbs("sigma_a")?;
    let sigma_s = params.rgbs("sigma_s")?;
    let le = params.rgbs("Le")?;
    let n_density = match (&sigma_a, &sigma_s) {
        (None, None) => {
            return Err(SceneError::general(
                "RGB grid requires \"sigma_a\" and/or \"sigma_s\" parameter values",
            ));
        }
        (Some((a, _)), Some((s, l))) if a.len() != s.len() => {
            return Err(SceneError::at(
                l.clone(),
                format!(
                    "different number of samples ({} vs {}) provided for \"sigma_a\" and \"sigma_s\"",
                    a.len(),
                    s.len()
                ),
            ));
        }
        (Some((a, _)), _) => a.len(),
        (None, Some((s, _))) => s.len(),
    };
    if let Some((l, at)) = &le {
        if sigma_a.is_none() {
            return Err(SceneError::at(
                at.clone(),
                "RGB grid requires \"sigma_a\" if \"Le\" value provided",
            ));
        }
        if l.len() != n_density {
            return Err(SceneError::at(
                at.clone(),
                format!(
                    "expected {n_density} values for \"Le\" parameter but were given {}",
                    l.len()
                ),
            ));
        }
    }
    let (nx, ny, nz, n) = resolution(params)?;
    if n_density != n {
        let at = sigma_a
            .as_ref()
            .or(sigma_s.as_ref())
            .map(|(_, l)| l.clone());
        let message =
            format!("RGB grid medium has {n_density} density values; expected nx·ny·nz = {n}");
        return Err(match at {
            Some(l) => SceneError::at(l, message),
            None => SceneError::general(message),
        });
    }
    let grid = |g: Option<(Vec<Rgb>, Location)>| {
        g.map(|(v, _)| SampledGrid::new(v, nx, ny, nz).expect("sizes checked"))
    };
    Ok(GridMediumDesc::Rgb(RgbGridDesc {
        medium_to_render: ctm,
        bounds: bounds(params)?,
        g: params.float("g", 0.0)?,
        sigma_a: grid(sigma_a),
        sigma_s: grid(sigma_s),
        scale: params.float("scale", 1.0)?,
        le: grid(le),
        le_scale: params.float("Lescale", 1.0)?,
    }))
}

fn cloud(
    params: &ParamList,
    ctm: Transform,
    dir: &SearchPath,
) -> Result<GridMediumDesc, SceneError> {
    Ok(GridMediumDesc::Cloud(CloudDesc {
        medium_to_render: ctm,
        bounds: bounds(params)?,
        sigma_a: sigma(params, "sigma_a", dir)?,
        sigma_s: sigma(params, "sigma_s", dir)?,
        g: params.float("g", 0.0)?,
        density: params.float("density", 1.0)?,
        wispiness: params.float("wispiness", 1.0)?,
        frequency: params.float("frequency", 5.0)?,
    }))
}

fn nanovdb(
    params: &ParamList,
    ctm: Transform,
    dir: &SearchPath,
) -> Result<GridMediumDesc, SceneError> {
    let Some(filename) = params.string("filename")? else {
        return Err(SceneError::general(
            "must supply \"filename\" to \"nanovdb\" medium",
        ));
    };
    let path = dir.resolve(&filename);
    crate::files_read::record(&path);
    let at = |m: String| params.error_at("filename", m);
    let data =
        std::fs::read(&path).map_err(|e| at(format!("cannot read {}: {e}", path.display())))?;
    let gridname = params
        .string("gridname")?
        .unwrap_or_else(|| "density".into());
    let read = |name: &str| {
        crate::nanovdb::read_float_grid(&data, name)
            .map_err(|e| at(format!("{}: {e}", path.display())))
    };
    let Some(density) = read(&gridname)? else {
        return Err(at(format!(
            "{}: didn't find \"{gridname}\" grid",
            path.display()
        )));
    };
    let temperature_name = params
        .string("temperaturename")?
        .unwrap_or_else(|| "temperature".into());
    let temperature = read(&temperature_name)?;
    Ok(GridMediumDesc::NanoVdb(NanoVdbDesc {
        medium_to_render: ctm,
        sigma_a: sigma(params, "sigma_a", dir)?,
        sigma_s: sigma(params, "sigma_s", dir)?,
        scale: params.float("scale", 1.0)?,
        g: params.float("g", 0.0)?,
        density,
        temperature,
        le_scale: params.float("Lescale", 1.0)?,
        temperature_offset: temperature_offset(params)?,
        temperature_scale: params.float("temperaturescale", 1.0)?,
    }))
}

#[cfg(test)]
mod tests;
