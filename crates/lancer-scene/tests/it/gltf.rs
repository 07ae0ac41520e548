//! glTF 2.0 models read as whole scenes: geometry and node transforms, cameras, materials,
//! punctual lights, the texture and image orientation of a rendered model, and clear errors on
//! broken files.

use crate::common::ScratchDir;
use lancer::Scene;
use lancer::film::{Film, PixelBounds};
use lancer::light::{DistantDesc, PointDesc, SpotDesc};
use lancer::material::MaterialDesc;
use lancer::material::{CoatedDiffuseMaterial, ConductorMaterial, MixMaterial};
use lancer::math::{PackedVec3, Vec3, cross, normalize};
use lancer::render::{RenderSettings, render};
use lancer::scene::desc::{CameraDesc, Geometry, LightDesc, Projection, SceneDesc};
use lancer::texture::{FloatTex, SpectrumTex};
use lancer_scene::load;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/gltf")
        .join(rel)
}

fn load_ok(path: &Path) -> SceneDesc {
    load(path).unwrap_or_else(|e| panic!("{e}")).desc
}

fn mesh(d: &SceneDesc, i: usize) -> &lancer::shape::TriangleMesh {
    match &d.shapes[i].geometry {
        Geometry::TriangleMesh(m) => m,
        g => panic!("not a mesh: {g:?}"),
    }
}

/// Standard base64, for data URIs.
fn base64(bytes: &[u8]) -> String {
    const A: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for k in 0..4 {
            if k <= c.len() {
                out.push(A[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// A unit quad in the z = 0 plane (4 vertices, 2 indexed triangles) as a data-URI buffer:
/// bytes 0..48 positions, 48..60 u16 indices.
fn quad_buffer() -> String {
    let mut b = Vec::new();
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        for c in p {
            b.extend(c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        b.extend(i.to_le_bytes());
    }
    format!("data:application/octet-stream;base64,{}", base64(&b))
}

/// A glTF document around the quad buffer: `extra` holds more top-level members (each ending
/// in a comma), `nodes` the node array, `prim` more members of the primitive.
fn quad_gltf(nodes: &str, prim: &str, extra: &str) -> String {
    format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  {extra}
  "scene": 0,
  "scenes": [{{"nodes": [0]}}],
  "nodes": {nodes},
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1 {prim}}}]}}],
  "buffers": [{{"byteLength": 60, "uri": "{}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                  {{"buffer": 0, "byteOffset": 48, "byteLength": 12}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
      "min": [0, 0, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}}
  ]
}}"#,
        quad_buffer()
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn triangle_and_shared_meshes_load_with_their_transforms() {
    let d = load_ok(&data("Triangle/Triangle.gltf"));
    assert_eq!(d.shapes.len(), 1);
    let m = mesh(&d, 0);
    assert_eq!(m.triangle_count(), 1);
    assert_eq!(
        m.positions,
        [PackedVec3::ZERO, PackedVec3::X, PackedVec3::Y]
    );
    assert_eq!(m.indices, [0, 1, 2]);
    // No light in the file: the default sky and key light.
    assert_eq!(d.lights.len(), 2);

    // SimpleMeshes: one mesh placed by two nodes, the second translated by +1 in x.
    let d = load_ok(&data("SimpleMeshes/SimpleMeshes.gltf"));
    assert_eq!(d.shapes.len(), 2);
    let (Geometry::TriangleMesh(a), Geometry::TriangleMesh(b)) =
        (&d.shapes[0].geometry, &d.shapes[1].geometry)
    else {
        panic!("meshes expected")
    };
    assert!(std::sync::Arc::ptr_eq(a, b), "the mesh is stored once");
    assert_eq!(a.normals.len(), 3);
    assert!(d.shapes[0].object_to_world.is_identity());
    let p = d.shapes[1].object_to_world.point(Vec3::new(0.5, 0.5, 0.0));
    assert!((p - Vec3::new(1.5, 0.5, 0.0)).length() < 1e-6, "{p}");

    let d = load_ok(&data("TextureCoordinateTest/TextureCoordinateTest.gltf"));
    assert_eq!(d.shapes.len(), 5);
    let tris: usize = (0..5).map(|i| mesh(&d, i).triangle_count()).sum();
    assert_eq!(tris, 10);
}

#[test]
fn node_hierarchy_composes_trs_and_matrices() {
    let dir = ScratchDir::new("hierarchy");
    // Parent: a matrix translating by (0, 0, −5) (column-major); child: rotation of 90° about
    // +z (quaternion (0, 0, sin 45°, cos 45°)), scale 2, translation (1, 0, 0):
    // world = parent · T · R · S.
    let nodes = r#"[{"children": [1], "matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,-5,1]},
        {"mesh": 0, "translation": [1, 0, 0], "rotation": [0, 0, 0.70710678, 0.70710678],
         "scale": [2, 2, 2]}]"#;
    let text = quad_gltf(nodes, "", "");
    let d = load_ok(&write(&dir, "h.gltf", &text));
    assert_eq!(d.shapes.len(), 1);
    let t = d.shapes[0].object_to_world;
    // (1, 0, 0) → scale (2, 0, 0) → rotate (0, 2, 0) → translate (1, 2, 0) → parent (1, 2, −5).
    let p = t.point(Vec3::X);
    assert!((p - Vec3::new(1.0, 2.0, -5.0)).length() < 1e-5, "{p}");
    let p = t.point(Vec3::Y);
    assert!((p - Vec3::new(-1.0, 0.0, -5.0)).length() < 1e-5, "{p}");
}

