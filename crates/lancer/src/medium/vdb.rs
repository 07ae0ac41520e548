//! A sparse float volume in VDB's index space, as read from a NanoVDB file: 8³ leaf blocks of
//! samples, constant tiles, a background value elsewhere, and the affine map between index
//! space and the grid's world space (lancer's medium space).
//!
//! Voxel (i, j, k) is a sample *at* the integer index point (VDB's convention, unlike
//! [`super::grid::SampledGrid`]'s cell centres); between samples the value is trilinear
//! (NanoVDB's `SampleFromVoxels` of order 1).

use crate::math::{Bounds3, Mat3, Vec3};

/// Largest number of 8³ blocks a grid may span (2²⁶ block slots: 256 MiB of indices).
pub const MAX_BLOCKS: u64 = 1 << 26;
/// Largest number of leaf blocks kept (2²¹ leaves: 4 GiB of samples).
pub const MAX_LEAVES: u64 = 1 << 21;

/// A block slot: background (nothing stored).
const EMPTY: u32 = u32::MAX;
/// A block slot holding a tile index has this bit set; otherwise it is a leaf index.
const TILE: u32 = 1 << 31;

/// A region of constant value (a VDB tile): `dim`³ voxels from `origin`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VdbTile {
    /// Lowest voxel of the tile.
    pub origin: [i32; 3],
    /// Its side in voxels (8, 128 or 4096 in a standard tree).
    pub dim: i32,
    /// Its value.
    pub value: f32,
}

/// What a reader gathers from a file: checked ([`VdbParts::check`]) it describes a grid.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VdbParts {
    /// World-space → index-space matrix and translation: index = m·(world − t).
    pub world_to_index: Mat3,
    /// Translation t (the world position of index (0, 0, 0)).
    pub translation: Vec3,
    /// World-space bounds of the active voxels (the medium's box).
    pub world_bounds: Bounds3,
    /// Index-space bounds of the active voxels, inclusive.
    pub index_bounds: [[i32; 3]; 2],
    /// Value of voxels nowhere stored.
    pub background: f32,
    /// Leaf origins (multiples of 8), one per 512 samples of `leaf_values`.
    pub leaf_origins: Vec<[i32; 3]>,
    /// Leaf samples, 512 per leaf, voxel (i, j, k) at ((i&7)·64 + (j&7)·8 + (k&7)).
    pub leaf_values: Vec<f32>,
    /// Tiles whose value differs from the background.
    pub tiles: Vec<VdbTile>,
}

/// A grid's parts checked by [`VdbParts::check`] (every size consistent, the block span within
/// [`MAX_BLOCKS`]): plain data, what a scene description holds; [`VdbGrid::new`] makes the grid
/// ready for lookups.
#[derive(Clone, Debug, PartialEq)]
pub struct VdbGridDesc {
    parts: VdbParts,
    /// First block (voxel ≫ 3) spanned by the leaves and tiles, and the span in blocks.
    block_min: [i32; 3],
    block_dims: [i32; 3],
}

impl VdbParts {
    /// Checks the parts before anything is allocated: an error names what is too large or
    /// inconsistent.
    pub fn check(self) -> Result<VdbGridDesc, String> {
        let n_leaves = self.leaf_origins.len() as u64;
        if n_leaves > MAX_LEAVES {
            return Err(format!("{n_leaves} leaf nodes (at most {MAX_LEAVES})"));
        }
        if self.leaf_values.len() as u64 != n_leaves * 512 {
            return Err("leaf values do not match the leaf count".into());
        }
        if !self.world_to_index.is_finite() || !self.translation.is_finite() {
            return Err("its transform is not finite".into());
        }
        // The blocks spanned by leaves and tiles.
        let mut lo = [i32::MAX; 3];
        let mut hi = [i32::MIN; 3];
        let mut include = |o: [i32; 3], dim: i32| {
            for a in 0..3 {
                lo[a] = lo[a].min(o[a] >> 3);
                hi[a] = hi[a].max(((o[a] as i64 + dim as i64 - 1) >> 3) as i32);
            }
        };
        for &o in &self.leaf_origins {
            include(o, 8);
        }
        for t in &self.tiles {
            if t.dim < 1 {
                return Err(format!("a tile of size {}", t.dim));
            }
            include(t.origin, t.dim);
        }
        let (block_min, block_dims) = if lo[0] > hi[0] {
            ([0; 3], [0; 3])
        } else {
            let dims: [i64; 3] = std::array::from_fn(|a| hi[a] as i64 - lo[a] as i64 + 1);
            let n = dims[0] as u64 * dims[1] as u64 * dims[2] as u64;
            if n > MAX_BLOCKS {
                return Err(format!(
                    "it spans {} × {} × {} blocks of 8³ voxels (at most {MAX_BLOCKS} in all)",
                    dims[0], dims[1], dims[2]
                ));
            }
            (lo, dims.map(|d| d as i32))
        };
        Ok(VdbGridDesc {
            parts: self,
            block_min,
            block_dims,
        })
    }
}

