//! `Camera`: pbrt-v4's `perspective` and `orthographic` cameras (others fall back to a
//! perspective one), with their screen window, thin lens and shutter.

use super::convert::Fallback;
use super::params::ParamList;
use crate::error::{Location, SceneError};
use lancer::math::Transform;
use lancer::scene::desc::{CameraDesc, Projection};

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
    params: &ParamList,
    ty: &str,
    camera_from_world: Transform,
    loc: &Location,
) -> Result<Fallback<CameraOptions>, SceneError> {
    let mut warnings = Vec::new();
    let projection = match ty {
        "perspective" => Projection::Perspective {
            fov: params.float_checked("fov", 90.0, "in (0, 180)", |v| v > 0.0 && v < 180.0)?,
        },
        "orthographic" => Projection::Orthographic,
        _ => {
            warnings.push(format!(
                "camera \"{ty}\" is not supported yet; lancer uses a perspective camera with fov 90"
            ));
            Projection::Perspective { fov: 90.0 }
        }
    };
    let screen_window = match params.floats("screenwindow")? {
        None => None,
        Some(w) if w.len() == 4 && w[0] < w[1] && w[2] < w[3] => Some([w[0], w[1], w[2], w[3]]),
        Some(_) => {
            return Err(params.error_at(
                "screenwindow",
                "\"float screenwindow\" needs 4 numbers: xmin xmax ymin ymax, with min < max",
            ));
        }
    };
    let frame_aspect = if params.has("frameaspectratio") {
        Some(params.float_checked("frameaspectratio", 1.0, "positive", |v| v > 0.0)?)
    } else {
        None
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
        lens_radius: params.float_checked("lensradius", 0.0, "at least 0", |v| v >= 0.0)?,
        focal_distance: params.float_checked("focaldistance", 1e6, "positive", |v| v > 0.0)?,
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

#[cfg(test)]
mod tests {}
