//! Reading media: `MakeNamedMedium` before and after `WorldBegin`, `MediumInterface` on shapes
//! and around the camera, presets, and the errors with their place.

use crate::load_pbrt_str;
use lancer::math::Rgb;
use lancer::medium::{HomogeneousDesc, MediumDesc, MediumInterface};
use std::path::Path;

fn load(text: &str) -> Result<crate::LoadedScene, String> {
    load_pbrt_str(text, "t.pbrt", Path::new(".")).map_err(|e| e.to_string())
}

fn warnings(l: &crate::LoadedScene) -> Vec<String> {
    l.warnings.iter().map(|w| w.to_string()).collect()
}

#[test]
fn named_media_bind_shapes_and_the_camera() {
    let text = "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 2 3]\n\
                \"float scale\" 0.5 \"float g\" 0.3\n\
                MediumInterface \"\" \"fog\"\n\
                Camera \"perspective\"\n\
                WorldBegin\n\
                MakeNamedMedium \"milk\" \"string type\" \"homogeneous\" \"string preset\" \"Wholemilk\"\n\
                \"rgb Le\" [0.5 0.5 0.5] \"float Lescale\" 2\n\
                Shape \"sphere\"\n\
                AttributeBegin\n\
                MediumInterface \"milk\" \"\"\n\
                Material \"interface\"\n\
                Shape \"sphere\"\n\
                AttributeEnd\n\
                MediumInterface \"milk\"\n\
                Shape \"sphere\"\n";
    let l = load(text).unwrap();
    assert_eq!(warnings(&l), Vec::<String>::new());
    let d = &l.desc;
    assert_eq!(
        d.media[0],
        MediumDesc::Homogeneous(HomogeneousDesc {
            sigma_a: Rgb::new(1.0, 2.0, 3.0),
            sigma_s: Rgb::ONE,
            scale: 0.5,
            le: Rgb::ZERO,
            le_scale: 1.0,
            g: 0.3,
        })
    );
    let MediumDesc::Homogeneous(HomogeneousDesc {
        sigma_a,
        sigma_s,
        le,
        le_scale,
        ..
    }) = d.media[1]
    else {
        panic!("media[1] is not homogeneous: {:?}", d.media[1]);
    };
    assert_eq!(sigma_a, Rgb::new(0.0011, 0.0024, 0.014));
    assert_eq!(sigma_s, Rgb::new(2.55, 3.21, 3.77));
    assert!((le - Rgb::splat(0.5)).abs().max_element() < 1e-6, "{le}");
    assert_eq!(le_scale, 2.0);
    // The camera is in the outside medium at `Camera`; the interface persists through
    // WorldBegin, so the first sphere has fog outside.
    assert_eq!(d.camera_medium, Some(0));
    let mi = |i: Option<u32>, o: Option<u32>| {
        Some(MediumInterface {
            inside: i,
            outside: o,
        })
    };
    let shapes: Vec<_> = d.shapes.iter().map(|s| s.medium_interface).collect();
    assert_eq!(
        shapes,
        [mi(None, Some(0)), mi(Some(1), None), mi(Some(1), Some(1))]
    );
}

#[test]
fn medium_errors_have_their_place() {
    let e = load("WorldBegin\nMediumInterface \"smoke\" \"\"\nShape \"sphere\"\n").unwrap_err();
    assert_eq!(
        e,
        "t.pbrt:3:1: no medium named \"smoke\" (MakeNamedMedium defines one)"
    );
    let e = load(
        "MakeNamedMedium \"a\" \"string type\" \"homogeneous\"\nWorldBegin\n\
                  MakeNamedMedium \"a\" \"string type\" \"homogeneous\"\n",
    )
    .unwrap_err();
    assert_eq!(e, "t.pbrt:3:1: named medium \"a\" redefined");
    let e = load("WorldBegin\nMakeNamedMedium \"a\" \"string type\" \"jelly\"\n").unwrap_err();
    assert!(
        e.starts_with("t.pbrt:2:1: unknown medium type \"jelly\""),
        "{e}"
    );
    let e = load("WorldBegin\nMakeNamedMedium \"a\"\n").unwrap_err();
    assert_eq!(
        e,
        "t.pbrt:2:1: MakeNamedMedium \"a\" needs a \"string type\""
    );
    let e =
        load("WorldBegin\nMakeNamedMedium \"a\" \"string type\" \"homogeneous\" \"float g\" 1\n")
            .unwrap_err();
    assert!(e.starts_with("t.pbrt:2:"), "{e}");
    assert!(e.contains("\"g\" must lie in (-1, 1), not 1"), "{e}");
}

