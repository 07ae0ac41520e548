//! MagicaVoxel `.vox` files: written and read back unchanged, the default palette when the
//! file has none, clear errors (naming the file) for truncated, lying or inconsistent files,
//! and `Shape "voxels"` in pbrt scenes, from a file or inline.

use crate::common::ScratchDir;
use lancer::math::Rgb;
use lancer::scene::desc::Geometry;
use lancer::shape::srgb8_to_linear;
use lancer_scene::load_pbrt_str;
use lancer_scene::vox::{default_palette, parse_vox, write_vox};
use std::path::PathBuf;

/// A small deterministic model: a 5×4×3 grid, every third cell filled with varied colours.
fn model() -> ([u32; 3], Vec<u8>) {
    let dims = [5, 4, 3];
    let cells = (0..60u32)
        .map(|i| {
            if i % 3 == 0 {
                (1 + (i * 37) % 255) as u8
            } else {
                0
            }
        })
        .collect();
    (dims, cells)
}

fn chunk(id: &[u8; 4], content: &[u8], children: &[u8]) -> Vec<u8> {
    let mut out = id.to_vec();
    out.extend_from_slice(&(content.len() as u32).to_le_bytes());
    out.extend_from_slice(&(children.len() as u32).to_le_bytes());
    out.extend_from_slice(content);
    out.extend_from_slice(children);
    out
}

fn file(children: &[u8]) -> Vec<u8> {
    let mut out = b"VOX ".to_vec();
    out.extend_from_slice(&150u32.to_le_bytes());
    out.extend_from_slice(&chunk(b"MAIN", &[], children));
    out
}

fn size(d: [u32; 3]) -> Vec<u8> {
    chunk(
        b"SIZE",
        &d.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<_>>(),
        &[],
    )
}

fn xyzi(count: u32, voxels: &[[u8; 4]]) -> Vec<u8> {
    let mut c = count.to_le_bytes().to_vec();
    c.extend(voxels.iter().flatten());
    chunk(b"XYZI", &c, &[])
}

#[test]
fn round_trip_with_a_palette() {
    let (dims, cells) = model();
    let mut pal = [[0u8; 4]; 256];
    for (i, e) in pal.iter_mut().enumerate() {
        *e = [i as u8, (255 - i) as u8, (i * 7) as u8, 255];
    }
    let bytes = write_vox(dims, &cells, Some(&pal));
    let m = parse_vox(&bytes, "model.vox").unwrap();
    assert!(m.warnings.is_empty(), "{:?}", m.warnings);
    assert_eq!(m.grid.dims(), dims);
    assert_eq!(m.grid.cells(), &cells[..]);
    for (i, e) in pal.iter().enumerate().skip(1) {
        let want = Rgb::new(
            srgb8_to_linear(e[0]),
            srgb8_to_linear(e[1]),
            srgb8_to_linear(e[2]),
        );
        assert_eq!(m.grid.palette()[i], want, "palette index {i}");
    }
}

#[test]
fn srgb_decoding() {
    assert_eq!(srgb8_to_linear(0), 0.0);
    assert_eq!(srgb8_to_linear(255), 1.0);
    // 10/255 is on the linear segment; 128/255 = 0.50196 decodes to 0.21586.
    assert!((srgb8_to_linear(10) - 10.0 / 255.0 / 12.92).abs() < 1e-7);
    assert!((srgb8_to_linear(128) - 0.21586).abs() < 1e-4);
}

#[test]
fn default_palette_without_rgba() {
    let p = default_palette();
    assert_eq!(p[0], [0, 0, 0, 0]);
    assert_eq!(p[1], [0xff, 0xff, 0xff, 0xff]);
    assert_eq!(p[2], [0xff, 0xff, 0xcc, 0xff]);
    assert_eq!(p[7], [0xff, 0xcc, 0xff, 0xff]);
    assert_eq!(p[215], [0, 0, 0x33, 0xff]);
    assert_eq!(p[216], [0xee, 0, 0, 0xff]);
    assert_eq!(p[226], [0, 0xee, 0, 0xff]);
    assert_eq!(p[236], [0, 0, 0xee, 0xff]);
    assert_eq!(p[246], [0xee, 0xee, 0xee, 0xff]);
    assert_eq!(p[255], [0x11, 0x11, 0x11, 0xff]);
    let mut distinct: Vec<_> = p[1..].to_vec();
    distinct.sort();
    distinct.dedup();
    assert_eq!(distinct.len(), 255);
    let (dims, cells) = model();
    let m = parse_vox(&write_vox(dims, &cells, None), "m.vox").unwrap();
    assert_eq!(m.grid.palette()[1], Rgb::ONE);
    assert_eq!(m.grid.palette()[255], Rgb::splat(srgb8_to_linear(0x11)));
}

