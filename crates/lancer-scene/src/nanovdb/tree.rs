//! The grid buffer of NanoVDB format version 19 (float grids), as laid out by that version's
//! `NanoVDB.h`: every structure is aligned to 32 bytes, children are found by index, never by
//! pointer.
//!
//! | structure | bytes | fields used (byte offset) |
//! |---|---|---|
//! | GridData | 608 | magic (0), world bbox 6×f64 (264), inverse map 9×f32 row-major (348), translation 3×f32 (384), blind-data count (592) |
//! | GridBlindMetaData | 288 each | — (skipped) |
//! | TreeData | 64 | byte offset of the root from the tree (24), node counts 4×u32 (32) |
//! | RootData | 64 + 32 per tile | index bbox 6×i32 (0), tile count (32), background (48); tile: key u64 (0), value (8), child index i32 (12) |
//! | upper InternalData (32³) | 139 328 | child mask (4096), table of 32³ values or child indices (8192), child offset i32 (139 296) |
//! | lower InternalData (16³) | 17 472 | child mask (512), table (1024), child offset (17 440) |
//! | LeafData (8³) | 2 144 | values 512×f32 (64) |
//!
//! A root tile's key packs its origin as (i ≫ 12) ≪ 42 | (j ≫ 12) ≪ 21 | (k ≫ 12); the root's
//! children follow its tiles; an internal node's child n sits at
//! node + offset·(node size) + index·(child size); slot n of a node of side 2ᴸ holds the child or
//! tile at local position (n ≫ 2L, (n ≫ L) & (2ᴸ−1), n & (2ᴸ−1)), and a leaf's sample (i, j, k)
//! at (i&7)·64 + (j&7)·8 + (k&7).

use super::Bytes;
use lancer::math::{Bounds3, Mat3, Vec3};
use lancer::medium::vdb::{MAX_LEAVES, VdbParts, VdbTile};

const GRID_BYTES: u64 = 608;
const BLIND_BYTES: u64 = 288;
const ROOT_BYTES: u64 = 64;
const ROOT_TILE_BYTES: u64 = 32;
const UPPER_BYTES: u64 = 139_328;
const LOWER_BYTES: u64 = 17_472;
const LEAF_BYTES: u64 = 2_144;
/// Most tiles kept from one grid.
const MAX_TILES: usize = 1 << 22;

/// An internal node's shape: log₂ of its side, its size, where its fields are.
struct Internal {
    log2: u32,
    bytes: u64,
    child_mask: u64,
    table: u64,
    offset: u64,
    /// log₂ of the side, in voxels, of what one slot covers.
    child_log2: u32,
}

const UPPER: Internal = Internal {
    log2: 5,
    bytes: UPPER_BYTES,
    child_mask: 4096,
    table: 8192,
    offset: 139_296,
    child_log2: 7,
};
const LOWER: Internal = Internal {
    log2: 4,
    bytes: LOWER_BYTES,
    child_mask: 512,
    table: 1024,
    offset: 17_440,
    child_log2: 3,
};

/// The walk's state: the buffer, what it gathered, and its budgets.
struct Walk<'a> {
    b: Bytes<'a>,
    parts: VdbParts,
    /// Nodes still allowed per level (a buffer cannot hold more distinct nodes than its size
    /// allows; a hostile file could point many parents at one child).
    budget_upper: u64,
    budget_lower: u64,
    budget_leaf: u64,
}