#[test]
fn grid_media_are_read_and_unknown_parameters_are_reported() {
    let l = load(
        "WorldBegin\nMakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"float density\" [1]\n\
         MakeNamedMedium \"h\" \"string type\" \"homogeneous\" \"float sigma\" 1\n\
         MediumInterface \"g\" \"h\"\nShape \"sphere\"\n",
    )
    .unwrap();
    let w = warnings(&l);
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(
        w[0],
        "t.pbrt:3:49: parameter \"float sigma\" of MakeNamedMedium \"h\" is not used by lancer; ignored"
    );
    // The grid is medium 0, the homogeneous one medium 1.
    assert!(
        matches!(l.desc.media[0], MediumDesc::Grid(_)),
        "{:?}",
        l.desc.media[0]
    );
    assert_eq!(
        l.desc.shapes[0].medium_interface,
        Some(MediumInterface {
            inside: Some(0),
            outside: Some(1)
        })
    );
}

#[test]
fn volpath_is_the_default_integrator() {
    let l = load("WorldBegin\nShape \"sphere\"\n").unwrap();
    assert_eq!(
        l.desc.integrator,
        lancer::integrator::Integrator::VolPath {
            max_depth: 5,
            regularize: false
        }
    );
}

#[test]
fn mlt_goes_through_media() {
    // mlt's paths are bdpt's, which sample media: a scene with media keeps its mlt, unwarned.
    let text = "Integrator \"mlt\" \"integer maxdepth\" 7 \"bool regularize\" true\n\
                WorldBegin\n\
                MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n";
    let l = load(text).unwrap();
    assert!(
        matches!(
            l.desc.integrator,
            lancer::integrator::Integrator::Mlt(o) if o.max_depth == 7 && o.regularize
        ),
        "{:?}",
        l.desc.integrator
    );
    assert!(warnings(&l).is_empty(), "{:?}", warnings(&l));
}

#[test]
fn lights_sit_in_the_current_outside_medium() {
    // pbrt-v4 gives a light the outside medium current at `LightSource`: bdpt's and
    // lightpath's light paths start in it. Lights in vacuum before it are padded with `None`.
    let text = "Integrator \"bdpt\"\n\
                WorldBegin\n\
                MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n\
                LightSource \"point\"\n\
                MediumInterface \"fog\" \"fog\"\n\
                LightSource \"spot\"\n\
                MediumInterface \"\" \"\"\n\
                LightSource \"point\"\n";
    let l = load(text).unwrap();
    // bdpt renders the media itself: no warning, no fallback to volpath.
    assert_eq!(warnings(&l), Vec::<String>::new());
    assert!(matches!(
        l.desc.integrator,
        lancer::integrator::Integrator::Bdpt { .. }
    ));
    assert_eq!(l.desc.lights.len(), 3);
    assert_eq!(l.desc.light_media, [None, Some(0)]);
}

#[test]
fn simplevolpath_refuses_delta_lights_as_pbrt_does() {
    let e = load("Integrator \"simplevolpath\"\nWorldBegin\nLightSource \"point\"\n").unwrap_err();
    assert!(
        e.starts_with("t.pbrt:3:1:") && e.contains("\"simplevolpath\" supports only area"),
        "{e}"
    );
    let l = load(
        "Integrator \"simplevolpath\" \"integer maxdepth\" 3\nWorldBegin\n\
         LightSource \"infinite\"\nAreaLightSource \"diffuse\"\nShape \"sphere\"\n",
    )
    .unwrap();
    assert_eq!(warnings(&l), Vec::<String>::new());
}