#[test]
fn strips_fans_and_lines() {
    let dir = ScratchDir::new("modes");
    // As a strip, indices 0 1 2 0 2 3 give 4 triangles; as a fan, 4 as well; lines are skipped.
    let strip = load_ok(&write(
        &dir,
        "s.gltf",
        &quad_gltf(r#"[{"mesh": 0}]"#, r#", "mode": 5"#, ""),
    ));
    assert_eq!(
        mesh(&strip, 0).indices,
        [0, 1, 2, 2, 1, 0, 2, 0, 2, 2, 0, 3]
    );
    let fan = load_ok(&write(
        &dir,
        "f.gltf",
        &quad_gltf(r#"[{"mesh": 0}]"#, r#", "mode": 6"#, ""),
    ));
    assert_eq!(mesh(&fan, 0).indices, [1, 2, 0, 2, 0, 0, 0, 2, 0, 2, 3, 0]);
    let err = load(&write(
        &dir,
        "l.gltf",
        &quad_gltf(r#"[{"mesh": 0}]"#, r#", "mode": 1"#, ""),
    ))
    .unwrap_err();
    assert!(err.message.contains("no triangles"), "{err}");
}

/// Where a world point lands on the image (x right, y down, pixels); pbrt's perspective
/// (camera space looks down +z, +x is the image's right, the fov spans the shorter axis).
fn project(cam: &CameraDesc, w: u32, h: u32, p: Vec3) -> (f32, f32) {
    let Projection::Perspective { fov } = cam.projection else {
        panic!("not perspective")
    };
    let c = cam.camera_from_world.point(p);
    assert!(c.z > 0.0, "{p} is behind the camera");
    let t = (fov.to_radians() * 0.5).tan();
    let (sx, sy) = (c.x / (c.z * t), c.y / (c.z * t));
    let aspect = w as f32 / h as f32;
    let (hw, hh) = if aspect > 1.0 {
        (aspect, 1.0)
    } else {
        (1.0, 1.0 / aspect)
    };
    (
        (sx + hw) / (2.0 * hw) * w as f32,
        (hh - sy) / (2.0 * hh) * h as f32,
    )
}

#[test]
fn cameras_are_read_from_their_nodes() {
    let d = load_ok(&data("Cameras/Cameras.gltf"));
    // The first camera: perspective, yfov 0.7 rad, aspect 1, at (0.5, 0.5, 3) looking down −z.
    let Projection::Perspective { fov } = d.camera.projection else {
        panic!("perspective expected")
    };
    assert!((fov - 0.7f32.to_degrees()).abs() < 1e-3, "{fov}");
    assert_eq!((d.film.xresolution, d.film.yresolution), (600, 600));
    let c = d.camera.camera_from_world.point(Vec3::new(0.5, 0.5, 0.0));
    assert!((c - Vec3::new(0.0, 0.0, 3.0)).length() < 1e-5, "{c}");
    // World +x is the image's right, +y its top: not mirrored.
    let (x0, y0) = project(&d.camera, 600, 600, Vec3::new(0.5, 0.5, 0.0));
    let (x1, _) = project(&d.camera, 600, 600, Vec3::new(1.0, 0.5, 0.0));
    let (_, y1) = project(&d.camera, 600, 600, Vec3::new(0.5, 1.0, 0.0));
    assert!((x0 - 300.0).abs() < 0.01 && (y0 - 300.0).abs() < 0.01);
    // tan(0.35) = 0.365: 0.5 at distance 3 is 0.457 of the half-image.
    assert!(
        (x1 - 300.0 - 300.0 * 0.5 / 3.0 / 0.35f32.tan()).abs() < 0.5,
        "{x1}"
    );
    assert!(y1 < y0);

    // The same file with the orthographic camera first.
    let text = std::fs::read_to_string(data("Cameras/Cameras.gltf"))
        .unwrap()
        .replace(r#""nodes" : [ 0, 1, 2 ]"#, r#""nodes" : [ 0, 2, 1 ]"#);
    let dir = ScratchDir::new("ortho");
    std::fs::copy(
        data("Cameras/simpleSquare.bin"),
        dir.join("simpleSquare.bin"),
    )
    .unwrap();
    let d = load_ok(&write(&dir, "o.gltf", &text));
    assert_eq!(d.camera.projection, Projection::Orthographic);
    assert_eq!(d.camera.screen_window, Some([-1.0, 1.0, -1.0, 1.0]));
    assert_eq!((d.film.xresolution, d.film.yresolution), (600, 600));
}

#[test]
fn metallic_roughness_materials_map_to_lancer_materials() {
    let dir = ScratchDir::new("materials");
    let nodes =
        r#"[{"children": [1, 2, 3, 4]}, {"mesh": 0}, {"mesh": 1}, {"mesh": 2}, {"mesh": 3}]"#;
    let materials = r#""materials": [
        {"pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.4, 0.6, 1], "metallicFactor": 0.5,
         "roughnessFactor": 0.5}},
        {"pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.6, 0.2, 1], "metallicFactor": 1,
         "roughnessFactor": 0.2}},
        {"pbrMetallicRoughness": {"metallicFactor": 0}, "alphaMode": "MASK",
         "alphaCutoff": 0.5, "emissiveFactor": [1, 0.5, 0.25],
         "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4}}},
        {"pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.3], "metallicFactor": 0},
         "alphaMode": "BLEND", "doubleSided": true}
    ],"#;
    let mut text = quad_gltf(nodes, "", materials);
    // Four meshes, one per material, on the same accessors.
    let prims: Vec<String> = (0..4)
        .map(|m| {
            format!(r#"{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "material": {m}}}]}}"#)
        })
        .collect();
    let old = r#""meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1 }]}]"#;
    assert!(text.contains(old));
    text = text.replace(old, &format!(r#""meshes": [{}]"#, prims.join(",")));
    let d = load_ok(&write(&dir, "m.gltf", &text));
    assert_eq!(d.shapes.len(), 4);
    let mat = |i: usize| &d.materials[d.shapes[i].material as usize];

    // Half metallic: a mix of coated diffuse and conductor, α = 0.5² = 0.25.
    let MaterialDesc::Mix(MixMaterial {
        materials: [a, b],
        amount,
    }) = *mat(0)
    else {
        panic!("{:?}", mat(0))
    };
    assert_eq!(amount, FloatTex::Const(0.5));
    let base = SpectrumTex::Const(Vec3::new(0.2, 0.4, 0.6));
    match &d.materials[a as usize] {
        MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance,
            uroughness,
            eta,
            remap_roughness,
            ..
        }) => {
            assert_eq!(*reflectance, base);
            assert_eq!(*uroughness, FloatTex::Const(0.25));
            assert_eq!(*eta, lancer::spectrum::Ior::Constant(1.5));
            assert!(!remap_roughness);
        }
        m => panic!("{m:?}"),
    }
    match &d.materials[b as usize] {
        MaterialDesc::Conductor(ConductorMaterial {
            reflectance,
            uroughness,
            ..
        }) => {
            assert_eq!(*reflectance, Some(base));
            assert_eq!(*uroughness, FloatTex::Const(0.25));
        }
        m => panic!("{m:?}"),
    }
    // Fully metallic: a conductor alone, α = 0.04.
    match mat(1) {
        MaterialDesc::Conductor(ConductorMaterial {
            reflectance,
            uroughness,
            ..
        }) => {
            assert_eq!(
                *reflectance,
                Some(SpectrumTex::Const(Vec3::new(0.9, 0.6, 0.2)))
            );
            let FloatTex::Const(r) = *uroughness else {
                panic!()
            };
            assert!((r - 0.04).abs() < 1e-6);
        }
        m => panic!("{m:?}"),
    }
    // Emissive × strength, one-sided; MASK with the default white alpha 1 ≥ 0.5: solid.
    let l = d.shapes[2].area_light.expect("an area light");
    assert_eq!(l.l, Vec3::new(4.0, 2.0, 1.0));
    assert!(!l.two_sided);
    assert_eq!(d.shapes[2].alpha, Some(FloatTex::Const(1.0)));
    assert!(matches!(mat(2), MaterialDesc::CoatedDiffuse(_)));
    // BLEND: the factor's alpha as stochastic alpha.
    assert_eq!(d.shapes[3].alpha, Some(FloatTex::Const(0.3)));
    assert_eq!(d.shapes[0].alpha, None);
    // An emitter is a light: no default lights added.
    assert!(d.lights.is_empty());
}

#[test]
fn punctual_lights_are_placed_by_their_nodes() {
    let dir = ScratchDir::new("lights");
    let extra = r#""extensionsUsed": ["KHR_lights_punctual"],
      "extensions": {"KHR_lights_punctual": {"lights": [
        {"type": "point", "color": [1, 0.5, 0.25], "intensity": 683},
        {"type": "spot", "intensity": 1366, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}},
        {"type": "directional", "intensity": 2049}
      ]}},"#;
    // A rotation of −90° about x turns the node's −z axis into −y (shining down).
    let down = "[-0.70710678, 0, 0, 0.70710678]";
    let nodes = format!(
        r#"[{{"children": [1, 2, 3, 4]}}, {{"mesh": 0}},
        {{"translation": [1, 2, 3], "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}},
        {{"translation": [0, 5, 0], "rotation": {down}, "extensions": {{"KHR_lights_punctual": {{"light": 1}}}}}},
        {{"rotation": {down}, "extensions": {{"KHR_lights_punctual": {{"light": 2}}}}}}]"#
    );
    let d = load_ok(&write(&dir, "l.gltf", &quad_gltf(&nodes, "", extra)));
    assert_eq!(d.lights.len(), 3, "{:?}", d.lights);
    let close = |a: Vec3, b: Vec3| (a - b).length() < 1e-5;
    match &d.lights[0] {
        LightDesc::Point(PointDesc { from, intensity }) => {
            assert!(close(*from, Vec3::new(1.0, 2.0, 3.0)));
            // 683 cd → 1 W/sr, times the colour.
            assert!(close(*intensity, Vec3::new(1.0, 0.5, 0.25)), "{intensity}");
        }
        l => panic!("{l:?}"),
    }
    match &d.lights[1] {
        LightDesc::Spot(SpotDesc {
            from,
            to,
            intensity,
            cone_angle,
            cone_delta_angle,
        }) => {
            assert!(close(*from, Vec3::new(0.0, 5.0, 0.0)));
            assert!(close(normalize(*to - *from), -Vec3::Y), "{to}");
            assert!(close(*intensity, Vec3::splat(2.0)));
            assert!((cone_angle - 0.5f32.to_degrees()).abs() < 1e-4);
            assert!((cone_delta_angle - 0.3f32.to_degrees()).abs() < 1e-4);
        }
        l => panic!("{l:?}"),
    }
    match &d.lights[2] {
        LightDesc::Distant(DistantDesc { direction, l }) => {
            // Direction towards the light: up.
            assert!(close(normalize(*direction), Vec3::Y), "{direction}");
            assert!(close(*l, Vec3::splat(3.0)));
        }
        l => panic!("{l:?}"),
    }
}

/// Renders `d` at `w`×`h` with `spp` samples and returns the linear pixels.
fn render_image(mut d: SceneDesc, w: u32, h: u32, spp: u32) -> Vec<Vec3> {
    d.film.xresolution = w;
    d.film.yresolution = h;
    let scene = Scene::build(&d).unwrap();
    let bounds = PixelBounds {
        x0: 0,
        x1: w as i32,
        y0: 0,
        y1: h as i32,
    };
    let settings = RenderSettings {
        samples: 0..spp,
        spp,
        seed: 1,
        max_component_value: f32::INFINITY,
        ..RenderSettings::from_desc(&d)
    };
    let mut film = Film::new(w, h, bounds);
    render(
        &scene,
        &settings,
        &mut film,
        &|_| {},
        &AtomicBool::new(false),
    );
    film.image(1.0)
}

#[test]
fn texture_coordinate_test_renders_the_right_way_round() {
    let d = load_ok(&data("TextureCoordinateTest/TextureCoordinateTest.gltf"));
    let (w, h) = (240u32, 180u32);
    // The four textured squares (the back plane has no uv); the top-left one is the square
    // with the smallest x and the largest y.
    let boxes: Vec<(Vec3, Vec3)> = (0..d.shapes.len())
        .filter(|&i| !mesh(&d, i).uvs.is_empty())
        .map(|i| {
            let m = mesh(&d, i);
            let t = d.shapes[i].object_to_world;
            let ps: Vec<Vec3> = m.positions.iter().map(|&p| t.point(p.into())).collect();
            let lo = ps.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
            let hi = ps.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
            (lo, hi)
        })
        .collect();
    assert_eq!(boxes.len(), 4);
    let top_left = *boxes
        .iter()
        .min_by(|a, b| (a.0.x - a.0.y).total_cmp(&(b.0.x - b.0.y)))
        .unwrap();
    let top_right = *boxes
        .iter()
        .max_by(|a, b| (a.0.x + a.0.y).total_cmp(&(b.0.x + b.0.y)))
        .unwrap();
    // A point of a square at fractions (fx from its left, fy from its top).
    let at = |b: (Vec3, Vec3), fx: f32, fy: f32| {
        Vec3::new(
            b.0.x + fx * (b.1.x - b.0.x),
            b.1.y - fy * (b.1.y - b.0.y),
            b.1.z,
        )
    };
    let img = render_image(d.clone(), w, h, 16);
    let patch = |p: Vec3| {
        let (x, y) = project(&d.camera, w, h, p);
        let (x, y) = (x as i32, y as i32);
        let mut sum = Vec3::ZERO;
        for dy in -1..=1 {
            for dx in -1..=1 {
                sum += img[((y + dy) as u32 * w + (x + dx) as u32) as usize];
            }
        }
        ((x, y), sum / 9.0)
    };
    // The yellow square is on the image's left and the red one on its right (not mirrored).
    let ((xl, yl), yellow) = patch(at(top_left, 0.5, 0.85));
    let ((xr, _), red) = patch(at(top_right, 0.5, 0.85));
    assert!(
        xl < w as i32 / 2 && xr > w as i32 / 2 && yl < h as i32 * 6 / 10,
        "{xl} {xr} {yl}"
    );
    assert!(
        yellow.x > 3.0 * yellow.z && yellow.y > 3.0 * yellow.z,
        "{yellow}"
    );
    assert!(red.x > 3.0 * red.y && red.x > 3.0 * red.z, "{red}");
}

#[test]
fn texture_lookups_follow_gltf_uv_orientation() {
    // glTF's (0, 0) is the image's top-left texel. The top-left square of TextureCoordinateTest
    // maps its top-left corner to uv (0, 0) and its bottom-right to (0.4, 0.4) (the model's
    // README): the colour lancer looks up at a point (fx from the left, fy from the top) of
    // the square must be the PNG's texel at (0.4·fx, 0.4·fy) × baseColorFactor (0.8, 0.8, 0).
    // The model is built so that a flipped v gives the same marks (only the text differs), so
    // many points are compared, against both hypotheses.
    let d = load_ok(&data("TextureCoordinateTest/TextureCoordinateTest.gltf"));
    let scene = Scene::build(&d).unwrap();
    let png = lancer_scene::image_read::read_image(
        &data("TextureCoordinateTest/TextureCoordinateTemplate.png"),
        lancer_scene::image_read::Encoding::Srgb,
    )
    .unwrap()
    .rgb;
    let texel = |u: f32, v: f32| {
        let x = ((u * png.width as f32) as u32).min(png.width - 1);
        let y = ((v * png.height as f32) as u32).min(png.height - 1);
        Vec3::from(png.texels[(y * png.width + x) as usize]) * Vec3::new(0.8, 0.8, 0.0)
    };
    let i = (0..d.shapes.len())
        .filter(|&i| !mesh(&d, i).uvs.is_empty())
        .min_by(|&a, &b| {
            let key = |i: usize| {
                let t = d.shapes[i].object_to_world;
                let c = t.point(mesh(&d, i).position(0));
                c.x - c.y
            };
            key(a).total_cmp(&key(b))
        })
        .unwrap();
    let t = d.shapes[i].object_to_world;
    let ps: Vec<Vec3> = mesh(&d, i)
        .positions
        .iter()
        .map(|&p| t.point(p.into()))
        .collect();
    let lo = ps.iter().fold(Vec3::INFINITY, |a, &p| a.min(p));
    let hi = ps.iter().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
    let (mut err_right, mut err_flipped, mut n) = (0.0, 0.0, 0);
    for a in 0..120 {
        for b in 0..120 {
            let (fx, fy) = ((a as f32 + 0.5) / 120.0, (b as f32 + 0.5) / 120.0);
            let o = Vec3::new(
                lo.x + fx * (hi.x - lo.x),
                hi.y - fy * (hi.y - lo.y),
                hi.z + 1.0,
            );
            let hit = scene
                .intersect(&lancer::ray::Ray::new(o, -Vec3::Z))
                .expect("the square is there");
            let lancer::material::Material::CoatedDiffuse(CoatedDiffuseMaterial {
                reflectance,
                ..
            }) = *scene.material(scene.prim(hit.prim).material)
            else {
                panic!("coated diffuse expected")
            };
            let c = scene
                .textures()
                .spectrum(reflectance, &Scene::tex_coord(&hit.si));
            let (right, flipped) = (texel(0.4 * fx, 0.4 * fy), texel(0.4 * fx, 1.0 - 0.4 * fy));
            // Only the points where the two hypotheses differ tell them apart.
            if (right - flipped).abs().element_sum() < 0.3 {
                continue;
            }
            err_right += (c - right).abs().element_sum();
            err_flipped += (c - flipped).abs().element_sum();
            n += 1;
        }
    }
    assert!(n >= 100, "only {n} telling points");
    let (err_right, err_flipped) = (err_right / n as f32, err_flipped / n as f32);
    assert!(
        err_right < 0.25 * err_flipped,
        "mean error over {n} points {err_right} (v as glTF says), {err_flipped} (v flipped)"
    );
}

/// A PNG of `w`×`h` 8-bit RGB pixels, row 0 at the top.
fn png_bytes(w: u32, h: u32, rgb: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header().unwrap();
    writer.write_image_data(rgb).unwrap();
    writer.finish().unwrap();
    out
}

#[test]
fn embedded_images_are_decoded_and_placed_by_texcoords() {
    // A 2×2 image: red and green on the top row, blue and white below; the quad's corners take
    // glTF uv (0, 1) at (0, 0, 0) … (0, 0) at (0, 1, 0), so the image stands upright on it.
    let png = png_bytes(2, 2, &[255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255]);
    let mut buf = Vec::new();
    for p in [
        [0.0f32, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ] {
        for c in p {
            buf.extend(c.to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        buf.extend(i.to_le_bytes());
    }
    for t in [[0.0f32, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]] {
        for c in t {
            buf.extend(c.to_le_bytes());
        }
    }
    let image_offset = buf.len();
    buf.extend(&png);
    let text = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_0": 2}}, "indices": 1, "material": 0}}]}}],
  "materials": [{{"pbrMetallicRoughness": {{"baseColorTexture": {{"index": 0}}, "metallicFactor": 0}}}}],
  "textures": [{{"source": 0, "sampler": 0}}],
  "samplers": [{{"magFilter": 9728, "wrapS": 33071, "wrapT": 33071}}],
  "images": [{{"bufferView": 3, "mimeType": "image/png"}}],
  "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{b64}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}},
                  {{"buffer": 0, "byteOffset": 48, "byteLength": 12}},
                  {{"buffer": 0, "byteOffset": 60, "byteLength": 32}},
                  {{"buffer": 0, "byteOffset": {image_offset}, "byteLength": {png_len}}}],
  "accessors": [
    {{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}},
    {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}},
    {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}}
  ]}}"#,
        len = buf.len(),
        b64 = base64(&buf),
        png_len = png.len()
    );
    let dir = ScratchDir::new("embedded");
    let d = load_ok(&write(&dir, "e.gltf", &text));
    let scene = Scene::build(&d).unwrap();
    let colour_at = |x: f32, y: f32| {
        let hit = scene
            .intersect(&lancer::ray::Ray::new(Vec3::new(x, y, 1.0), -Vec3::Z))
            .expect("the quad is there");
        let lancer::material::Material::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance, ..
        }) = *scene.material(scene.prim(hit.prim).material)
        else {
            panic!("coated diffuse expected")
        };
        scene
            .textures()
            .spectrum(reflectance, &Scene::tex_coord(&hit.si))
    };
    let close = |a: Vec3, b: Vec3| (a - b).abs().max_element() < 1e-3;
    assert!(
        close(colour_at(0.25, 0.75), Vec3::X),
        "{}",
        colour_at(0.25, 0.75)
    );
    assert!(
        close(colour_at(0.75, 0.75), Vec3::Y),
        "{}",
        colour_at(0.75, 0.75)
    );
    assert!(
        close(colour_at(0.25, 0.25), Vec3::Z),
        "{}",
        colour_at(0.25, 0.25)
    );
    assert!(
        close(colour_at(0.75, 0.25), Vec3::ONE),
        "{}",
        colour_at(0.75, 0.25)
    );
}