impl VdbGridDesc {
    /// The parts as read.
    pub fn parts(&self) -> &VdbParts {
        &self.parts
    }

    /// World-space bounds of the active voxels.
    pub fn world_bounds(&self) -> Bounds3 {
        self.parts.world_bounds
    }
}

/// A sparse VDB float grid, ready for lookups.
#[derive(Clone, Debug, PartialEq)]
pub struct VdbGrid {
    world_to_index: Mat3,
    translation: Vec3,
    world_bounds: Bounds3,
    index_bounds: [[i32; 3]; 2],
    background: f32,
    /// First block (voxel ≫ 3) of the block array, and its size in blocks.
    block_min: [i32; 3],
    block_dims: [i32; 3],
    blocks: Vec<u32>,
    leaf_values: Vec<f32>,
    tile_values: Vec<f32>,
}

impl VdbGrid {
    /// The grid of checked parts: the block array over their span, each slot the leaf or the
    /// tile that covers it (a leaf wins over a tile, a smaller tile over a larger one), or
    /// empty (the background).
    pub fn new(desc: VdbGridDesc) -> VdbGrid {
        let VdbGridDesc {
            parts,
            block_min,
            block_dims,
        } = desc;
        let n_blocks = block_dims.iter().map(|&d| d as usize).product::<usize>();
        let mut g = VdbGrid {
            world_to_index: parts.world_to_index,
            translation: parts.translation,
            world_bounds: parts.world_bounds,
            index_bounds: parts.index_bounds,
            background: parts.background,
            block_min,
            block_dims,
            blocks: vec![EMPTY; n_blocks],
            leaf_values: parts.leaf_values,
            tile_values: Vec::with_capacity(parts.tiles.len()),
        };
        // Tiles first (largest first), so that leaves inside them win.
        let mut tiles = parts.tiles;
        tiles.sort_by_key(|t| std::cmp::Reverse(t.dim));
        for t in tiles {
            let id = g.tile_values.len() as u32 | TILE;
            g.tile_values.push(t.value);
            let b0 = t.origin.map(|v| v >> 3);
            let b1: [i32; 3] =
                std::array::from_fn(|a| ((t.origin[a] as i64 + t.dim as i64 - 1) >> 3) as i32);
            for bz in b0[2]..=b1[2] {
                for by in b0[1]..=b1[1] {
                    for bx in b0[0]..=b1[0] {
                        if let Some(s) = g.slot([bx, by, bz]) {
                            g.blocks[s] = id;
                        }
                    }
                }
            }
        }
        for (n, o) in parts.leaf_origins.iter().enumerate() {
            if let Some(s) = g.slot(o.map(|v| v >> 3)) {
                g.blocks[s] = n as u32;
            }
        }
        g
    }

    /// The index in `blocks` of block b, if inside the array.
    #[inline]
    fn slot(&self, b: [i32; 3]) -> Option<usize> {
        let mut s = 0usize;
        for a in (0..3).rev() {
            let r = b[a].wrapping_sub(self.block_min[a]);
            if r < 0 || r >= self.block_dims[a] {
                return None;
            }
            s = s * self.block_dims[a] as usize + r as usize;
        }
        Some(s)
    }

    /// The value stored at voxel (i, j, k).
    #[inline]
    pub fn value(&self, i: i32, j: i32, k: i32) -> f32 {
        let Some(s) = self.slot([i >> 3, j >> 3, k >> 3]) else {
            return self.background;
        };
        match self.blocks[s] {
            EMPTY => self.background,
            id if id & TILE != 0 => self.tile_values[(id & !TILE) as usize],
            leaf => {
                let off = (((i & 7) << 6) | ((j & 7) << 3) | (k & 7)) as usize;
                self.leaf_values[leaf as usize * 512 + off]
            }
        }
    }

    /// Index-space position of world-space `p`: m·(p − t).
    #[inline]
    pub fn world_to_index(&self, p: Vec3) -> Vec3 {
        self.world_to_index * (p - self.translation)
    }

    /// The trilinear blend at index-space point `x` of the eight voxels around it.
    #[inline]
    pub fn sample_index(&self, x: Vec3) -> f32 {
        let f = x.floor();
        // Far outside every stored block: the background (keeps the i32 conversion exact).
        if !f.is_finite() || f.abs().max_element() >= 1.0e9 {
            return self.background;
        }
        let u = x - f;
        let (i, j, k) = (f.x as i32, f.y as i32, f.z as i32);
        let v = |a: i32, b: i32, c: i32| self.value(i + a, j + b, k + c);
        let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
        let x00 = lerp(u.z, v(0, 0, 0), v(0, 0, 1));
        let x01 = lerp(u.z, v(0, 1, 0), v(0, 1, 1));
        let x10 = lerp(u.z, v(1, 0, 0), v(1, 0, 1));
        let x11 = lerp(u.z, v(1, 1, 0), v(1, 1, 1));
        lerp(u.x, lerp(u.y, x00, x01), lerp(u.y, x10, x11))
    }

