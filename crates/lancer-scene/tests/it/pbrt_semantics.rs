//! What pbrt-v4's directives mean, checked on the `SceneDesc` they build: the current
//! transformation matrix and its blocks, named coordinate systems, defaults, light
//! normalisation, named materials, instancing, film exposure and relative file names.

use crate::common::ScratchDir;
use lancer::integrator::Integrator;
use lancer::light::{DistantDesc, PointDesc, SpotDesc};
use lancer::material::MaterialDesc;
use lancer::material::{DielectricMaterial, DiffuseMaterial, MixMaterial};
use lancer::math::{Vec3, normalize};
use lancer::sampling::SamplerKind;
use lancer::scene::desc::{Geometry, LightDesc, Projection, SceneDesc};
use lancer::shape::{BoxDesc, ConeDesc, HyperboloidDesc, ParaboloidDesc, SphereDesc};
use lancer::texture::SpectrumTex;
use lancer_scene::{load, load_pbrt_str};
use std::path::Path;

fn scene(text: &str) -> SceneDesc {
    load_pbrt_str(text, "t.pbrt", Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"))
        .desc
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-5 * (1.0 + b.abs().max_element())
}

#[track_caller]
fn assert_close(a: Vec3, b: Vec3) {
    assert!(close(a, b), "{a} != {b}");
}

/// Where each shape's object-space origin lands in the world, in file order.
fn origins(d: &SceneDesc) -> Vec<Vec3> {
    d.shapes
        .iter()
        .map(|s| s.object_to_world.point(Vec3::ZERO))
        .collect()
}

#[test]
fn transforms_post_multiply_the_ctm() {
    // pbrt: CTM ← CTM · T, so the last transform written applies first to the object.
    let d = scene(
        r#"WorldBegin
        Translate 1 0 0
        Scale 2 2 2
        Rotate 90 0 0 1
        Shape "sphere""#,
    );
    let m = d.shapes[0].object_to_world;
    // (1,0,0) → rotate → (0,1,0) → scale → (0,2,0) → translate → (1,2,0).
    assert_close(m.point(Vec3::X), Vec3::new(1.0, 2.0, 0.0));
    assert_close(m.point(Vec3::ZERO), Vec3::new(1.0, 0.0, 0.0));
}

#[test]
fn transform_and_concat_take_column_major_matrices() {
    let d = scene(
        r#"WorldBegin
        Transform [1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1]
        Shape "sphere"
        ConcatTransform [2 0 0 0  0 2 0 0  0 0 2 0  1 0 0 1]
        Shape "sphere""#,
    );
    assert_close(origins(&d)[0], Vec3::new(5.0, 6.0, 7.0));
    let m = d.shapes[1].object_to_world;
    // Translate(5,6,7) · Translate(1,0,0) · Scale(2).
    assert_close(m.point(Vec3::ZERO), Vec3::new(6.0, 6.0, 7.0));
    assert_close(m.point(Vec3::X), Vec3::new(8.0, 6.0, 7.0));
}

#[test]
fn blocks_restore_the_ctm_and_the_material() {
    let d = scene(
        r#"WorldBegin
        Material "diffuse" "rgb reflectance" [0.1 0.2 0.3]
        AttributeBegin
          Translate 0 0 4
          Material "conductor"
          Shape "sphere"
        AttributeEnd
        TransformBegin
          Translate 0 3 0
        TransformEnd
        Shape "sphere""#,
    );
    assert_close(origins(&d)[0], Vec3::new(0.0, 0.0, 4.0));
    assert_close(origins(&d)[1], Vec3::ZERO);
    let m0 = &d.materials[d.shapes[0].material as usize];
    let m1 = &d.materials[d.shapes[1].material as usize];
    assert!(matches!(m0, MaterialDesc::Conductor(_)), "{m0:?}");
    assert_eq!(
        *m1,
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: SpectrumTex::Const(Vec3::new(0.1, 0.2, 0.3))
        })
    );
}

#[test]
fn unbalanced_blocks_are_errors() {
    for text in ["WorldBegin AttributeEnd", "WorldBegin AttributeBegin"] {
        let e = load_pbrt_str(text, "t.pbrt", Path::new("."))
            .err()
            .unwrap_or_else(|| panic!("{text:?} was accepted"));
        assert!(e.to_string().contains("Attribute"), "{text:?}: {e}");
    }
}

