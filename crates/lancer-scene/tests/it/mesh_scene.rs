//! Bare `.obj` and `.ply` meshes loaded as whole scenes: a camera that sees the mesh the right
//! way round, lights, materials from the MTL; and (when the shared scene folder is there) the
//! real meshes.

use crate::common::ScratchDir;
use lancer::material::DiffuseMaterial;
use lancer::math::Vec3;
use lancer::scene::desc::{CameraDesc, Geometry, LightDesc, Projection, SceneDesc};
use lancer_scene::load;
use std::path::{Path, PathBuf};

/// Where a world point lands on the image, in pixels (x right, y down), or `None` behind the
/// camera. pbrt's perspective: the fov spans the shorter axis.
fn project(cam: &CameraDesc, xres: u32, yres: u32, p: Vec3) -> Option<(f32, f32)> {
    let Projection::Perspective { fov } = cam.projection else {
        panic!("not perspective")
    };
    let c = cam.camera_from_world.point(p);
    if c.z <= 0.0 {
        return None;
    }
    let t = (fov.to_radians() * 0.5).tan();
    let (sx, sy) = (c.x / (c.z * t), c.y / (c.z * t));
    let aspect = xres as f32 / yres as f32;
    let (hw, hh) = if aspect > 1.0 {
        (aspect, 1.0)
    } else {
        (1.0, 1.0 / aspect)
    };
    Some((
        (sx + hw) / (2.0 * hw) * xres as f32,
        (hh - sy) / (2.0 * hh) * yres as f32,
    ))
}

fn bounds(d: &SceneDesc) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for s in &d.shapes {
        let Geometry::TriangleMesh(m) = &s.geometry else {
            panic!("not a mesh")
        };
        for &p in &m.positions {
            lo = lo.min(p.into());
            hi = hi.max(p.into());
        }
    }
    (lo, hi)
}

/// The whole bounding box is in the image, the centre near the middle, +x to the right and +y
/// up; there is a sky and a key light.
fn check_framing(d: &SceneDesc) {
    let (w, h) = (d.film.xresolution, d.film.yresolution);
    assert_eq!((w, h), (800, 600));
    let (lo, hi) = bounds(d);
    let centre = (lo + hi) * 0.5;
    let (cx, cy) = project(&d.camera, w, h, centre).expect("centre in front of the camera");
    assert!(
        (cx - w as f32 / 2.0).abs() < 1.0 && (cy - h as f32 / 2.0).abs() < 1.0,
        "{cx} {cy}"
    );
    for i in 0..8 {
        let corner = Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        );
        let (x, y) = project(&d.camera, w, h, corner).expect("corner in front");
        assert!(
            (0.0..w as f32).contains(&x) && (0.0..h as f32).contains(&y),
            "{corner} at {x} {y}"
        );
    }
    let size = (hi - lo).length();
    let (rx, _) = project(&d.camera, w, h, centre + Vec3::X * size * 0.1).unwrap();
    let (_, uy) = project(&d.camera, w, h, centre + Vec3::Y * size * 0.1).unwrap();
    assert!(rx > cx, "+x must appear on the right");
    assert!(uy < cy, "+y must appear up");
    assert!(
        d.lights
            .iter()
            .any(|l| matches!(l, LightDesc::UniformInfinite(_)))
    );
    assert!(d.lights.iter().any(|l| matches!(l, LightDesc::Distant(_))));
}

#[test]
fn an_obj_file_becomes_a_framed_lit_scene() {
    let dir = ScratchDir::new("obj");
    // A box 2 × 1 × 1 off the origin.
    let mut text = String::new();
    for i in 0..8 {
        let x = if i & 1 == 0 { 10.0 } else { 12.0 };
        let y = if i & 2 == 0 { 5.0 } else { 6.0 };
        let z = if i & 4 == 0 { -3.0 } else { -2.0 };
        text += &format!("v {x} {y} {z}\n");
    }
    text += "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n";
    std::fs::write(dir.join("box.obj"), &text).unwrap();
    let loaded = load(&dir.join("box.obj")).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.desc;
    assert_eq!(d.shapes.len(), 1);
    let Geometry::TriangleMesh(m) = &d.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(m.triangle_count(), 12);
    check_framing(d);
}

#[test]
fn a_ply_file_becomes_a_framed_lit_scene() {
    let dir = ScratchDir::new("ply");
    std::fs::write(
        dir.join("tri.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         -1 0 0\n1 0 0\n0 2 0\n3 0 1 2\n",
    )
    .unwrap();
    let loaded = load(&dir.join("tri.ply")).unwrap_or_else(|e| panic!("{e}"));
    check_framing(&loaded.desc);
}

#[test]
fn mtl_materials_split_the_mesh_and_emit() {
    let dir = ScratchDir::new("mtl");
    std::fs::write(
        dir.join("m.mtl"),
        "newmtl red\nKd 0.8 0.1 0.1\nmap_Kd red.png\nnewmtl lamp\nKd 0 0 0\nKe 5 5 5\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("m.obj"),
        "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nusemtl red\nf 1 2 3\n\
         usemtl lamp\nf 1 3 4\nusemtl nothere\nf 1 4 2\n",
    )
    .unwrap();
    let loaded = load(&dir.join("m.obj")).unwrap_or_else(|e| panic!("{e}"));
    let d = &loaded.desc;
    assert_eq!(d.shapes.len(), 3);
    let red = &d.materials[d.shapes[0].material as usize];
    assert_eq!(
        *red,
        lancer::material::MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: lancer::texture::SpectrumTex::Const(Vec3::new(0.8, 0.1, 0.1))
        })
    );
    assert!(d.shapes[0].area_light.is_none());
    assert_eq!(d.shapes[1].area_light.map(|a| a.l), Some(Vec3::splat(5.0)));
    let w: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    assert!(w.iter().any(|w| w.contains("map_Kd red.png")), "{w:?}");
    assert!(
        w.iter()
            .any(|w| w.contains("m.obj:10:1: material 'nothere'")),
        "{w:?}"
    );
}