#[test]
fn every_truncation_is_an_error_naming_the_file() {
    let (dims, cells) = model();
    let bytes = write_vox(dims, &cells, Some(&default_palette()));
    for len in 0..bytes.len() {
        let e = parse_vox(&bytes[..len], "cut.vox").unwrap_err();
        assert_eq!(e.file, "cut.vox");
        assert!(e.to_string().starts_with("cut.vox: "), "{e}");
    }
}

#[test]
fn lying_and_inconsistent_files() {
    let err = |bytes: &[u8]| parse_vox(bytes, "bad.vox").unwrap_err().message;
    assert!(err(b"PLY 1234").contains("not a MagicaVoxel"));
    // A MAIN claiming 4 GiB of children.
    let mut lying_main = b"VOX ".to_vec();
    lying_main.extend_from_slice(&150u32.to_le_bytes());
    lying_main.extend_from_slice(b"MAIN");
    lying_main.extend_from_slice(&0u32.to_le_bytes());
    lying_main.extend_from_slice(&u32::MAX.to_le_bytes());
    assert!(
        err(&lying_main).contains("truncated"),
        "{}",
        err(&lying_main)
    );
    // A count of 2³² − 1 voxels in a chunk holding one.
    let lying_count = file(&[size([4, 4, 4]), xyzi(u32::MAX, &[[1, 1, 1, 3]])].concat());
    let e = err(&lying_count);
    assert!(e.contains("claims 4294967295 voxels"), "{e}");
    // A size far beyond MagicaVoxel's (a 4 GB grid): refused before any allocation.
    let huge = file(&[size([4000, 1000, 1000]), xyzi(1, &[[1, 1, 1, 3]])].concat());
    assert!(
        err(&huge).contains("each side must be 1 to 256"),
        "{}",
        err(&huge)
    );
    let zero = file(&[size([4, 0, 4]), xyzi(0, &[])].concat());
    assert!(err(&zero).contains("each side"));
    // A voxel outside the model.
    let outside = file(&[size([4, 4, 4]), xyzi(1, &[[1, 4, 1, 3]])].concat());
    assert!(err(&outside).contains("(1, 4, 1)"), "{}", err(&outside));
    // Order and presence.
    let no_size = file(&xyzi(1, &[[1, 1, 1, 3]]));
    assert!(err(&no_size).contains("before any 'SIZE'"));
    assert!(err(&file(&size([2, 2, 2]))).contains("no 'XYZI'"));
    assert!(err(&file(&[])).contains("no 'SIZE'"));
    let short_rgba = file(&[size([2, 2, 2]), xyzi(0, &[]), chunk(b"RGBA", &[1; 40], &[])].concat());
    assert!(err(&short_rgba).contains("'RGBA'"));
    let not_main = [
        b"VOX ".as_slice(),
        &150u32.to_le_bytes(),
        &chunk(b"PACK", &[], &[]),
    ]
    .concat();
    assert!(err(&not_main).contains("not 'MAIN'"));
}

#[test]
fn extra_models_and_scene_graph_chunks() {
    let body = [
        chunk(b"PACK", &2u32.to_le_bytes(), &[]),
        size([2, 2, 2]),
        xyzi(2, &[[0, 0, 0, 5], [1, 1, 1, 0]]),
        size([3, 3, 3]),
        xyzi(1, &[[2, 2, 2, 7]]),
        chunk(b"nTRN", &[0; 28], &[]),
        chunk(b"nSHP", &[0; 20], &[]),
        chunk(b"MATL", &[0; 8], &[]),
    ]
    .concat();
    let m = parse_vox(&file(&body), "two.vox").unwrap();
    assert_eq!(m.grid.dims(), [2, 2, 2]);
    assert_eq!(m.grid.get(0, 0, 0), 5);
    assert_eq!(m.grid.filled_count(), 1);
    let w = m.warnings.join("; ");
    assert!(w.contains("2 models"), "{w}");
    assert!(w.contains("1 voxels of colour index 0"), "{w}");
}