#[test]
fn named_coordinate_systems_and_the_camera_frame() {
    let d = scene(
        r#"LookAt 1 2 3  0 0 0  0 1 0
        Camera "perspective"
        WorldBegin
        Translate 5 0 0
        CoordinateSystem "five"
        Translate 0 9 0
        CoordSysTransform "five"
        Shape "sphere"
        CoordSysTransform "camera"
        Shape "sphere""#,
    );
    assert_close(origins(&d)[0], Vec3::new(5.0, 0.0, 0.0));
    // "camera" is the camera's frame: its origin is the eye.
    assert_close(origins(&d)[1], Vec3::new(1.0, 2.0, 3.0));
    // WorldBegin resets the CTM, so the camera keeps LookAt's matrix.
    let eye = d.camera.camera_from_world.point(Vec3::new(1.0, 2.0, 3.0));
    assert_close(eye, Vec3::ZERO);
}

#[test]
fn look_at_is_left_handed_as_in_pbrt() {
    // pbrt's camera space: +z forward, +y up, +x right. Looking down −z from the origin,
    // world +x is to the camera's left (camera −x); `Scale -1 1 1` first undoes that.
    let d = scene(
        r#"LookAt 0 0 0  0 0 -1  0 1 0
        Camera "perspective"
        WorldBegin"#,
    );
    let c = d.camera.camera_from_world;
    assert_close(c.vector(Vec3::new(0.0, 0.0, -1.0)), Vec3::Z);
    assert_close(c.vector(Vec3::Y), Vec3::Y);
    assert_close(c.vector(Vec3::X), -Vec3::X);
    let d = scene(
        r#"Scale -1 1 1
        LookAt 0 0 0  0 0 -1  0 1 0
        Camera "perspective"
        WorldBegin"#,
    );
    assert_close(d.camera.camera_from_world.vector(Vec3::X), Vec3::X);
}

#[test]
fn defaults_are_pbrt_v4_defaults() {
    let d = scene("WorldBegin Shape \"sphere\"");
    assert_eq!(d.camera.projection, Projection::Perspective { fov: 90.0 });
    assert_eq!((d.film.xresolution, d.film.yresolution), (1280, 720));
    assert_eq!(d.sampler.spp, 16);
    // pbrt-v4's default integrator is volpath.
    assert!(matches!(
        d.integrator,
        Integrator::VolPath { max_depth: 5, .. }
    ));
    // fov spans the shorter axis: the ray through the top edge's middle is 45° off axis.
    assert!((edge_angle(&d, 640.0, 0.0) - 45.0).abs() < 1e-3);
    assert_eq!(
        d.materials[d.shapes[0].material as usize],
        MaterialDesc::default()
    );
    assert_eq!(
        d.shapes[0].geometry,
        Geometry::Sphere(SphereDesc {
            radius: 1.0,
            z_min: -1.0,
            z_max: 1.0,
            phi_max: 360.0
        })
    );
    assert_eq!(d.film.scale, 1.0);
}

/// Degrees between the camera's axis and the ray through raster point (x, y).
fn edge_angle(d: &SceneDesc, x: f32, y: f32) -> f32 {
    let camera = lancer::camera::Camera::from_desc(
        &d.camera,
        (d.film.xresolution, d.film.yresolution),
        d.film.diagonal,
    )
    .expect("camera");
    let dir = camera.world_from_camera.inverse().vector(
        camera
            .generate_ray(glam::Vec2::new(x, y), glam::Vec2::splat(0.5))
            .expect("a ray")
            .ray
            .d,
    );
    normalize(dir).z.acos().to_degrees()
}

#[test]
fn portrait_films_put_the_fov_on_the_width() {
    let d = scene(
        r#"Film "rgb" "integer xresolution" [100] "integer yresolution" [200]
        Camera "perspective" "float fov" [40]
        WorldBegin"#,
    );
    assert!((edge_angle(&d, 0.0, 100.0) - 20.0).abs() < 1e-3);
    let d = scene(
        r#"Film "rgb" "integer xresolution" [300] "integer yresolution" [200]
        Camera "perspective" "float fov" [40]
        WorldBegin"#,
    );
    assert!((edge_angle(&d, 150.0, 0.0) - 20.0).abs() < 1e-3);
    // screenwindow overrides the aspect rule.
    let d = scene(
        r#"Film "rgb" "integer xresolution" [300] "integer yresolution" [200]
        Camera "perspective" "float fov" [40] "float screenwindow" [-0.5 0.5 -0.5 0.5]
        WorldBegin"#,
    );
    let half = (20f32.to_radians().tan() * 0.5).atan().to_degrees();
    assert!((edge_angle(&d, 0.0, 100.0) - half).abs() < 1e-3);
}

