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
mod tests {
    use super::*;
    use crate::pbrt::convert::testing::{err, typed, unused};
    use lancer::math::Vec3;

    type Converted = (Result<Fallback<CameraOptions>, SceneError>, Vec<String>);

    /// The one `Camera` of `text` under `ctm`, and its unread parameters.
    fn convert(text: &str, ctm: Transform) -> Converted {
        let (ty, params, loc) = typed(text);
        let out = camera(&params, &ty, ctm, &loc);
        (out, unused(&params))
    }

    /// A camera that converts without warnings and reads every parameter.
    #[track_caller]
    fn converted(text: &str) -> CameraOptions {
        let (out, unused) = convert(text, Transform::IDENTITY);
        let f = out.unwrap_or_else(|e| panic!("{e}"));
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
        assert!(unused.is_empty(), "{unused:?}");
        f.value
    }

    #[track_caller]
    fn error(text: &str) -> String {
        err(convert(text, Transform::IDENTITY).0)
    }

    #[test]
    fn defaults_are_pbrt_v4s() {
        let ctm = Transform::translate(Vec3::new(0.0, 0.0, 5.0));
        let (out, _) = convert(r#"Camera "perspective""#, ctm);
        let c = out.unwrap().value;
        assert_eq!(
            c.camera,
            CameraDesc {
                projection: Projection::Perspective { fov: 90.0 },
                camera_from_world: ctm,
                screen_window: None,
                lens_radius: 0.0,
                focal_distance: 1e6,
                shutter: [0.0, 1.0],
            }
        );
        assert_eq!(c.frame_aspect, None);
        let c = converted(r#"Camera "orthographic""#);
        assert_eq!(c.camera.projection, Projection::Orthographic);
    }

    #[test]
    fn every_parameter_is_read() {
        let c = converted(
            r#"Camera "perspective" "float fov" 45 "float screenwindow" [-1 1 -0.5 0.5]
               "float frameaspectratio" 2 "float lensradius" 0.1 "float focaldistance" 5
               "float shutteropen" 0.2 "float shutterclose" 0.8"#,
        );
        assert_eq!(
            c.camera,
            CameraDesc {
                projection: Projection::Perspective { fov: 45.0 },
                camera_from_world: Transform::IDENTITY,
                screen_window: Some([-1.0, 1.0, -0.5, 0.5]),
                lens_radius: 0.1,
                focal_distance: 5.0,
                shutter: [0.2, 0.8],
            }
        );
        assert_eq!(c.frame_aspect, Some(2.0));
    }

    #[test]
    fn other_cameras_are_perspective_with_a_warning() {
        let (out, unused) = convert(
            r#"Camera "realistic" "string lensfile" "wide.dat""#,
            Transform::IDENTITY,
        );
        let f = out.unwrap();
        assert_eq!(
            f.value.camera.projection,
            Projection::Perspective { fov: 90.0 }
        );
        assert_eq!(
            f.warnings,
            [
                "camera \"realistic\" is not supported yet; lancer uses a perspective camera with fov 90"
            ]
        );
        assert_eq!(unused.len(), 1);
    }

    #[test]
    fn the_shorter_side_of_the_frame_spans_the_field_of_view() {
        assert_eq!(frame_window(2.0), [-2.0, 2.0, -1.0, 1.0]);
        assert_eq!(frame_window(0.5), [-1.0, 1.0, -2.0, 2.0]);
        assert_eq!(frame_window(1.0), [-1.0, 1.0, -1.0, 1.0]);
    }

    #[test]
    fn errors_are_at_their_parameter() {
        assert_eq!(
            error("Camera \"perspective\"\n  \"float fov\" 180"),
            "t.pbrt:2:3: \"float fov\" must be in (0, 180), not 180"
        );
        let window = "\"float screenwindow\" needs 4 numbers: xmin xmax ymin ymax, with min < max";
        assert_eq!(
            error("Camera \"perspective\"\n  \"float screenwindow\" [-1 1 0]"),
            format!("t.pbrt:2:3: {window}")
        );
        assert_eq!(
            error("Camera \"orthographic\"\n  \"float screenwindow\" [1 -1 0 1]"),
            format!("t.pbrt:2:3: {window}")
        );
        assert_eq!(
            error("Camera \"perspective\"\n  \"float frameaspectratio\" 0"),
            "t.pbrt:2:3: \"float frameaspectratio\" must be positive, not 0"
        );
        assert_eq!(
            error("Camera \"perspective\"\n  \"float lensradius\" -1"),
            "t.pbrt:2:3: \"float lensradius\" must be at least 0, not -1"
        );
        assert_eq!(
            error("Camera \"perspective\"\n  \"float focaldistance\" 0"),
            "t.pbrt:2:3: \"float focaldistance\" must be positive, not 0"
        );
        assert_eq!(
            error("Camera \"perspective\" \"float shutteropen\" 1\n  \"float shutterclose\" 0.5"),
            "t.pbrt:2:3: the shutter closes before it opens"
        );
        // Without "shutterclose" (1 by default), at the directive.
        assert_eq!(
            error(r#"Camera "perspective" "float shutteropen" 2"#),
            "t.pbrt:1:1: the shutter closes before it opens"
        );
    }
}
