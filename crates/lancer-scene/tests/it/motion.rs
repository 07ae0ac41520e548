//! pbrt-v4's motion directives on the `SceneDesc` they build: two CTMs changed by
//! `ActiveTransform`, their times from `TransformTimes`, saved by attribute and transform
//! blocks; moving shapes, instances and cameras; the errors and warnings around them.

use lancer::math::Vec3;
use lancer::scene::desc::SceneDesc;
use lancer_scene::{LoadedScene, load_pbrt_str};
use std::path::Path;

fn load(text: &str) -> LoadedScene {
    load_pbrt_str(text, "t.pbrt", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

fn scene(text: &str) -> SceneDesc {
    let l = load(text);
    assert!(l.warnings.is_empty(), "{:?}", l.warnings);
    l.desc
}

#[track_caller]
fn assert_close(a: Vec3, b: Vec3) {
    assert!((a - b).abs().max_element() < 1e-5, "{a} != {b}");
}

const SPHERE: &str = r#"Shape "sphere" "float radius" 0.5"#;

#[test]
fn active_transform_picks_the_ctm_and_blocks_restore_it() {
    let d = scene(&format!(
        r#"WorldBegin
        AttributeBegin
          Translate 1 0 0
          ActiveTransform EndTime
          Translate 0 2 0
          ActiveTransform StartTime
          Translate 0 0 3
          {SPHERE}
        AttributeEnd
        {SPHERE}
        AttributeBegin
          ActiveTransform EndTime
        AttributeEnd
        Translate 0 5 0
        {SPHERE}"#
    ));
    // The first sphere moves from (1, 0, 3) to (1, 2, 0); `AttributeEnd` restores both CTMs
    // and `ActiveTransform All`, so the later spheres stand still.
    assert_eq!(d.motion.shapes.len(), 1);
    let m = &d.motion.shapes[0];
    assert_eq!(m.world_from_object.times(), [0.0, 1.0]);
    assert_close(
        m.world_from_object.start().point(Vec3::ZERO),
        Vec3::new(1.0, 0.0, 3.0),
    );
    assert_close(
        m.world_from_object.end().point(Vec3::ZERO),
        Vec3::new(1.0, 2.0, 0.0),
    );
    let halfway = m.world_from_object.interpolate(0.5).point(Vec3::ZERO);
    assert_close(halfway, Vec3::new(1.0, 1.0, 1.5));
    assert_eq!(d.shapes.len(), 2);
    assert_close(
        d.shapes[1].object_to_world.point(Vec3::ZERO),
        Vec3::new(0.0, 5.0, 0.0),
    );
}

#[test]
fn transform_times_and_a_moving_camera() {
    let d = scene(&format!(
        r#"TransformTimes 0.5 2
        ActiveTransform EndTime
        Translate 0 0 -4
        ActiveTransform All
        Camera "perspective" "float shutteropen" 0.5 "float shutterclose" 2
        WorldBegin
        {SPHERE}"#
    ));
    let cam = d.motion.camera.expect("the camera moves");
    assert_eq!(cam.times(), [0.5, 2.0]);
    // The CTM at `Camera` is camera-from-world; the camera's position is its inverse's
    // image of the origin: (0, 0, 0) at the start, (0, 0, 4) at the end.
    assert_close(cam.start().point(Vec3::ZERO), Vec3::ZERO);
    assert_close(cam.end().point(Vec3::ZERO), Vec3::new(0.0, 0.0, 4.0));
    assert_eq!(d.camera.shutter, [0.5, 2.0]);
    // After WorldBegin the CTMs are reset: the sphere stands still.
    assert!(d.motion.shapes.is_empty() && d.shapes.len() == 1);
}

#[test]
fn moving_instances_and_still_ones() {
    let d = scene(&format!(
        r#"WorldBegin
        ObjectBegin "o"
          {SPHERE}
        ObjectEnd
        ObjectInstance "o"
        AttributeBegin
          ActiveTransform EndTime
          Rotate 90 0 0 1
          ActiveTransform All
          Translate 2 0 0
          ObjectInstance "o"
        AttributeEnd"#
    ));
    assert_eq!(d.instances.len(), 1);
    assert_eq!(d.motion.instances.len(), 1);
    let m = &d.motion.instances[0].object_to_world;
    assert_close(m.start().point(Vec3::ZERO), Vec3::new(2.0, 0.0, 0.0));
    assert_close(m.end().point(Vec3::ZERO), Vec3::new(0.0, 2.0, 0.0));
    // Decomposed interpolation: the translation part goes along the chord from (2, 0, 0) to
    // (0, 2, 0), not along the arc, while the object turns 45° about its own origin.
    let half = m.interpolate(0.5);
    assert_close(half.point(Vec3::ZERO), Vec3::new(1.0, 1.0, 0.0));
    let h = std::f32::consts::FRAC_1_SQRT_2;
    assert_close(half.vector(Vec3::X), Vec3::new(h, h, 0.0));
}

#[test]
fn shapes_moving_inside_objects_move_in_every_instance() {
    // pbrt-v4: a shape moving by A(t) inside an object stands at T·A(t) in an instance T.
    let d = scene(&format!(
        r#"WorldBegin
        ObjectBegin "o"
          {SPHERE}
          ActiveTransform EndTime
          Translate 0 1 0
          ActiveTransform All
          {SPHERE}
        ObjectEnd
        AttributeBegin
          Translate 2 0 0
          Rotate 90 0 0 1
          Scale 2 2 2
          ObjectInstance "o"
        AttributeEnd
        ObjectInstance "o""#
    ));
    // The still sphere stays in the object; the moving one becomes a moving shape per instance.
    assert_eq!(d.objects[0].shapes.len(), 1);
    assert_eq!(d.instances.len(), 2);
    assert_eq!(d.motion.shapes.len(), 2);
    let m = &d.motion.shapes[0].world_from_object;
    assert_close(m.start().point(Vec3::ZERO), Vec3::new(2.0, 0.0, 0.0));
    // (0, 1, 0) scaled by 2 and turned 90° about z: (−2, 0, 0), then moved by (2, 0, 0).
    assert_close(m.end().point(Vec3::ZERO), Vec3::ZERO);
    // Halfway: T·A(0.5) = T·(0, 0.5, 0) = (1, 0, 0), and the radius is scaled by 2.
    let half = m.interpolate(0.5);
    assert_close(half.point(Vec3::ZERO), Vec3::new(1.0, 0.0, 0.0));
    assert_close(half.vector(Vec3::X), Vec3::new(0.0, 2.0, 0.0));
    let m = &d.motion.shapes[1].world_from_object;
    assert_close(m.end().point(Vec3::ZERO), Vec3::new(0.0, 1.0, 0.0));
}

#[test]
fn moving_area_lights_are_refused_and_oddities_warned() {
    let e = load_pbrt_str(
        &format!(
            "WorldBegin\nAreaLightSource \"diffuse\"\nActiveTransform EndTime\nTranslate 1 0 0\n\
             ActiveTransform All\n  {SPHERE}"
        ),
        "t.pbrt",
        Path::new("."),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("t.pbrt:6:3: this area light's shape moves"),
        "{e}"
    );
    let e = load_pbrt_str("TransformTimes 1 0\nWorldBegin", "t.pbrt", Path::new(".")).unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.pbrt:1:1: TransformTimes: the end time 0 comes before the start time 1"
    );
    // A moving light stays at its start pose, as in pbrt-v4, with a word about it.
    let l = load(
        r#"WorldBegin
        ActiveTransform EndTime
        Translate 1 0 0
        LightSource "point""#,
    );
    assert_eq!(l.warnings.len(), 1);
    assert!(
        l.warnings[0]
            .to_string()
            .contains("pbrt-v4 keeps lights at their start pose")
    );
}