#[test]
fn stratified_sampler_takes_x_times_y_samples() {
    let d = scene(
        r#"Sampler "stratified" "integer xsamples" [3] "integer ysamples" [5] "bool jitter" false
        WorldBegin"#,
    );
    assert_eq!(d.sampler.spp, 15);
    assert_eq!(
        d.sampler.kind,
        SamplerKind::Stratified {
            xsamples: 3,
            ysamples: 5,
            jitter: false
        }
    );
    let d = scene(r#"Sampler "independent" "integer pixelsamples" [7] WorldBegin"#);
    assert_eq!(
        (d.sampler.kind, d.sampler.spp),
        (SamplerKind::Independent, 7)
    );
}

fn point_intensity(light: &str) -> Vec3 {
    let d = scene(&format!("WorldBegin {light}"));
    match &d.lights[..] {
        [LightDesc::Point(PointDesc { intensity, .. })] => *intensity,
        other => panic!("{other:?}"),
    }
}

fn luminance(c: Vec3) -> f32 {
    lancer::math::luminance(c)
}

#[test]
fn light_spectra_are_normalised_as_pbrt_v4_does() {
    // RGB passes through.
    assert_close(
        point_intensity(r#"LightSource "point" "rgb I" [1 2 3] "float scale" [2]"#),
        Vec3::new(2.0, 4.0, 6.0),
    );
    // A black body has luminance 1 (times scale), warm at 3000 K.
    let bb = point_intensity(r#"LightSource "point" "blackbody I" [3000] "float scale" [5]"#);
    assert!((luminance(bb) - 5.0).abs() < 0.01, "{bb}");
    assert!(bb.x > bb.y && bb.y > bb.z, "3000 K is reddish: {bb}");
    // So does a named spectrum: the CIE illuminant A is warm, D65 is white.
    let a = point_intensity(r#"LightSource "point" "spectrum I" "stdillum-A""#);
    assert!((luminance(a) - 1.0).abs() < 0.01 && a.x > a.z, "{a}");
    let d65 = point_intensity(r#"LightSource "point" "spectrum I" "stdillum-D65""#);
    assert!(
        close(d65, Vec3::ONE) || (d65 - Vec3::ONE).abs().max_element() < 0.02,
        "{d65}"
    );
    // The default is the colour space's illuminant: white, 1.
    assert_close(point_intensity(r#"LightSource "point""#), Vec3::ONE);
}

#[test]
fn power_sets_the_total_flux() {
    // Φ = 4π·I for a point light.
    let i = point_intensity(r#"LightSource "point" "rgb I" [1 1 1] "float power" [100]"#);
    assert_close(i, Vec3::splat(100.0 / (4.0 * std::f32::consts::PI)));
    let d = scene(
        r#"WorldBegin
        LightSource "spot" "rgb I" [1 1 1] "float power" [10]
            "float coneangle" [30] "float conedeltaangle" [0]"#,
    );
    let LightDesc::Spot(SpotDesc { intensity, .. }) = d.lights[0] else {
        panic!("{:?}", d.lights)
    };
    // A hard-edged cone: Φ = 2π(1 − cos θ)·I.
    let k = 2.0 * std::f32::consts::PI * (1.0 - 30f32.to_radians().cos());
    assert_close(intensity, Vec3::splat(10.0 / k));
}

#[test]
fn lights_are_placed_by_the_ctm() {
    let d = scene(
        r#"WorldBegin
        Translate 0 10 0
        LightSource "point" "point3 from" [1 0 0]
        Rotate 90 1 0 0
        LightSource "distant" "point3 from" [0 0 0] "point3 to" [0 0 1]"#,
    );
    let LightDesc::Point(PointDesc { from, .. }) = d.lights[0] else {
        panic!()
    };
    assert_close(from, Vec3::new(1.0, 10.0, 0.0));
    let LightDesc::Distant(DistantDesc { direction, .. }) = d.lights[1] else {
        panic!()
    };
    // Towards the light: from − to = −z, which a 90° turn about x takes to +y.
    assert_close(normalize(direction), Vec3::new(0.0, 1.0, 0.0));
}

#[test]
fn named_materials_resolve_whenever_they_are_defined() {
    let d = scene(
        r#"WorldBegin
        MakeNamedMaterial "red" "string type" "diffuse" "rgb reflectance" [0.8 0 0]
        NamedMaterial "red"
        Shape "sphere"
        NamedMaterial "later"
        Shape "sphere"
        MakeNamedMaterial "later" "string type" "dielectric" "float eta" [1.33]
        MakeNamedMaterial "both" "string type" "mix" "string materials" ["red" "later"]
            "float amount" [0.25]
        NamedMaterial "both"
        Shape "sphere""#,
    );
    let mat = |i: usize| d.materials[d.shapes[i].material as usize].clone();
    assert_eq!(
        mat(0),
        MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: SpectrumTex::Const(Vec3::new(0.8, 0.0, 0.0))
        })
    );
    assert!(
        matches!(mat(1), MaterialDesc::Dielectric(DielectricMaterial { eta, .. }) if eta == lancer::spectrum::Ior::Constant(1.33))
    );
    let MaterialDesc::Mix(MixMaterial { materials, .. }) = mat(2) else {
        panic!("{:?}", mat(2))
    };
    assert_eq!(d.materials[materials[0] as usize], mat(0));
    assert_eq!(d.materials[materials[1] as usize], mat(1));
}

#[test]
fn an_undefined_named_material_is_an_error_where_it_is_used() {
    let e = load_pbrt_str(
        "WorldBegin\nNamedMaterial \"nope\"\nShape \"sphere\"",
        "t.pbrt",
        Path::new("."),
    )
    .expect_err("undefined material");
    let msg = e.to_string();
    assert!(msg.contains("nope") && msg.contains("t.pbrt:2"), "{msg}");
}

#[test]
fn instances_compose_the_object_and_the_instance_transforms() {
    let d = scene(
        r#"WorldBegin
        ObjectBegin "thing"
          Translate 0 1 0
          Shape "sphere" "float radius" [0.5]
        ObjectEnd
        Shape "disk"
        AttributeBegin
          Translate 5 0 0
          ObjectInstance "thing"
        AttributeEnd
        ObjectInstance "thing""#,
    );
    assert_eq!(d.objects.len(), 1);
    assert_eq!(
        d.shapes.len(),
        1,
        "the object's shapes are not world shapes"
    );
    assert_eq!(d.instances.len(), 2);
    let obj = &d.objects[0];
    assert_eq!(obj.name, "thing");
    let p = |i: usize| {
        d.instances[i]
            .object_to_world
            .point(obj.shapes[0].object_to_world.point(Vec3::ZERO))
    };
    assert_close(p(0), Vec3::new(5.0, 1.0, 0.0));
    assert_close(p(1), Vec3::new(0.0, 1.0, 0.0));
    // The CTM at ObjectBegin does not leak out of it.
    assert_close(origins(&d)[0], Vec3::ZERO);
}

#[test]
fn attribute_sets_defaults_for_later_directives() {
    let d = scene(
        r#"WorldBegin
        Attribute "shape" "float radius" [0.25]
        Attribute "light" "rgb I" [3 3 3]
        Shape "sphere"
        Shape "sphere" "float radius" [2]
        LightSource "point""#,
    );
    let radius = |i: usize| match d.shapes[i].geometry {
        Geometry::Sphere(SphereDesc { radius, .. }) => radius,
        ref g => panic!("{g:?}"),
    };
    assert_eq!((radius(0), radius(1)), (0.25, 2.0));
    let LightDesc::Point(PointDesc { intensity, .. }) = d.lights[0] else {
        panic!()
    };
    assert_close(intensity, Vec3::splat(3.0));
}

#[test]
fn film_exposure_is_shutter_time_times_iso_over_100() {
    let d = scene(
        r#"Camera "perspective" "float shutteropen" [0] "float shutterclose" [0.5]
        Film "rgb" "float iso" [400]
        WorldBegin"#,
    );
    assert_eq!(d.film.scale, 2.0);
}

#[test]
fn reverse_orientation_is_an_attribute() {
    let d = scene(
        r#"WorldBegin
        AttributeBegin
          ReverseOrientation
          Shape "sphere"
        AttributeEnd
        Shape "sphere""#,
    );
    assert!(d.shapes[0].reverse_orientation);
    assert!(!d.shapes[1].reverse_orientation);
}

#[test]
fn area_lights_follow_their_shapes() {
    let d = scene(
        r#"WorldBegin
        AttributeBegin
          AreaLightSource "diffuse" "rgb L" [4 5 6] "bool twosided" true
          Shape "disk"
        AttributeEnd
        Shape "disk""#,
    );
    let a = d.shapes[0].area_light.expect("emits");
    assert_close(a.l, Vec3::new(4.0, 5.0, 6.0));
    assert!(a.two_sided);
    assert!(d.shapes[1].area_light.is_none());
}

#[test]
fn relative_names_resolve_against_the_scene_folder_then_the_including_file() {
    let dir = ScratchDir::new("include");
    std::fs::create_dir_all(dir.join("geometry")).unwrap();
    std::fs::write(
        dir.join("main.pbrt"),
        "WorldBegin\nInclude \"geometry/parts.pbrt\"\n",
    )
    .unwrap();
    // pbrt-v4 resolves names in included files against the main file's folder...
    std::fs::write(
        dir.join("geometry/parts.pbrt"),
        "Include \"geometry/sphere.pbrt\"\nInclude \"disk.pbrt\"\n",
    )
    .unwrap();
    std::fs::write(dir.join("geometry/sphere.pbrt"), "Shape \"sphere\"\n").unwrap();
    // ...and lancer falls back to the including file's own folder.
    std::fs::write(dir.join("geometry/disk.pbrt"), "Shape \"disk\"\n").unwrap();
    let d = load(&dir.join("main.pbrt"))
        .unwrap_or_else(|e| panic!("{e}"))
        .desc;
    assert!(matches!(d.shapes[0].geometry, Geometry::Sphere(_)));
    assert!(matches!(d.shapes[1].geometry, Geometry::Disk(_)));
}

#[test]
fn spectrum_files_resolve_like_includes() {
    let dir = ScratchDir::new("spd");
    std::fs::create_dir_all(dir.join("spds")).unwrap();
    std::fs::write(dir.join("spds/flat.spd"), "400 2\n700 2\n").unwrap();
    std::fs::write(
        dir.join("main.pbrt"),
        "WorldBegin\nLightSource \"point\" \"spectrum I\" \"spds/flat.spd\"\n",
    )
    .unwrap();
    let d = load(&dir.join("main.pbrt"))
        .unwrap_or_else(|e| panic!("{e}"))
        .desc;
    let LightDesc::Point(PointDesc { intensity, .. }) = d.lights[0] else {
        panic!()
    };
    // A flat spectrum normalised to luminance 1: nearly white (illuminant E is a bit pink
    // in sRGB's D65 white).
    assert!((luminance(intensity) - 1.0).abs() < 0.01, "{intensity}");
}

#[test]
fn quadrics_and_boxes_take_pbrts_defaults() {
    let loaded = load_pbrt_str(
        r#"WorldBegin
        Shape "cone"
        Shape "paraboloid"
        Shape "hyperboloid"
        Shape "box"
        Shape "cone" "float radius" [2] "float height" [3] "float phimax" [90]
        Shape "paraboloid" "float radius" [2] "float zmin" [0.5] "float zmax" [3] "float phimax" [180]
        Shape "hyperboloid" "point3 p1" [1 0 -1] "point3 p2" [0 1 1] "float phimax" [270]
        Shape "box" "point3 min" [-1 -2 -3] "point3 max" [1 2 3]"#,
        "t.pbrt",
        Path::new("."),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let g: Vec<&Geometry> = loaded.desc.shapes.iter().map(|s| &s.geometry).collect();
    assert_eq!(
        g,
        [
            &Geometry::Cone(ConeDesc {
                radius: 1.0,
                height: 1.0,
                phi_max: 360.0
            }),
            &Geometry::Paraboloid(ParaboloidDesc {
                radius: 1.0,
                z_min: 0.0,
                z_max: 1.0,
                phi_max: 360.0
            }),
            &Geometry::Hyperboloid(HyperboloidDesc {
                p1: Vec3::ZERO,
                p2: Vec3::ONE,
                phi_max: 360.0
            }),
            &Geometry::Box(BoxDesc {
                min: Vec3::splat(-1.0),
                max: Vec3::ONE
            }),
            &Geometry::Cone(ConeDesc {
                radius: 2.0,
                height: 3.0,
                phi_max: 90.0
            }),
            &Geometry::Paraboloid(ParaboloidDesc {
                radius: 2.0,
                z_min: 0.5,
                z_max: 3.0,
                phi_max: 180.0
            }),
            &Geometry::Hyperboloid(HyperboloidDesc {
                p1: Vec3::new(1.0, 0.0, -1.0),
                p2: Vec3::new(0.0, 1.0, 1.0),
                phi_max: 270.0
            }),
            &Geometry::Box(BoxDesc {
                min: Vec3::new(-1.0, -2.0, -3.0),
                max: Vec3::new(1.0, 2.0, 3.0)
            }),
        ]
    );
}

#[test]
fn degenerate_boxes_and_quadrics_are_errors_where_they_are_written() {
    for (text, words) in [
        (
            "Shape \"box\" \"point3 min\" [0 0 0] \"point3 max\" [1 0 1]",
            "below its \"max\"",
        ),
        (
            "Shape \"hyperboloid\" \"point3 p1\" [1 0 1] \"point3 p2\" [0 1 1]",
            "different heights",
        ),
        ("Shape \"cone\" \"float height\" [0]", "positive"),
        ("Shape \"paraboloid\" \"float zmin\" [2]", "less than zmax"),
    ] {
        let e = load_pbrt_str(&format!("WorldBegin\n{text}"), "t.pbrt", Path::new("."))
            .expect_err(text);
        let msg = e.to_string();
        assert!(
            msg.contains("t.pbrt:2:") && msg.contains(words),
            "{text}: {msg}"
        );
    }
}

#[test]
fn loopsubdiv_refines_its_control_mesh() {
    let d = scene(
        r#"WorldBegin
        Shape "loopsubdiv" "integer levels" [2]
            "point3 P" [1 1 1  1 -1 -1  -1 1 -1  -1 -1 1]
            "integer indices" [0 1 2  0 3 1  0 2 3  1 3 2]"#,
    );
    let Geometry::TriangleMesh(m) = &d.shapes[0].geometry else {
        panic!("{:?}", d.shapes[0].geometry)
    };
    // Each level splits every triangle in four; the limit surface gets smooth normals.
    assert_eq!(m.triangle_count(), 4 * 16);
    assert_eq!(m.normals.len(), m.positions.len());
    // pbrt's default is 3 levels.
    let d = scene(
        r#"WorldBegin
        Shape "loopsubdiv" "point3 P" [0 0 0  1 0 0  0 1 0]"#,
    );
    let Geometry::TriangleMesh(m) = &d.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(m.triangle_count(), 64);
}

#[test]
fn color_space_applies_to_rgb_values_inside_its_block() {
    let d = scene(
        r#"ColorSpace "rec2020"
        Film "rgb" "string sensor" "canon_eos_5d_mkiv" "float whitebalance" [5000]
        ColorSpace "srgb"
        WorldBegin
        AttributeBegin
          ColorSpace "aces2065-1"
          LightSource "point" "rgb I" [1 1 1]
        AttributeEnd
        LightSource "point" "rgb I" [1 1 1]
        AttributeBegin
          ColorSpace "rec2020"
          LightSource "point" "rgb I" [0 1 0]
        AttributeEnd"#,
    );
    // The film writes in the space current at `Film`, with its sensor and white balance.
    assert_eq!(d.film.color_space, lancer::spectrum::ColorSpace::Rec2020);
    assert_eq!(d.film.sensor.name(), "canon_eos_5d_mkiv");
    assert_eq!(d.film.white_balance, 5000.0);
    let i: Vec<Vec3> = d
        .lights
        .iter()
        .map(|l| match l {
            LightDesc::Point(PointDesc { intensity, .. }) => Vec3::from(*intensity),
            other => panic!("{other:?}"),
        })
        .collect();
    // ACES white is its D60 illuminant at luminance 1: warmer than sRGB's white.
    assert!(i[0].x > 1.0 && i[0].z < 1.0, "{}", i[0]);
    assert!((luminance(i[0]) - 1.0).abs() < 1e-3, "{}", i[0]);
    // AttributeEnd restores sRGB.
    assert_close(i[1], Vec3::ONE);
    // Rec. 2020 green in linear sRGB (ITU-R BT.2087): (−0.5876, 1.1329, −0.1006).
    let want = Vec3::new(-0.5876, 1.1329, -0.1006);
    assert!((i[2] - want).abs().max_element() < 2e-3, "{}", i[2]);
    let e = load_pbrt_str(r#"ColorSpace "p3""#, "t.pbrt", Path::new("."))
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.starts_with("t.pbrt:1:1: unknown colour space \"p3\""),
        "{e}"
    );
}