#[test]
fn bad_mesh_files_are_errors_naming_them() {
    let dir = ScratchDir::new("bad");
    let e = load(&dir.join("missing.obj")).unwrap_err();
    assert!(e.to_string().contains("missing.obj: cannot read"), "{e}");
    let e = load(&dir.join("missing.ply")).unwrap_err();
    assert!(e.to_string().contains("missing.ply: cannot read"), "{e}");
    std::fs::write(dir.join("points.obj"), "v 0 0 0\nv 1 1 1\n").unwrap();
    let e = load(&dir.join("points.obj")).unwrap_err();
    assert!(
        e.to_string()
            .contains("points.obj: the file has no triangles"),
        "{e}"
    );
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap();
    let e = load(&dir.join("bad.obj")).unwrap_err();
    assert!(e.to_string().contains("bad.obj:3: position index 3"), "{e}");
}

fn shared() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared")
}

#[test]
fn the_shared_bunny_obj_loads_framed() {
    let path = shared().join("scenes/meshes/stanford-bunny.obj");
    if !path.exists() {
        println!("note: {} not found; skipped", path.display());
        return;
    }
    let loaded = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let d = &loaded.desc;
    let Geometry::TriangleMesh(m) = &d.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(m.triangle_count(), 69451);
    check_framing(d);
}

#[test]
fn the_shared_mcguire_cornell_box_loads_with_its_materials() {
    let path = shared().join("scenes/real/mcguire-cornell-box/CornellBox-Original.obj");
    if !path.exists() {
        println!("note: {} not found; skipped", path.display());
        return;
    }
    let loaded = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.desc;
    assert!(d.shapes.len() >= 7, "{} shapes", d.shapes.len());
    let lights = d.shapes.iter().filter(|s| s.area_light.is_some()).count();
    assert_eq!(lights, 1, "the ceiling light");
    let red = d.materials.iter().any(|m| {
        *m == lancer::material::MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: lancer::texture::SpectrumTex::Const(Vec3::new(0.63, 0.065, 0.05)),
        })
    });
    assert!(red, "the red wall's Kd");
    check_framing(d);
}

#[test]
fn map_kd_images_become_textures_when_the_faces_have_uvs() {
    let dir = ScratchDir::new("map");
    // A 2 × 1 sRGB PNG: white, black.
    {
        let file = std::fs::File::create(dir.join("wb.png")).unwrap();
        let mut enc = png::Encoder::new(file, 2, 1);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().unwrap();
        w.write_image_data(&[255, 255, 255, 0, 0, 0]).unwrap();
    }
    std::fs::write(
        dir.join("t.mtl"),
        "newmtl tex\nKd 0.5 0.5 0.5\nmap_Kd wb.png\nnewmtl gone\nmap_Kd nothere.png\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("t.obj"),
        "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n\
         usemtl tex\nf 1/1 2/2 3/3\nusemtl gone\nf 1/1 3/3 2/2\n",
    )
    .unwrap();
    let loaded = load(&dir.join("t.obj")).unwrap_or_else(|e| panic!("{e}"));
    let d = &loaded.desc;
    assert_eq!(d.spectrum_textures.len(), 1);
    let lancer::texture::SpectrumTextureDesc::Image(t) = &d.spectrum_textures[0] else {
        panic!("not an image texture")
    };
    assert_eq!((t.image.width, t.image.height), (2, 1));
    // Read bilinearly, without a pyramid.
    assert!(!t.mip);
    assert_eq!(
        d.materials[d.shapes[0].material as usize],
        lancer::material::MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: lancer::texture::SpectrumTex::Tex(0)
        })
    );
    // The missing image falls back to Kd (the default grey here) with a warning on its line.
    assert_eq!(
        d.materials[d.shapes[1].material as usize],
        lancer::material::MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: lancer::texture::SpectrumTex::Const(Vec3::splat(0.6))
        })
    );
    let w: Vec<String> = loaded.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("t.obj:10:1: material 'gone': texture map_Kd nothere.png not used"),
        "{w:?}"
    );
}

#[test]
fn several_material_libraries_on_one_mtllib_line() {
    let dir = ScratchDir::new("libs");
    std::fs::write(dir.join("a.mtl"), "newmtl a\nKd 1 0 0\n").unwrap();
    std::fs::write(dir.join("b.mtl"), "newmtl b\nKd 0 1 0\n").unwrap();
    std::fs::write(
        dir.join("m.obj"),
        "mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl b\nf 1 2 3\nusemtl a\nf 1 3 2\n",
    )
    .unwrap();
    let loaded = load(&dir.join("m.obj")).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    let d = &loaded.desc;
    let kd = |i: usize| match &d.materials[d.shapes[i].material as usize] {
        lancer::material::MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: lancer::texture::SpectrumTex::Const(c),
        }) => *c,
        m => panic!("{m:?}"),
    };
    assert_eq!((kd(0), kd(1)), (Vec3::Y, Vec3::X));
}
