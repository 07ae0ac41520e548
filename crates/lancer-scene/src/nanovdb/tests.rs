//! The reader against Houdini's `sphere.nvdb` and against files written here, byte by byte
//! from the version-19 layout, uncompressed and ZIP-compressed.

use super::*;
use lancer::math::Vec3;
use lancer::medium::vdb::VdbGrid;

const SPHERE: &str = "../../../shared/scenes/real/houdini-media-tests/tests/resources/sphere.nvdb";

#[test]
fn reads_houdinis_zip_compressed_sphere() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(SPHERE);
    let Ok(data) = std::fs::read(&path) else {
        eprintln!("skipped: {} not found", path.display());
        return;
    };
    let grids = list_grids(&data).unwrap();
    assert_eq!(grids.len(), 1);
    let g = &grids[0];
    assert_eq!(
        (g.name.as_str(), g.grid_type, g.grid_class, g.codec),
        ("density", 1, 2, 1)
    );
    assert_eq!((g.voxel_count, g.grid_size), (18656, 277_632));
    let grid = VdbGrid::new(read_float_grid(&data, "density").unwrap().unwrap());
    assert!(read_float_grid(&data, "temperature").unwrap().is_none());
    // Its bounds, from the metadata: index [0, 31]³, world ±1.08984375, voxel 0.0703125.
    assert_eq!(grid.index_bounds(), [[0, 0, 0], [31, 31, 31]]);
    let wb = grid.world_bounds();
    assert_eq!(wb.min, Vec3::splat(-1.089_843_8));
    assert_eq!(wb.max, Vec3::splat(1.089_843_8));
    assert_eq!(grid.leaf_count(), 56);
    assert_eq!(grid.background(), 0.0);
    // A fog sphere: dense (1) at the centre, empty (0) in the corners, never negative; its
    // active voxels count matches the metadata.
    let centre = grid.sample_world(Vec3::ZERO);
    assert!((centre - 1.0).abs() < 1e-3, "{centre}");
    assert_eq!(grid.sample_world(Vec3::splat(1.05)), 0.0);
    let mut nonzero = 0;
    let mut max = 0.0f32;
    for k in -2..34 {
        for j in -2..34 {
            for i in -2..34 {
                let v = grid.value(i, j, k);
                assert!((0.0..=1.0).contains(&v));
                nonzero += (v > 0.0) as u32;
                max = max.max(v);
            }
        }
    }
    assert_eq!(max, 1.0);
    assert!(nonzero > 10_000 && nonzero <= 18656, "{nonzero}");
    // World → index: voxel size 0.0703125, index 0 at −1.08984375 + half a voxel or so: the
    // centre of the index box maps to the world origin.
    let c = grid.world_to_index(Vec3::ZERO);
    assert!((c - Vec3::splat(15.5)).abs().max_element() < 0.6, "{c}");
}

