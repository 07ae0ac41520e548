//! `Camera`: pbrt-v4's `perspective` and `orthographic` cameras (screen window, thin lens),
//! its `spherical` camera (equal-area or equirectangular) and its `realistic` camera (a lens
//! file, an aperture stop and its shape, a focus distance), all with their shutter.

use super::convert::{Fallback, Reader};
use crate::error::{Location, SceneError};
use crate::image_read::Encoding;
use lancer::camera::lens::{Aperture, LensDesc, LensInterface, SphericalMapping};
use lancer::math::Transform;
use lancer::scene::desc::{CameraDesc, Projection};
use std::sync::Arc;

/// What `Camera` sets: the camera, and the frame's aspect ratio (`frameaspectratio`), which
/// gives the screen window once the film is known when `screenwindow` does not.
#[derive(Clone, Debug)]
pub struct CameraOptions {
    /// The camera.
    pub camera: CameraDesc,
    /// `frameaspectratio`, if given.
    pub frame_aspect: Option<f32>,
}

/// The camera `ty` at `loc`, whose frame is `camera_from_world` (the CTM at `Camera`).
pub fn camera(
    r: &Reader,
    ty: &str,
    camera_from_world: Transform,
    loc: &Location,
) -> Result<Fallback<CameraOptions>, SceneError> {
    let params = r.params;
    let mut warnings = Vec::new();
    let projection = match ty {
        "perspective" => Projection::Perspective {
            fov: params.float_checked("fov", 90.0, "in (0, 180)", |v| v > 0.0 && v < 180.0)?,
        },
        "orthographic" => Projection::Orthographic,
        "spherical" => Projection::Spherical {
            mapping: match params.string("mapping")?.as_deref() {
                None | Some("equalarea") => SphericalMapping::EqualArea,
                Some("equirectangular") => SphericalMapping::Equirectangular,
                Some(m) => {
                    return Err(params.error_at(
                        "mapping",
                        format!(
                            "unknown spherical mapping \"{m}\" (expected \"equalarea\" or \"equirectangular\")"
                        ),
                    ));
                }
            },
        },
        "realistic" => {
            let (lens, warning) = realistic(r, loc)?;
            warnings.extend(warning);
            Projection::Realistic(Arc::new(lens))
        }
        _ => {
            return Err(SceneError::at(
                loc.clone(),
                format!(
                    "unknown camera \"{ty}\" (expected perspective, orthographic, spherical or realistic)"
                ),
            ));
        }
    };
    // pbrt-v4's realistic camera has no screen window, thin lens or frame; the others read
    // them (the spherical camera reads and ignores them).
    let projective = ty != "realistic";
    let screen_window = match params.floats("screenwindow")? {
        _ if !projective => None,
        None => None,
        Some(w) if w.len() == 4 && w[0] < w[1] && w[2] < w[3] => Some([w[0], w[1], w[2], w[3]]),
        Some(_) => {
            return Err(params.error_at(
                "screenwindow",
                "\"float screenwindow\" needs 4 numbers: xmin xmax ymin ymax, with min < max",
            ));
        }
    };
    let frame_aspect = if projective && params.has("frameaspectratio") {
        Some(params.float_checked("frameaspectratio", 1.0, "positive", |v| v > 0.0)?)
    } else {
        None
    };
    let (lens_radius, focal_distance) = if projective {
        (
            params.float_checked("lensradius", 0.0, "at least 0", |v| v >= 0.0)?,
            params.float_checked("focaldistance", 1e6, "positive", |v| v > 0.0)?,
        )
    } else {
        (0.0, 1e6)
    };
    let shutter_open = params.float("shutteropen", 0.0)?;
    let shutter_close = params.float("shutterclose", 1.0)?;
    if shutter_close < shutter_open {
        let at = params.location("shutterclose").unwrap_or(loc);
        return Err(SceneError::at(
            at.clone(),
            "the shutter closes before it opens",
        ));
    }
    let camera = CameraDesc {
        projection,
        camera_from_world,
        screen_window,
        lens_radius,
        focal_distance,
        shutter: [shutter_open, shutter_close],
    };
    Ok(Fallback {
        value: CameraOptions {
            camera,
            frame_aspect,
        },
        warnings,
    })
}