#[test]
fn a_glb_reads_its_buffer_from_the_binary_chunk() {
    // The quad's document with its buffer in the GLB's BIN chunk (no uri), translated by +z.
    let uri = quad_buffer();
    let bin = lancer_scene::gltf::data::base64_decode(uri.rsplit(',').next().unwrap()).unwrap();
    assert_eq!(bin.len(), 60);
    let json = quad_gltf(r#"[{"mesh": 0, "translation": [0, 0, 2]}]"#, "", "")
        .replace(&format!(r#", "uri": "{uri}""#), "");
    let mut json = json.into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend(((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    glb.extend((json.len() as u32).to_le_bytes());
    glb.extend(b"JSON");
    glb.extend(&json);
    glb.extend((bin.len() as u32).to_le_bytes());
    glb.extend(b"BIN\0");
    glb.extend(&bin);
    let dir = ScratchDir::new("glb");
    let p = dir.join("quad.glb");
    std::fs::write(&p, &glb).unwrap();
    let d = load_ok(&p);
    assert_eq!(mesh(&d, 0).triangle_count(), 2);
    assert_eq!(mesh(&d, 0).position(2), Vec3::new(1.0, 1.0, 0.0));
    let q = d.shapes[0].object_to_world.point(Vec3::ONE);
    assert!((q - Vec3::new(1.0, 1.0, 3.0)).length() < 1e-6, "{q}");
}

#[test]
fn broken_files_give_clear_errors() {
    let dir = ScratchDir::new("broken");
    let expect_err = |p: &Path, needle: &str| {
        let e = load(p).expect_err("must fail").to_string();
        assert!(e.contains(&p.display().to_string()), "{e}");
        assert!(e.contains(needle), "'{needle}' not in: {e}");
    };
    // A GLB whose JSON chunk claims more bytes than the file has.
    let json = br#"{"asset":{"version":"2.0"}}  "#;
    let mut glb = b"glTF".to_vec();
    glb.extend(2u32.to_le_bytes());
    glb.extend((12 + 8 + json.len() as u32).to_le_bytes());
    glb.extend((json.len() as u32 + 100).to_le_bytes());
    glb.extend(0x4E4F_534Au32.to_le_bytes());
    glb.extend(json);
    let p = dir.join("chunk.glb");
    std::fs::write(&p, &glb).unwrap();
    expect_err(&p, "claims");
    // A buffer file that is not there.
    let text = quad_gltf(r#"[{"mesh": 0}]"#, "", "").replace(&quad_buffer(), "missing.bin");
    expect_err(&write(&dir, "nobuf.gltf", &text), "missing.bin");
    // An accessor reading past its buffer view.
    let text = quad_gltf(r#"[{"mesh": 0}]"#, "", "").replace(
        r#""count": 4, "type": "VEC3""#,
        r#""count": 40, "type": "VEC3""#,
    );
    expect_err(&write(&dir, "acc.gltf", &text), "accessor 0");
    // An index past the vertices: the quad's indices read as positions of a 2-vertex mesh.
    let text = quad_gltf(r#"[{"mesh": 0}]"#, "", "").replace(
        r#""count": 4, "type": "VEC3""#,
        r#""count": 2, "type": "VEC3""#,
    );
    expect_err(&write(&dir, "idx.gltf", &text), "out of range");
    // Absurd counts and offsets are refused, not allocated or overflowed.
    let text = quad_gltf(r#"[{"mesh": 0}]"#, "", "").replace(
        r#"{"bufferView": 0, "componentType": 5126, "count": 4,"#,
        r#"{"bufferView": 0, "componentType": 5126, "count": 4000000000,"#,
    );
    expect_err(&write(&dir, "huge.gltf", &text), "too many");
    let text = quad_gltf(r#"[{"mesh": 0}]"#, "", "").replace(
        r#"{"bufferView": 0, "componentType": 5126, "count": 4,"#,
        r#"{"bufferView": 0, "byteOffset": 18446744073709551000, "componentType": 5126, "count": 4,"#,
    );
    assert!(load(&write(&dir, "offset.gltf", &text)).is_err());
    // A buffer shorter than it says.
    let text = quad_gltf(r#"[{"mesh": 0}]"#, "", "")
        .replace(r#""byteLength": 60"#, r#""byteLength": 600"#);
    expect_err(&write(&dir, "short.gltf", &text), "600");
    // Not JSON.
    expect_err(&write(&dir, "junk.gltf", "{ nope"), "JSON");
    // A required extension lancer does not know is named.
    let text = quad_gltf(
        r#"[{"mesh": 0}]"#,
        "",
        r#""extensionsRequired": ["EXT_nope"],"#,
    );
    expect_err(&write(&dir, "ext.gltf", &text), "EXT_nope");
}

/// Box.glb with its GLB chunks rebuilt: the JSON passed through `edit_json`, and the binary
/// chunk through `edit_bin`.
fn edited_box(
    dir: &Path,
    name: &str,
    edit_json: impl Fn(&str) -> String,
    edit_bin: impl Fn(&mut Vec<u8>),
) -> PathBuf {
    let b = std::fs::read(data("Box.glb")).unwrap();
    let jlen = u32::from_le_bytes(b[12..16].try_into().unwrap()) as usize;
    let json = edit_json(std::str::from_utf8(&b[20..20 + jlen]).unwrap());
    let mut json = json.into_bytes();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let bstart = 20 + jlen;
    let blen = u32::from_le_bytes(b[bstart..bstart + 4].try_into().unwrap()) as usize;
    let mut bin = b[bstart + 8..bstart + 8 + blen].to_vec();
    edit_bin(&mut bin);
    let mut out = b"glTF".to_vec();
    out.extend(2u32.to_le_bytes());
    out.extend(((12 + 8 + json.len() + 8 + bin.len()) as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(0x4E4F_534Au32.to_le_bytes());
    out.extend(&json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(0x004E_4942u32.to_le_bytes());
    out.extend(&bin);
    let p = dir.join(name);
    std::fs::write(&p, out).unwrap();
    p
}

#[test]
fn draco_box_decodes_to_the_unit_cube() {
    let d = load_ok(&data("Box.glb"));
    assert_eq!(d.shapes.len(), 1);
    let m = mesh(&d, 0);
    // The Khronos Box: 6 faces × 2 triangles over 24 vertices (4 per face, for flat normals).
    assert_eq!(m.triangle_count(), 12);
    assert_eq!(m.positions.len(), 24);
    // The unit cube centred at the origin: every coordinate is ±0.5 (Draco quantizes
    // positions, hence the tolerance), and both signs occur on every axis.
    for p in &m.positions {
        for c in p.to_array() {
            assert!((c.abs() - 0.5).abs() < 1e-3, "{p}");
        }
    }
    let lo = m
        .positions
        .iter()
        .fold(Vec3::INFINITY, |a, &p| a.min(p.into()));
    let hi = m
        .positions
        .iter()
        .fold(Vec3::NEG_INFINITY, |a, &p| a.max(p.into()));
    assert!((lo + Vec3::splat(0.5)).length() < 2e-3, "{lo}");
    assert!((hi - Vec3::splat(0.5)).length() < 2e-3, "{hi}");
    // Every corner of the cube is there (3 vertices each, one per face meeting there).
    for corner in 0..8 {
        let c = Vec3::new(
            if corner & 1 == 0 { -0.5 } else { 0.5 },
            if corner & 2 == 0 { -0.5 } else { 0.5 },
            if corner & 4 == 0 { -0.5 } else { 0.5 },
        );
        let n = m
            .positions
            .iter()
            .filter(|&&p| (Vec3::from(p) - c).length() < 2e-3)
            .count();
        assert_eq!(n, 3, "corner {c}");
    }
    // Normals are unit axis vectors, and each triangle's vertices share its face's normal,
    // which points out of the cube (away from the centre) and agrees with the winding.
    assert_eq!(m.normals.len(), 24);
    for n in &m.normals {
        let a = n.abs();
        assert!(
            (a.max_element() - 1.0).abs() < 1e-2 && a.min_element() < 1e-2,
            "{n}"
        );
        assert!((n.length() - 1.0).abs() < 1e-2, "{n}");
    }
    let mut faces_seen = Vec::new();
    for t in m.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| m.position(t[k] as usize));
        let geo = normalize(cross(b - a, c - a));
        let centre = (a + b + c) / 3.0;
        for &i in t {
            assert!(m.normal(i as usize).dot(geo) > 0.99, "{t:?}");
        }
        assert!(geo.dot(centre) > 0.0, "{t:?} faces inwards");
        faces_seen.push(geo.round());
    }
    for axis in [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z] {
        assert_eq!(
            faces_seen.iter().filter(|f| **f == axis).count(),
            2,
            "{axis}"
        );
    }
    // Not textured: no uvs.
    assert!(m.uvs.is_empty());
}

#[test]
fn draco_box_textured_has_its_uvs() {
    let d = load_ok(&data("BoxTextured.glb"));
    let m = mesh(&d, 0);
    assert_eq!(m.triangle_count(), 12);
    assert_eq!(m.uvs.len(), 24);
    // The file's TEXCOORD_0 accessor declares min (0, 0) and max (6, 1): u repeats the
    // texture across the faces; the decoded values must fill that range (v' = 1 − v stays
    // in [0, 1]).
    let lo = m.uvs.iter().fold(glam::Vec2::INFINITY, |a, &p| a.min(p));
    let hi = m
        .uvs
        .iter()
        .fold(glam::Vec2::NEG_INFINITY, |a, &p| a.max(p));
    assert!(lo.abs().max_element() < 1e-3, "{lo}");
    assert!((hi - glam::Vec2::new(6.0, 1.0)).length() < 1e-2, "{hi}");
    // Each face maps one unit tile of the texture (u in [k, k+1], v in [0, 1]) onto its square:
    // each triangle is half of it, |(b − a) ⊥ (c − a)| = 2 · ½ = 1, and its corners lie on
    // the tile's corners.
    for t in m.indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| m.uvs[t[k] as usize]);
        assert!(((b - a).perp_dot(c - a).abs() - 1.0).abs() < 1e-2, "{t:?}");
        let k = a.x.min(b.x).min(c.x).round();
        for p in [a, b, c] {
            assert!(
                (p.x - k).abs() < 2e-3 || (p.x - k - 1.0).abs() < 2e-3,
                "{p}"
            );
            assert!(p.y.abs() < 2e-3 || (p.y - 1.0).abs() < 2e-3, "{p}");
        }
    }
    // The material samples the embedded image.
    assert!(
        format!("{:?}", d.materials[0]).contains("Tex("),
        "{:?}",
        d.materials[0]
    );
    assert!(
        d.spectrum_textures
            .iter()
            .any(|t| matches!(t, lancer::texture::SpectrumTextureDesc::Image(_)))
    );
}

#[test]
fn broken_draco_data_gives_clear_errors() {
    let dir = ScratchDir::new("draco");
    let expect_err = |p: &Path, needles: &[&str]| {
        let e = load(p).expect_err("must fail").to_string();
        assert!(e.contains(&p.display().to_string()), "{e}");
        for needle in needles {
            assert!(e.contains(needle), "'{needle}' not in: {e}");
        }
    };
    // The Draco stream truncated to 40 of its 118 bytes.
    let p = edited_box(
        &dir,
        "truncated.glb",
        |j| j.replace(r#""byteLength":118"#, r#""byteLength":40"#),
        |_| {},
    );
    expect_err(&p, &["mesh 0 'Mesh' primitive 0", "Draco", "40 bytes"]);
    // Its body overwritten with junk after the header.
    let p = edited_box(
        &dir,
        "corrupt.glb",
        |j| j.to_string(),
        |b| {
            for (i, x) in b[11..118].iter_mut().enumerate() {
                *x = (i as u8).wrapping_mul(97) ^ 0xA5;
            }
        },
    );
    expect_err(&p, &["mesh 0 'Mesh' primitive 0", "Draco"]);
    // Not Draco at all (the magic is wrong).
    let p = edited_box(
        &dir,
        "magic.glb",
        |j| j.to_string(),
        |b| b[..5].copy_from_slice(b"NOPE!"),
    );
    expect_err(&p, &["Draco"]);
    // An accessor count the decoded data does not match.
    let p = edited_box(
        &dir,
        "count.glb",
        |j| j.replace(r#""count":36"#, r#""count":30"#),
        |_| {},
    );
    expect_err(&p, &["declares 30", "36"]);
    // An attribute id the stream does not have.
    let p = edited_box(
        &dir,
        "attr.glb",
        |j| j.replace(r#""POSITION":1}"#, r#""POSITION":7}"#),
        |_| {},
    );
    expect_err(&p, &["POSITION", "attribute 7"]);
}

#[test]
fn shared_samples_load() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/scenes/gltf");
    if !root.is_dir() {
        eprintln!(
            "note: {} is absent; the shared glTF samples are not checked",
            root.display()
        );
        return;
    }
    for model in [
        "Duck/glTF/Duck.gltf",
        "MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf",
        "spot.glb",
        "Box.glb",
        "BoxTextured.glb",
    ] {
        let d = load_ok(&root.join(model));
        assert!(!d.shapes.is_empty(), "{model}");
    }
    // spot.glb, exported by Blender: a 16:9 camera and a sun of 3 W/m² written as 2049 lux.
    let d = load_ok(&root.join("spot.glb"));
    assert_eq!((d.film.xresolution, d.film.yresolution), (1067, 600));
    assert_eq!(d.lights.len(), 1);
    let LightDesc::Distant(DistantDesc { l, .. }) = d.lights[0] else {
        panic!("{:?}", d.lights)
    };
    assert!((l - Vec3::splat(3.0)).length() < 1e-4, "{l}");
}

/// Files the fuzzer found crashing the reader (`fuzz/fuzz_targets/gltf.rs`): each must now be a
/// clear error naming the file.
/// (file under tests/data/gltf, words the error must contain)
const FUZZ_REGRESSIONS: &[(&str, &str)] = &[
    (
        "fuzz/position-accessor-out-of-range.gltf",
        "refers to accessor",
    ),
    (
        "fuzz/image-without-source.glb",
        "has neither a uri nor a bufferView",
    ),
];

#[test]
fn fuzz_regressions_are_clear_errors() {
    for &(file, words) in FUZZ_REGRESSIONS {
        let path = data(file);
        let e = lancer_scene::load(&path).expect_err(file).to_string();
        assert!(e.contains(file.rsplit('/').next().unwrap()), "{e}");
        assert!(e.contains(words), "{e}");
    }
}