const HEAD: &str = "Camera \"perspective\"\nWorldBegin\n";

#[test]
fn pbrt_voxels_from_a_file_and_inline() {
    let dir = ScratchDir::new("pbrt");
    let (dims, cells) = model();
    std::fs::write(dir.join("m.vox"), write_vox(dims, &cells, None)).unwrap();
    let text = format!("{HEAD}Shape \"voxels\" \"string filename\" \"m.vox\"\n");
    let d = load_pbrt_str(&text, "scene.pbrt", &dir).unwrap().desc;
    let Geometry::Voxels(g) = &d.shapes[0].geometry else {
        panic!("{:?}", d.shapes[0].geometry)
    };
    assert_eq!(g.cells(), &cells[..]);

    let text = format!(
        "{HEAD}Shape \"voxels\" \"integer dims\" [2 1 2] \"integer indices\" [0 1 2 0] \
         \"float palette\" [0.5 0.25 0.125]\n"
    );
    let d = load_pbrt_str(&text, "inline.pbrt", &dir).unwrap().desc;
    let Geometry::Voxels(g) = &d.shapes[0].geometry else {
        panic!()
    };
    assert_eq!(g.dims(), [2, 1, 2]);
    assert_eq!(g.cells(), &[0, 1, 2, 0]);
    assert_eq!(g.palette()[1], Rgb::new(0.5, 0.25, 0.125));
    // Index 2 keeps the default palette's colour (ff, ff, cc).
    assert_eq!(g.palette()[2], Rgb::new(1.0, 1.0, srgb8_to_linear(0xcc)));
}

#[test]
fn pbrt_voxel_errors() {
    let dir = ScratchDir::new("errors");
    let fails = |body: &str| {
        load_pbrt_str(&format!("{HEAD}{body}\n"), "s.pbrt", &dir)
            .unwrap_err()
            .to_string()
    };
    let e = fails("Shape \"voxels\" \"integer dims\" [2 2 2] \"integer indices\" [1 1 1]");
    assert!(
        e.contains("3 values for 2×2×2 = 8 cells") && e.contains("s.pbrt:3"),
        "{e}"
    );
    let e = fails("Shape \"voxels\" \"integer dims\" [2 2] \"integer indices\" [1 1 1 1]");
    assert!(e.contains("three positive values"), "{e}");
    let e = fails("Shape \"voxels\" \"integer dims\" [1 1 1] \"integer indices\" [300]");
    assert!(e.contains("300"), "{e}");
    let e = fails("Shape \"voxels\" \"string filename\" \"missing.vox\"");
    assert!(e.contains("missing.vox"), "{e}");
    std::fs::write(dir.join("cut.vox"), b"VOX \x96\0\0\0MAIN").unwrap();
    let e = fails("Shape \"voxels\" \"string filename\" \"cut.vox\"");
    assert!(e.contains("cut.vox") && e.contains("truncated"), "{e}");
    let e = fails(
        "AreaLightSource \"diffuse\" \"rgb L\" [1 1 1]\n\
         Shape \"voxels\" \"integer dims\" [1 1 1] \"integer indices\" [1]",
    );
    assert!(e.contains("area light"), "{e}");
}

#[test]
fn the_shipped_voxel_scene_loads() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scenes/voxels.pbrt");
    let (loaded, files) = lancer_scene::files_read::recording(|| lancer_scene::load(&path));
    let loaded = loaded.unwrap();
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    // `lancer info --files` lists the model.
    assert!(
        files.iter().any(|f| f.ends_with("voxels/island.vox")),
        "{files:?}"
    );
    let g = loaded
        .desc
        .shapes
        .iter()
        .find_map(|s| match &s.geometry {
            Geometry::Voxels(g) => Some(g.clone()),
            _ => None,
        })
        .expect("a voxels shape");
    assert_eq!(g.dims(), [32, 32, 24]);
    assert_eq!(g.filled_count(), 5441);
    // Grass, from the file's own palette: sRGB (86, 160, 60).
    assert_eq!(
        g.palette()[1],
        Rgb::new(
            srgb8_to_linear(86),
            srgb8_to_linear(160),
            srgb8_to_linear(60)
        )
    );
    let scene = lancer::Scene::build(&loaded.desc).unwrap();
    assert!(
        scene
            .shapes()
            .iter()
            .any(|s| matches!(s, lancer::shape::Shape::Voxels(_)))
    );
}
