//! The grid buffer of a NanoVDB float grid, in the two layouts lancer reads: format version
//! 19 (as Houdini writes it; that version's `NanoVDB.h`) and version 32 (today's NanoVDB; the
//! offsets its `PNanoVDB.h` publishes). Every structure is aligned to 32 bytes; nodes hold no
//! pointers.
//!
//! | structure | v19 bytes | v32 bytes | fields used (v19 / v32 byte offset) |
//! |---|---|---|---|
//! | GridData | 608 (+ 288 per blind-data record) | 672 | world bbox 6×f64 (264 / 560), inverse map 9×f32 row-major (348 / 332), translation 3×f32 (384 / 368), blind-data count u32 (592 / —) |
//! | TreeData | 64 | 64 | byte offset of the root from the tree, u64 (24) |
//! | RootData | 64 | 64 | index bbox 6×i32 (0), tile count u32 (32 / 24), background f32 (48 / 28) |
//! | root tile | 32 | 32 | key u64 (0), value f32 (8 / 20), child: i32 index (12) / i64 byte offset from the root, 0 = none (8) |
//! | upper node (32³) | 139 328 | 270 400 | child mask (4096 / 4128), table of 4-byte / 8-byte entries (8192 / 8256), child offset i32 (139 296 / —) |
//! | lower node (16³) | 17 472 | 33 856 | child mask (512 / 544), table (1024 / 1088), child offset (17 440 / —) |
//! | leaf (8³) | 2 144 | 2 144 | values 512×f32 (64 / 96) |
//!
//! A root tile's key packs its origin as (i ≫ 12) ≪ 42 | (j ≫ 12) ≪ 21 | (k ≫ 12). Version 19
//! finds children by index: the root's after its tiles, an internal node's child n at
//! node + offset·(node size) + index·(child size); version 32 stores each child's signed byte
//! offset from its parent in the table entry. Slot n of a node of side 2ᴸ covers local position
//! (n ≫ 2L, (n ≫ L) & (2ᴸ−1), n & (2ᴸ−1)); a leaf's sample (i, j, k) is at
//! (i&7)·64 + (j&7)·8 + (k&7). A slot without a child holds a tile value (the entry's first
//! 4 bytes).

use super::Bytes;
use lancer::math::{Bounds3, Mat3, Vec3};
use lancer::medium::vdb::{MAX_LEAVES, VdbParts, VdbTile};

const ROOT_BYTES: u64 = 64;
const ROOT_TILE_BYTES: u64 = 32;
const LEAF_BYTES: u64 = 2_144;
/// Most tiles kept from one grid.
const MAX_TILES: usize = 1 << 22;

/// An internal node's shape: log₂ of its side, its size, where its fields are.
struct Internal {
    log2: u32,
    bytes: u64,
    child_mask: u64,
    table: u64,
    /// Version 19's child offset field (in node sizes); `None` for version 32.
    offset: Option<u64>,
    /// log₂ of the side, in voxels, of what one slot covers.
    child_log2: u32,
}

/// Where one format version keeps what the walk reads.
struct Layout {
    world_bbox: u64,
    inv_map: u64,
    translation: u64,
    /// v19: the blind-data count's offset (the tree follows the records); v32: none.
    blind_count: Option<u64>,
    grid_bytes: u64,
    root_tile_count: u64,
    root_background: u64,
    tile_value: u64,
    /// Bytes per table entry (4 in v19, 8 in v32).
    stride: u64,
    upper: Internal,
    lower: Internal,
    leaf_values: u64,
    v32: bool,
}

const V19: Layout = Layout {
    world_bbox: 264,
    inv_map: 348,
    translation: 384,
    blind_count: Some(592),
    grid_bytes: 608,
    root_tile_count: 32,
    root_background: 48,
    tile_value: 8,
    stride: 4,
    upper: Internal {
        log2: 5,
        bytes: 139_328,
        child_mask: 4096,
        table: 8192,
        offset: Some(139_296),
        child_log2: 7,
    },
    lower: Internal {
        log2: 4,
        bytes: 17_472,
        child_mask: 512,
        table: 1024,
        offset: Some(17_440),
        child_log2: 3,
    },
    leaf_values: 64,
    v32: false,
};

const V32: Layout = Layout {
    world_bbox: 560,
    inv_map: 332,
    translation: 368,
    blind_count: None,
    grid_bytes: 672,
    root_tile_count: 24,
    root_background: 28,
    tile_value: 20,
    stride: 8,
    upper: Internal {
        log2: 5,
        bytes: 270_400,
        child_mask: 4128,
        table: 8256,
        offset: None,
        child_log2: 7,
    },
    lower: Internal {
        log2: 4,
        bytes: 33_856,
        child_mask: 544,
        table: 1088,
        offset: None,
        child_log2: 3,
    },
    leaf_values: 96,
    v32: true,
};