    /// The trilinear value at world-space point `p`.
    #[inline]
    pub fn sample_world(&self, p: Vec3) -> f32 {
        self.sample_index(self.world_to_index(p))
    }

    /// World-space bounds of the active voxels.
    pub fn world_bounds(&self) -> Bounds3 {
        self.world_bounds
    }

    /// Index-space bounds of the active voxels, inclusive.
    pub fn index_bounds(&self) -> [[i32; 3]; 2] {
        self.index_bounds
    }

    /// The background value.
    pub fn background(&self) -> f32 {
        self.background
    }

    /// Number of leaf blocks stored.
    pub fn leaf_count(&self) -> usize {
        self.leaf_values.len() / 512
    }

    /// Bytes held.
    pub fn bytes(&self) -> usize {
        self.blocks.len() * 4 + self.leaf_values.len() * 4 + self.tile_values.len() * 4
    }

    /// The largest voxel value over the index box [lo, hi] (inclusive), clamped to the active
    /// index bounds; 0 when nothing is larger (pbrt-v4 starts its maximum at 0).
    pub fn max_in(&self, lo: [i32; 3], hi: [i32; 3]) -> f32 {
        let [b0, b1] = self.index_bounds;
        let a: [i32; 3] = std::array::from_fn(|i| lo[i].max(b0[i]));
        let b: [i32; 3] = std::array::from_fn(|i| hi[i].min(b1[i]));
        let mut m = 0.0f32;
        for k in a[2]..=b[2] {
            for j in a[1]..=b[1] {
                for i in a[0]..=b[0] {
                    m = m.max(self.value(i, j, k));
                }
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One leaf at origin (8, 0, −8) with value i + 10j + 100k at local (i, j, k), a tile of 8³
    /// at (0, 0, 0) with value 7, background 0.5, index = world/2 (voxel size 2).
    fn parts() -> VdbParts {
        let mut leaf = vec![0.0; 512];
        for i in 0..8 {
            for j in 0..8 {
                for k in 0..8 {
                    leaf[i * 64 + j * 8 + k] = (i + 10 * j + 100 * k) as f32;
                }
            }
        }
        VdbParts {
            world_to_index: Mat3::from_diagonal(glam::Vec3::splat(0.5)),
            translation: Vec3::ZERO,
            world_bounds: Bounds3::new(Vec3::new(0.0, 0.0, -16.0), Vec3::new(32.0, 16.0, 16.0)),
            index_bounds: [[0, 0, -8], [15, 7, 7]],
            background: 0.5,
            leaf_origins: vec![[8, 0, -8]],
            leaf_values: leaf,
            tiles: vec![VdbTile {
                origin: [0, 0, 0],
                dim: 8,
                value: 7.0,
            }],
        }
    }

    #[test]
    fn values_come_from_leaves_tiles_and_background() {
        let g = VdbGrid::new(parts().check().unwrap());
        assert_eq!(g.value(8, 0, -8), 0.0);
        assert_eq!(g.value(9, 2, -5), 1.0 + 20.0 + 300.0);
        assert_eq!(g.value(3, 3, 3), 7.0);
        assert_eq!(g.value(-1, 0, 0), 0.5);
        assert_eq!(g.value(i32::MIN, i32::MAX, 0), 0.5);
        assert_eq!(g.leaf_count(), 1);
    }

    #[test]
    fn trilinear_between_voxels() {
        let g = VdbGrid::new(parts().check().unwrap());
        // Index (9.5, 2, −5) blends voxels 9 and 10 on x: 321.5.
        assert!((g.sample_index(Vec3::new(9.5, 2.0, -5.0)) - 321.5).abs() < 1e-4);
        // World (19, 4, −10) is index (9.5, 2, −5).
        assert!((g.sample_world(Vec3::new(19.0, 4.0, -10.0)) - 321.5).abs() < 1e-4);
        // Between the tile (7) at x = 7 and the background at x = 8 (no leaf at k = 2).
        let v = g.sample_index(Vec3::new(7.25, 1.0, 2.0));
        assert!((v - (0.75 * 7.0 + 0.25 * 0.5)).abs() < 1e-5, "{v}");
        assert_eq!(g.sample_index(Vec3::splat(f32::NAN)), 0.5);
    }

    #[test]
    fn max_in_covers_the_box() {
        let g = VdbGrid::new(parts().check().unwrap());
        assert_eq!(g.max_in([8, 0, -8], [8, 0, -8]), 0.0);
        assert_eq!(
            g.max_in([-100, -100, -100], [100, 100, 100]),
            7.0 + 70.0 + 700.0
        );
        assert_eq!(g.max_in([0, 0, 0], [7, 7, 7]), 7.0);
    }

    #[test]
    fn sizes_are_checked_before_allocating() {
        let mut p = parts();
        p.tiles.push(VdbTile {
            origin: [-(1 << 30), 0, 0],
            dim: 4096,
            value: 1.0,
        });
        let e = p.check().unwrap_err();
        assert!(e.contains("blocks"), "{e}");
        let mut p = parts();
        p.leaf_values.pop();
        assert!(p.check().is_err());
    }
}