/// Reads a version-19 float grid buffer.
pub fn read_v19(buf: &[u8]) -> Result<VdbParts, String> {
    let b = Bytes { data: buf };
    if b.u64(0)? != super::MAGIC {
        return Err("the grid buffer has no NanoVDB magic number".into());
    }
    let mut wb = [0.0f64; 6];
    for (i, v) in wb.iter_mut().enumerate() {
        *v = b.f64(264 + 8 * i as u64)?;
    }
    let inv: [f32; 9] = std::array::from_fn(|i| b.f32(348 + 4 * i as u64).unwrap_or(f32::NAN));
    let t: [f32; 3] = std::array::from_fn(|i| b.f32(384 + 4 * i as u64).unwrap_or(f32::NAN));
    let blind = b.u32(592)? as u64;
    let tree = GRID_BYTES + blind * BLIND_BYTES;
    let root = tree + b.u64(tree + 24)?;
    let mut bbox = [[0i32; 3]; 2];
    for (i, v) in bbox.iter_mut().flatten().enumerate() {
        *v = b.i32(root + 4 * i as u64)?;
    }
    let tile_count = b.u32(root + 32)? as u64;
    let background = b.f32(root + 48)?;
    let n = buf.len() as u64;
    let mut w = Walk {
        b,
        parts: VdbParts {
            // NanoVDB multiplies row-major: index = M·(world − t).
            world_to_index: Mat3::from_cols_array(&inv).transpose(),
            translation: Vec3::from_array(t),
            world_bounds: Bounds3::new(
                Vec3::new(wb[0] as f32, wb[1] as f32, wb[2] as f32),
                Vec3::new(wb[3] as f32, wb[4] as f32, wb[5] as f32),
            ),
            index_bounds: bbox,
            background,
            ..VdbParts::default()
        },
        budget_upper: n / UPPER_BYTES,
        budget_lower: n / LOWER_BYTES,
        budget_leaf: (n / LEAF_BYTES).min(MAX_LEAVES),
    };
    let tiles = root + ROOT_BYTES;
    let children = tiles
        + tile_count
            .checked_mul(ROOT_TILE_BYTES)
            .ok_or("too many root tiles")?;
    w.b.slice(tiles, tile_count * ROOT_TILE_BYTES)?;
    for t in 0..tile_count {
        let at = tiles + t * ROOT_TILE_BYTES;
        let key = w.b.u64(at)?;
        let part = |s: u32| ((((key >> s) & 0x1f_ffff) as u32) << 12) as i32;
        let origin = [part(42), part(21), part(0)];
        let child = w.b.i32(at + 12)?;
        if child < 0 {
            w.tile(origin, 4096, w.b.f32(at + 8)?)?;
        } else {
            w.internal(&UPPER, children + child as u64 * UPPER_BYTES, origin)?;
        }
    }
    Ok(w.parts)
}

impl Walk<'_> {
    fn tile(&mut self, origin: [i32; 3], dim: i32, value: f32) -> Result<(), String> {
        if value == self.parts.background {
            return Ok(());
        }
        if self.parts.tiles.len() >= MAX_TILES {
            return Err(format!("more than {MAX_TILES} tiles"));
        }
        self.parts.tiles.push(VdbTile { origin, dim, value });
        Ok(())
    }

    /// Reads the internal node of shape `s` at `at`, whose first voxel is `origin`.
    fn internal(&mut self, s: &Internal, at: u64, origin: [i32; 3]) -> Result<(), String> {
        let budget = if s.log2 == 5 {
            &mut self.budget_upper
        } else {
            &mut self.budget_lower
        };
        if *budget == 0 {
            return Err("more internal nodes than the grid buffer can hold".into());
        }
        *budget -= 1;
        let node = self.b.slice(at, s.bytes)?;
        let slots = 1u32 << (3 * s.log2);
        let mask = &node[s.child_mask as usize..s.child_mask as usize + slots as usize / 8];
        let table = &node[s.table as usize..s.table as usize + 4 * slots as usize];
        let offset = i32::from_le_bytes(node[s.offset as usize..][..4].try_into().unwrap());
        let side = (1u32 << s.log2) - 1;
        for n in 0..slots {
            let local = [n >> (2 * s.log2), (n >> s.log2) & side, n & side];
            let o: [i32; 3] =
                std::array::from_fn(|a| origin[a].wrapping_add((local[a] << s.child_log2) as i32));
            let word: [u8; 4] = table[4 * n as usize..][..4].try_into().unwrap();
            if mask[(n >> 3) as usize] & (1 << (n & 7)) == 0 {
                self.tile(o, 1 << s.child_log2, f32::from_le_bytes(word))?;
                continue;
            }
            // Child n: node + offset·(node size) + index·(child size).
            let index = u32::from_le_bytes(word) as i64;
            let child = at as i64 + offset as i64 * s.bytes as i64;
            if s.log2 == 5 {
                let c = child + index * LOWER_BYTES as i64;
                if c < 0 {
                    return Err("a child node lies before the grid".into());
                }
                self.internal(&LOWER, c as u64, o)?;
            } else {
                let c = child + index * LEAF_BYTES as i64;
                if c < 0 {
                    return Err("a leaf lies before the grid".into());
                }
                self.leaf(c as u64, o)?;
            }
        }
        Ok(())
    }

    fn leaf(&mut self, at: u64, origin: [i32; 3]) -> Result<(), String> {
        if self.budget_leaf == 0 {
            return Err("more leaf nodes than the grid buffer can hold".into());
        }
        self.budget_leaf -= 1;
        let values = self.b.slice(at + 64, 2048)?;
        self.parts.leaf_origins.push(origin);
        self.parts.leaf_values.extend(
            values
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap())),
        );
        Ok(())
    }
}
