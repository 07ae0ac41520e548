//! lancer's `Shape "sdf"` in pbrt files: the expression reaches the scene description, and
//! its errors point at the line and column inside the string in the file.

use lancer::scene::desc::Geometry;
use lancer::shape::SdfDesc;
use lancer_scene::load_pbrt_str;
use std::path::Path;

fn load(text: &str) -> Result<lancer::scene::desc::SceneDesc, lancer_scene::SceneError> {
    load_pbrt_str(text, "t.pbrt", Path::new(".")).map(|s| s.desc)
}

#[test]
fn sdf_shape_reaches_the_scene() {
    let d = load(
        "WorldBegin\nShape \"sdf\" \"string expr\" \"smooth_union(sphere(0.6), translate([0, 0.5, 0], torus(0.7, 0.18)), 0.25)\"\n\
         Shape \"sdf\" \"string expr\" \"intersection(plane([0, 1, 0], 0), sphere(2))\"\n\
         Shape \"sdf\" \"string expr\" \"repeat([2, 0, 2], sphere(0.5))\" \"point3 min\" [-5 -1 -5] \"point3 max\" [5 1 5]\n",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(d.shapes.len(), 3);
    let Geometry::Sdf(SdfDesc { function, bounds }) = &d.shapes[0].geometry else {
        panic!("{:?}", d.shapes[0].geometry)
    };
    assert!(bounds.is_none());
    // The blend's box: the torus reaches 0.88 sideways, and 0.5 + 0.18 up, plus k/4.
    let b = function.bounds();
    assert!((b.hi.x - (0.88 + 0.0625)).abs() < 1e-9 && (b.hi.y - (0.68 + 0.0625)).abs() < 1e-9);
    // At the centre the torus is 0.68 away, farther than k from the sphere's −0.6: no blend.
    assert!((function.eval(glam::DVec3::ZERO) + 0.6).abs() < 1e-12);
    let Geometry::Sdf(SdfDesc { bounds, .. }) = &d.shapes[2].geometry else {
        panic!()
    };
    assert_eq!(
        *bounds,
        Some((
            lancer::math::Vec3::new(-5.0, -1.0, -5.0),
            lancer::math::Vec3::new(5.0, 1.0, 5.0)
        ))
    );
}

#[test]
fn expression_errors_point_into_the_string() {
    // Line 3; the string's quote is at column 29, so its text starts at column 30.
    let text = "WorldBegin\nAttributeBegin\n  Shape \"sdf\" \"string expr\" \"union(sphere(1), torus(1 0.5))\"\nAttributeEnd\n";
    let e = load(text).unwrap_err();
    let loc = e.location.as_ref().expect("a location");
    assert_eq!((loc.line, loc.col), (3, 30 + 25), "{e}");
    assert!(
        e.message
            .contains("expected ',' or ')' in the arguments of 'torus'"),
        "{e}"
    );

    let e = load("WorldBegin\nShape \"sdf\" \"string expr\" \"union(sphere(1), tours(1, 0.5))\"\n")
        .unwrap_err();
    let loc = e.location.as_ref().unwrap();
    assert_eq!((loc.line, loc.col), (2, 28 + 17), "{e}");
    assert!(
        e.message.contains("unknown function 'tours'") && e.message.contains("torus"),
        "{e}"
    );
}

#[test]
fn unbounded_or_incomplete_sdf_is_refused_clearly() {
    let e =
        load("WorldBegin\nShape \"sdf\" \"string expr\" \"plane([0, 1, 0], 0)\"\n").unwrap_err();
    assert!(
        e.message.contains("unbounded") && e.message.contains("point3 min"),
        "{e}"
    );
    assert_eq!(e.location.as_ref().unwrap().line, 2);
    let e =
        load("WorldBegin\nShape \"sdf\" \"string expr\" \"sphere(1)\" \"point3 min\" [0 0 0]\n")
            .unwrap_err();
    assert!(e.message.contains("both"), "{e}");
    let e = load("WorldBegin\nShape \"sdf\"\n").unwrap_err();
    assert!(e.message.contains("string expr"), "{e}");
}