/// pbrt-v4's `realistic` camera: the lens file `lensfile` (rows of curvature radius,
/// thickness, index and aperture diameter in mm, `#` comments), `aperturediameter` (mm, 1 by
/// default), `focusdistance` (10 by default) and the stop's shape `aperture`: `circular` (or
/// absent), `gaussian`, `square`, `pentagon`, `star`, or an image file. A warning when the
/// aperture is wider than the lens file's stop, which limits it (as pbrt-v4 warns).
fn realistic(r: &Reader, loc: &Location) -> Result<(LensDesc, Option<String>), SceneError> {
    let params = r.params;
    let Some(name) = params.string("lensfile")? else {
        return Err(SceneError::at(
            loc.clone(),
            "a \"realistic\" camera needs a lens description file, \"string lensfile\"",
        ));
    };
    let at = params.location("lensfile").unwrap_or(loc).clone();
    let path = r.dir.resolve(&name);
    let text = std::fs::read_to_string(&path)
        .map_err(|e| SceneError::at(at.clone(), format!("{}: {e}", path.display())))?;
    let interfaces = lens_interfaces(&text)
        .map_err(|m| SceneError::at(at.clone(), format!("{}: {m}", path.display())))?;
    let aperture_diameter =
        params.float_checked("aperturediameter", 1.0, "positive", |v| v > 0.0)?;
    let focus_distance = params.float_checked("focusdistance", 10.0, "positive", |v| v > 0.0)?;
    let aperture = match params.string("aperture")?.as_deref() {
        None | Some("") | Some("circular") => Aperture::Circular,
        Some("gaussian") => Aperture::Gaussian,
        Some("square") => Aperture::Square,
        Some("pentagon") => Aperture::Pentagon,
        Some("star") => Aperture::Star,
        Some(file) => {
            let path = r.dir.resolve(file);
            let is_png = path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| e.eq_ignore_ascii_case("png"));
            let encoding = if is_png {
                Encoding::Srgb
            } else {
                Encoding::Linear
            };
            let image = r
                .images
                .rgb(&path, encoding)
                .map_err(|e| params.error_at("aperture", e.to_string()))?;
            let lit = image
                .texels
                .iter()
                .any(|&t| lancer::math::Rgb::from(t).max_element() > 0.0);
            if !lit || image.texels.iter().any(|t| !t.is_finite()) {
                return Err(params.error_at(
                    "aperture",
                    format!(
                        "{}: the aperture image must let some light through and hold finite values only",
                        path.display()
                    ),
                ));
            }
            Aperture::Image(image)
        }
    };
    let warning = interfaces
        .iter()
        .find(|i| i.curvature_radius == 0.0 && aperture_diameter > i.aperture_diameter)
        .map(|stop| {
            format!(
                "\"aperturediameter\" {aperture_diameter} mm is wider than the aperture stop of {} ({} mm); clamped to it, as pbrt-v4 does",
                name, stop.aperture_diameter
            )
        });
    Ok((
        LensDesc {
            interfaces,
            aperture_diameter,
            focus_distance,
            aperture,
        },
        warning,
    ))
}

/// The interfaces of a lens file: whitespace-separated numbers (`#` starts a comment), four a
/// row. An error names the line of a word that is not a number, or says how many values the
/// file holds when they are not a non-zero multiple of four.
pub fn lens_interfaces(text: &str) -> Result<Vec<LensInterface>, String> {
    let mut values = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("");
        for word in line.split_whitespace() {
            match word.parse::<f32>() {
                Ok(v) if v.is_finite() => values.push(v),
                _ => return Err(format!("line {}: \"{word}\" is not a number", n + 1)),
            }
        }
    }
    if values.is_empty() || values.len() % 4 != 0 {
        return Err(format!(
            "a lens file holds rows of 4 numbers (curvature radius, thickness, index, aperture diameter), not {} values",
            values.len()
        ));
    }
    Ok(values
        .chunks_exact(4)
        .map(|c| LensInterface {
            curvature_radius: c[0],
            thickness: c[1],
            eta: c[2],
            aperture_diameter: c[3],
        })
        .collect())
}

/// The screen window of a frame of aspect ratio `frame` (width / height) when the scene gives
/// none: [−frame, frame] × [−1, 1] for a wide frame, [−1, 1] × [−1/frame, 1/frame] for a tall
/// one, so that the shorter side spans [−1, 1] (and the field of view).
pub fn frame_window(frame: f32) -> [f32; 4] {
    if frame > 1.0 {
        [-frame, frame, -1.0, 1.0]
    } else {
        [-1.0, 1.0, -1.0 / frame, 1.0 / frame]
    }
}

#[cfg(test)]
mod tests;