/// Writes a file of one float grid in format 19 or 32: one root tile → one upper node → one
/// lower node → the given leaves (origins inside [0, 128)³), plus a constant 8³ tile in the
/// lower node at `tile`; index = world·4 (voxel size ¼).
pub(crate) fn write_grid(
    name: &str,
    leaves: &[([i32; 3], [f32; 512])],
    tile: ([i32; 3], f32),
    zip: bool,
    v32: bool,
) -> Vec<u8> {
    fn put<const N: usize>(b: &mut [u8], at: usize, v: [u8; N]) {
        b[at..at + N].copy_from_slice(&v);
    }
    // (grid bytes, name, inverse map, world bbox, class, upper bytes, lower bytes, leaf values)
    let (grid, name_at, inv, wbox, class) = if v32 {
        (672, 40, 332, 560, 632)
    } else {
        (608, 8, 348, 264, 584)
    };
    let (upper_bytes, lower_bytes, leaf_values) = if v32 {
        (270_400, 33_856, 96)
    } else {
        (139_328, 17_472, 64)
    };
    let tree = grid;
    let root = tree + 64;
    let upper = root + 64 + 32;
    let lower = upper + upper_bytes;
    let leaf0 = lower + lower_bytes;
    let size = leaf0 + 2144 * leaves.len();
    let mut g = vec![0u8; size];
    put(&mut g, 0, MAGIC.to_le_bytes());
    g[name_at..name_at + name.len()].copy_from_slice(name.as_bytes());
    for (i, v) in [0.0f64, 0.0, 0.0, 32.0, 32.0, 32.0].iter().enumerate() {
        put(&mut g, wbox + 8 * i, v.to_le_bytes());
    }
    for i in 0..3 {
        put(&mut g, inv + 16 * i, 4.0f32.to_le_bytes());
    }
    put(&mut g, class, 2u32.to_le_bytes()); // fog volume
    put(&mut g, class + 4, 1u32.to_le_bytes()); // float
    put(&mut g, tree + 24, 64u64.to_le_bytes());
    // Root: bbox [0, 127]³, one tile of key 0 whose child is the upper node, background 0.
    for i in 0..3 {
        put(&mut g, root + 12 + 4 * i, 127i32.to_le_bytes());
    }
    let slot = |o: [i32; 3]| ((o[0] >> 3) << 8 | (o[1] >> 3) << 4 | (o[2] >> 3)) as usize;
    if v32 {
        put(&mut g, root + 24, 1u32.to_le_bytes());
        put(&mut g, root + 64 + 8, 96i64.to_le_bytes());
        g[upper + 4128] |= 1;
        put(&mut g, upper + 8256, (upper_bytes as i64).to_le_bytes());
        for (n, (o, _)) in leaves.iter().enumerate() {
            let s = slot(*o);
            g[lower + 544 + s / 8] |= 1 << (s % 8);
            let off = (lower_bytes + 2144 * n) as i64;
            put(&mut g, lower + 1088 + 8 * s, off.to_le_bytes());
        }
        put(
            &mut g,
            lower + 1088 + 8 * slot(tile.0),
            tile.1.to_le_bytes(),
        );
    } else {
        put(&mut g, root + 32, 1u32.to_le_bytes());
        put(&mut g, root + 64 + 12, 0i32.to_le_bytes());
        g[upper + 4096] |= 1;
        put(&mut g, upper + 139_296, 1i32.to_le_bytes());
        put(&mut g, lower + 17_440, 1i32.to_le_bytes());
        for (n, (o, _)) in leaves.iter().enumerate() {
            let s = slot(*o);
            g[lower + 512 + s / 8] |= 1 << (s % 8);
            put(&mut g, lower + 1024 + 4 * s, (n as u32).to_le_bytes());
        }
        put(
            &mut g,
            lower + 1024 + 4 * slot(tile.0),
            tile.1.to_le_bytes(),
        );
    }
    for (n, (_, vals)) in leaves.iter().enumerate() {
        for (i, v) in vals.iter().enumerate() {
            put(
                &mut g,
                leaf0 + 2144 * n + leaf_values + 4 * i,
                v.to_le_bytes(),
            );
        }
    }
    // The file: header, metadata, name, data.
    let data = if zip {
        use std::io::Write;
        let mut e = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        e.write_all(&g).unwrap();
        let z = e.finish().unwrap();
        let mut d = (z.len() as u64).to_le_bytes().to_vec();
        d.extend(z);
        d
    } else {
        g.clone()
    };
    let mut f = Vec::new();
    f.extend(MAGIC.to_le_bytes());
    if v32 {
        f.extend((32u32 << 21 | 7 << 10).to_le_bytes());
    } else {
        f.extend(19u16.to_le_bytes());
        f.extend(0u16.to_le_bytes());
    }
    f.extend(1u16.to_le_bytes());
    f.extend((zip as u16).to_le_bytes());
    let mut meta = vec![0u8; if v32 { META_BYTES_32 } else { META_BYTES }];
    put(&mut meta, 0, (size as u64).to_le_bytes());
    put(&mut meta, 8, (data.len() as u64).to_le_bytes());
    put(&mut meta, 32, 1u32.to_le_bytes());
    put(&mut meta, 36, 2u32.to_le_bytes());
    put(
        &mut meta,
        if v32 { 136 } else { 40 },
        (name.len() as u32 + 1).to_le_bytes(),
    );
    f.extend(meta);
    f.extend(name.as_bytes());
    f.push(0);
    f.extend(data);
    f
}

