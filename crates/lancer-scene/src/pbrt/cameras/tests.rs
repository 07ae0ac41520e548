use super::*;
use crate::pbrt::convert::testing::{err, typed_in, unused, with_reader};
use lancer::math::Vec3;
use std::path::Path;

type Converted = (Result<Fallback<CameraOptions>, SceneError>, Vec<String>);

/// The one `Camera` of `text` under `ctm`, relative names against `dir`, and its unread
/// parameters.
fn convert_in(text: &str, dir: &Path, ctm: Transform) -> Converted {
    let (ty, params, loc) = typed_in(text, dir);
    let out = with_reader(&params, dir, |r| camera(r, &ty, ctm, &loc));
    (out, unused(&params))
}

fn convert(text: &str, ctm: Transform) -> Converted {
    convert_in(text, Path::new("."), ctm)
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
fn spherical_cameras() {
    // pbrt-v4's default mapping is the equal-area square; it reads the projective cameras'
    // frame and lens parameters and ignores them.
    let c = converted(
        r#"Camera "spherical" "float lensradius" 0.1 "float focaldistance" 3
           "float frameaspectratio" 2 "float screenwindow" [-1 1 -1 1]"#,
    );
    assert_eq!(
        c.camera.projection,
        Projection::Spherical {
            mapping: SphericalMapping::EqualArea
        }
    );
    let c = converted(r#"Camera "spherical" "string mapping" "equirectangular""#);
    assert_eq!(
        c.camera.projection,
        Projection::Spherical {
            mapping: SphericalMapping::Equirectangular
        }
    );
    assert_eq!(
        error("Camera \"spherical\"\n  \"string mapping\" \"cube\""),
        "t.pbrt:2:3: unknown spherical mapping \"cube\" (expected \"equalarea\" or \"equirectangular\")"
    );
    assert_eq!(
        error(r#"Camera "fisheye""#),
        "t.pbrt:1:1: unknown camera \"fisheye\" (expected perspective, orthographic, spherical or realistic)"
    );
}

/// A folder holding `lens.dat` with `text`.
fn lens_dir(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("lancer-lens-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("lens.dat"), text).unwrap();
    dir
}

const LENS: &str = "# a lens\n 35 4 1.6 20 # front\n 0 3 0 10\n -35 30 1 20\n";

#[test]
fn realistic_cameras_read_their_lens_file() {
    let dir = lens_dir("ok", LENS);
    let (out, unused) = convert_in(
        r#"Camera "realistic" "string lensfile" "lens.dat" "float aperturediameter" 8
           "float focusdistance" 2 "string aperture" "pentagon" "float shutterclose" 0.5"#,
        &dir,
        Transform::IDENTITY,
    );
    let f = out.unwrap();
    assert!(
        f.warnings.is_empty() && unused.is_empty(),
        "{:?} {unused:?}",
        f.warnings
    );
    let Projection::Realistic(lens) = &f.value.camera.projection else {
        panic!("a realistic camera")
    };
    assert_eq!(lens.interfaces.len(), 3);
    assert_eq!(
        lens.interfaces[0],
        LensInterface {
            curvature_radius: 35.0,
            thickness: 4.0,
            eta: 1.6,
            aperture_diameter: 20.0
        }
    );
    assert_eq!(lens.interfaces[1].curvature_radius, 0.0);
    assert_eq!((lens.aperture_diameter, lens.focus_distance), (8.0, 2.0));
    assert_eq!(lens.aperture, Aperture::Pentagon);
    assert_eq!(f.value.camera.shutter, [0.0, 0.5]);
    // pbrt-v4's defaults: aperture 1 mm, focus at 10, circular.
    let (out, _) = convert_in(
        r#"Camera "realistic" "string lensfile" "lens.dat""#,
        &dir,
        Transform::IDENTITY,
    );
    let Projection::Realistic(lens) = out.unwrap().value.camera.projection else {
        panic!("a realistic camera")
    };
    assert_eq!(
        (lens.aperture_diameter, lens.focus_distance, &lens.aperture),
        (1.0, 10.0, &Aperture::Circular)
    );
    // Wider than the stop: clamped, with pbrt-v4's warning.
    let (out, _) = convert_in(
        r#"Camera "realistic" "string lensfile" "lens.dat" "float aperturediameter" 12"#,
        &dir,
        Transform::IDENTITY,
    );
    assert_eq!(
        out.unwrap().warnings,
        [
            "\"aperturediameter\" 12 mm is wider than the aperture stop of lens.dat (10 mm); clamped to it, as pbrt-v4 does"
        ]
    );
}

#[test]
fn realistic_camera_errors_are_at_their_parameter() {
    let dir = lens_dir("bad", "35 4 1.6 20\n0 3 x 10\n");
    let (out, _) = convert_in(
        "Camera \"realistic\"\n  \"string lensfile\" \"lens.dat\"",
        &dir,
        Transform::IDENTITY,
    );
    let e = err(out);
    assert!(
        e.starts_with("t.pbrt:2:3: ") && e.ends_with("lens.dat: line 2: \"x\" is not a number"),
        "{e}"
    );
    let dir = lens_dir("short", "35 4 1.6 20 0 3\n");
    let (out, _) = convert_in(
        r#"Camera "realistic" "string lensfile" "lens.dat""#,
        &dir,
        Transform::IDENTITY,
    );
    assert!(err(out).ends_with("not 6 values"));
    let (out, _) = convert_in(
        r#"Camera "realistic" "string lensfile" "none.dat""#,
        &dir,
        Transform::IDENTITY,
    );
    let e = err(out);
    assert!(
        e.starts_with("t.pbrt:1:20: ")
            && e.ends_with("none.dat: No such file or directory (os error 2)"),
        "{e}"
    );
    assert_eq!(
        error(r#"Camera "realistic""#),
        "t.pbrt:1:1: a \"realistic\" camera needs a lens description file, \"string lensfile\""
    );
    let dir = lens_dir("aperture", LENS);
    let (out, _) = convert_in(
        "Camera \"realistic\" \"string lensfile\" \"lens.dat\"\n  \"string aperture\" \"hole.png\"",
        &dir,
        Transform::IDENTITY,
    );
    assert!(err(out).starts_with("t.pbrt:2:3: "));
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