/// The walk's state: the buffer, what it gathered, and its budgets.
struct Walk<'a> {
    b: Bytes<'a>,
    l: &'static Layout,
    parts: VdbParts,
    /// Nodes still allowed per level (a buffer cannot hold more distinct nodes than its size
    /// allows; a hostile file could point many parents at one child).
    budget_upper: u64,
    budget_lower: u64,
    budget_leaf: u64,
}

/// Reads a float grid buffer of format `version` (19 or 32).
pub fn read(buf: &[u8], version: u32) -> Result<VdbParts, String> {
    let l = if version == 32 { &V32 } else { &V19 };
    let b = Bytes { data: buf };
    // "NanoVDB" and a digit (0 in v19, 0 or 1 in v32): compare the first seven bytes.
    const PREFIX: u64 = 0x00ff_ffff_ffff_ffff;
    if b.u64(0)? & PREFIX != super::MAGIC & PREFIX {
        return Err("the grid buffer has no NanoVDB magic number".into());
    }
    let mut wb = [0.0f64; 6];
    for (i, v) in wb.iter_mut().enumerate() {
        *v = b.f64(l.world_bbox + 8 * i as u64)?;
    }
    let inv: [f32; 9] =
        std::array::from_fn(|i| b.f32(l.inv_map + 4 * i as u64).unwrap_or(f32::NAN));
    let t: [f32; 3] =
        std::array::from_fn(|i| b.f32(l.translation + 4 * i as u64).unwrap_or(f32::NAN));
    let tree = match l.blind_count {
        Some(at) => l.grid_bytes + b.u32(at)? as u64 * 288,
        None => l.grid_bytes,
    };
    let root = tree + b.u64(tree + 24)?;
    let mut bbox = [[0i32; 3]; 2];
    for (i, v) in bbox.iter_mut().flatten().enumerate() {
        *v = b.i32(root + 4 * i as u64)?;
    }
    let tile_count = b.u32(root + l.root_tile_count)? as u64;
    let background = b.f32(root + l.root_background)?;
    let n = buf.len() as u64;
    let mut w = Walk {
        b,
        l,
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
        budget_upper: n / l.upper.bytes,
        budget_lower: n / l.lower.bytes,
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
        // The upper node's address, if the tile has one.
        let child = if l.v32 {
            match w.b.u64(at + 8)? as i64 {
                0 => None,
                off => Some(root as i64 + off),
            }
        } else {
            match w.b.i32(at + 12)? {
                i if i < 0 => None,
                i => Some(children as i64 + i as i64 * l.upper.bytes as i64),
            }
        };
        match child {
            None => w.tile(origin, 4096, w.b.f32(at + l.tile_value)?)?,
            Some(c) if c >= 0 => w.internal(&l.upper, c as u64, origin)?,
            Some(_) => return Err("a node lies before the grid".into()),
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
        let stride = self.l.stride as usize;
        let table = &node[s.table as usize..s.table as usize + stride * slots as usize];
        let offset = s.offset.map(|o| {
            let o = o as usize;
            i32::from_le_bytes(node[o..o + 4].try_into().unwrap()) as i64
        });
        let side = (1u32 << s.log2) - 1;
        for n in 0..slots {
            let local = [n >> (2 * s.log2), (n >> s.log2) & side, n & side];
            let o: [i32; 3] =
                std::array::from_fn(|a| origin[a].wrapping_add((local[a] << s.child_log2) as i32));
            let entry = &table[stride * n as usize..][..stride];
            let word: [u8; 4] = entry[..4].try_into().unwrap();
            if mask[(n >> 3) as usize] & (1 << (n & 7)) == 0 {
                self.tile(o, 1 << s.child_log2, f32::from_le_bytes(word))?;
                continue;
            }
            let upper = s.log2 == 5;
            let child_bytes = if upper {
                self.l.lower.bytes
            } else {
                LEAF_BYTES
            } as i64;
            let c = match offset {
                // v19, child n: node + offset·(node size) + index·(child size).
                Some(off) => {
                    let index = u32::from_le_bytes(word) as i64;
                    at as i64 + off * s.bytes as i64 + index * child_bytes
                }
                // v32: the entry is the child's byte offset from this node.
                None => at as i64 + i64::from_le_bytes(entry.try_into().unwrap()),
            };
            if c < 0 {
                return Err("a node lies before the grid".into());
            }
            if upper {
                let l = self.l;
                self.internal(&l.lower, c as u64, o)?;
            } else {
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
        let values = self.b.slice(at + self.l.leaf_values, 2048)?;
        self.parts.leaf_origins.push(origin);
        self.parts.leaf_values.extend(
            values
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap())),
        );
        Ok(())
    }
}