/// A version-19 file (see [`write_grid`]).
pub(crate) fn write_v19(
    name: &str,
    leaves: &[([i32; 3], [f32; 512])],
    tile: ([i32; 3], f32),
    zip: bool,
) -> Vec<u8> {
    write_grid(name, leaves, tile, zip, false)
}

fn ramp_leaf(base: f32) -> [f32; 512] {
    std::array::from_fn(|n| base + n as f32)
}

#[test]
fn reads_its_own_files_uncompressed_and_zipped() {
    let leaves = [([8, 0, 16], ramp_leaf(0.0)), ([0, 8, 0], ramp_leaf(1000.0))];
    for (zip, v32) in [(false, false), (true, false), (false, true), (true, true)] {
        let f = write_grid("density", &leaves, ([16, 16, 16], 5.0), zip, v32);
        assert!(read_float_grid(&f, "temperature").unwrap().is_none());
        let g = VdbGrid::new(read_float_grid(&f, "density").unwrap().unwrap());
        assert_eq!(g.leaf_count(), 2);
        // Voxel (9, 2, 19) of leaf (8, 0, 16): local (1, 2, 3) → 1·64 + 2·8 + 3 = 83.
        assert_eq!(g.value(9, 2, 19), 83.0);
        assert_eq!(g.value(7, 15, 7), 1000.0 + 7.0 * 64.0 + 7.0 * 8.0 + 7.0);
        assert_eq!(g.value(20, 17, 23), 5.0); // the tile
        assert_eq!(g.value(40, 40, 40), 0.0); // background
        // World (9.25, 2, 19)/4 is index (9.25, 2, 19): ¾·83 + ¼·(83 + 64).
        let v = g.sample_world(Vec3::new(9.25, 2.0, 19.0) / 4.0);
        assert!((v - 99.0).abs() < 1e-3, "{v}");
        assert_eq!(g.index_bounds(), [[0; 3], [127; 3]]);
    }
}

#[test]
fn bad_files_give_errors_not_panics() {
    let leaves = [([8, 0, 16], ramp_leaf(0.0))];
    let good = write_v19("density", &leaves, ([16, 16, 16], 5.0), true);
    assert!(list_grids(b"not a vdb").unwrap_err().contains("NanoVDB"));
    // Every truncation fails cleanly.
    for n in (0..good.len()).step_by(1009) {
        let _ = read_float_grid(&good[..n], "density");
    }
    // Another format version.
    let mut v29 = good.clone();
    v29[8..12].copy_from_slice(&(29u32 << 21 | 3 << 10).to_le_bytes());
    assert!(
        list_grids(&v29).unwrap_err().contains("29.3.0"),
        "{:?}",
        list_grids(&v29)
    );
    // A grid size that does not match what inflates.
    let mut big = good.clone();
    big[16..24].copy_from_slice(&(1u64 << 31).to_le_bytes());
    assert!(
        read_float_grid(&big, "density")
            .unwrap_err()
            .contains("inflates")
    );
    // Corrupt bytes anywhere in an uncompressed file: errors or a grid, never a panic.
    let mut state = 7u64;
    for i in 0..100 {
        let mut f = write_grid("density", &leaves, ([16, 16, 16], 5.0), false, i % 2 == 1);
        for _ in 0..8 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let at = (state >> 33) as usize % f.len();
            f[at] = (state >> 20) as u8;
        }
        let _ = read_float_grid(&f, "density");
    }
}
