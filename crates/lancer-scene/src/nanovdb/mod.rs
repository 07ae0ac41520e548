//! NanoVDB files (`.nvdb`): the float grids pbrt-v4's `nanovdb` medium reads (`density`,
//! `temperature`), uncompressed or ZIP (zlib) compressed, read from the format's published
//! layout into lancer's sparse grid parts, checked ([`VdbGridDesc`]; the scene build makes the
//! [`lancer::medium::vdb::VdbGrid`]).
//!
//! A file is a sequence of *segments*. Each starts with a 16-byte header — the magic
//! `"NanoVDB0"` (u64), the format version, the number of grids (u16) and the codec (u16: 0 none,
//! 1 ZIP, 2 Blosc) — followed by one metadata record per grid (sizes, type, class, bounds, name)
//! and then the grids' data, each `fileSize` bytes: the raw grid buffer, or for ZIP a u64
//! compressed size and a zlib stream that inflates to the grid's `gridSize` bytes. All numbers
//! are little-endian.
//!
//! Format version 19 (Houdini's) writes the version as two u16 (major, minor) and a 144-byte
//! metadata record; version 32 (today's NanoVDB, magic `"NanoVDB0"` or `"NanoVDB2"`) packs it
//! in a u32 (major ≪ 21 | minor ≪ 10 | patch) with a 176-byte record; the grid name's length is
//! a u32 at byte 40 or 136 of the record. The grid buffer is a pointer-free VDB tree whose
//! layout depends on the version ([`tree`]). Every offset and count read
//! from a file is checked against the buffer before use, and sizes before allocation.

mod tree;

use lancer::medium::vdb::VdbGridDesc;
use std::io::Read;

/// "NanoVDB0" as a little-endian u64.
const MAGIC: u64 = 0x3042_4456_6f6e_614e;
/// "NanoVDB2", version 32.6's magic number of files.
const MAGIC_FILE: u64 = 0x3242_4456_6f6e_614e;
/// Largest grid buffer accepted (4 GiB).
const MAX_GRID_BYTES: u64 = 1 << 32;
/// The metadata record of format 19 before the grid name.
const META_BYTES: usize = 144;
/// The metadata record of format 32 before the grid name.
const META_BYTES_32: usize = 176;

/// A grid's record in a segment.
#[derive(Clone, Debug, PartialEq)]
pub struct GridInfo {
    /// The grid's name.
    pub name: String,
    /// NanoVDB's grid type (1 = float).
    pub grid_type: u32,
    /// NanoVDB's grid class (0 unknown, 1 level set, 2 fog volume, …).
    pub grid_class: u32,
    /// Active voxels.
    pub voxel_count: u64,
    /// Bytes of the grid buffer once decompressed.
    pub grid_size: u64,
    /// Bytes it takes in the file.
    pub file_size: u64,
    /// Compression of its data (0 none, 1 ZIP, 2 Blosc).
    pub codec: u16,
    /// Major format version (19 or 32).
    pub version: u32,
    /// Offset of its data in the file.
    offset: usize,
}

/// A little-endian reader over a byte slice that fails instead of reading past its end.
pub(crate) struct Bytes<'a> {
    pub(crate) data: &'a [u8],
}

impl<'a> Bytes<'a> {
    pub(crate) fn slice(&self, at: u64, n: u64) -> Result<&'a [u8], String> {
        let end = at.checked_add(n).ok_or("an offset overflows")?;
        if end > self.data.len() as u64 {
            return Err(format!(
                "truncated: needs bytes {at}..{end} of {}",
                self.data.len()
            ));
        }
        Ok(&self.data[at as usize..end as usize])
    }
    pub(crate) fn u16(&self, at: u64) -> Result<u16, String> {
        Ok(u16::from_le_bytes(self.slice(at, 2)?.try_into().unwrap()))
    }
    pub(crate) fn u32(&self, at: u64) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.slice(at, 4)?.try_into().unwrap()))
    }
    pub(crate) fn i32(&self, at: u64) -> Result<i32, String> {
        Ok(i32::from_le_bytes(self.slice(at, 4)?.try_into().unwrap()))
    }
    pub(crate) fn u64(&self, at: u64) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.slice(at, 8)?.try_into().unwrap()))
    }
    pub(crate) fn f32(&self, at: u64) -> Result<f32, String> {
        Ok(f32::from_le_bytes(self.slice(at, 4)?.try_into().unwrap()))
    }
    pub(crate) fn f64(&self, at: u64) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.slice(at, 8)?.try_into().unwrap()))
    }
}

/// The grids a NanoVDB file holds, in file order.
pub fn list_grids(data: &[u8]) -> Result<Vec<GridInfo>, String> {
    let b = Bytes { data };
    let mut grids = Vec::new();
    let mut at = 0u64;
    while at < data.len() as u64 {
        let magic = b.u64(at)?;
        if magic != MAGIC && magic != MAGIC_FILE {
            return Err(if at == 0 {
                "not a NanoVDB file (no \"NanoVDB0\" magic number)".to_string()
            } else {
                format!("no segment header at byte {at}")
            });
        }
        let v = b.u32(at + 8)?;
        let version = if b.u16(at + 8)? == 19 { 19 } else { v >> 21 };
        if version != 19 && version != 32 {
            return Err(format!(
                "NanoVDB format version {}.{}.{} is not supported (lancer reads versions 19 \
                 and 32)",
                v >> 21,
                (v >> 10) & 0x7ff,
                v & 0x3ff
            ));
        }
        let (meta_bytes, name_at) = if version == 32 {
            (META_BYTES_32 as u64, 136)
        } else {
            (META_BYTES as u64, 40)
        };
        let count = b.u16(at + 12)?;
        let codec = b.u16(at + 14)?;
        at += 16;
        let mut metas = Vec::with_capacity(count.min(64) as usize);
        for _ in 0..count {
            let grid_size = b.u64(at)?;
            let file_size = b.u64(at + 8)?;
            let voxel_count = b.u64(at + 24)?;
            let grid_type = b.u32(at + 32)?;
            let grid_class = b.u32(at + 36)?;
            let name_size = b.u32(at + name_at)? as u64;
            let raw = b.slice(at + meta_bytes, name_size)?;
            let name = raw.split(|&c| c == 0).next().unwrap_or(&[]);
            metas.push(GridInfo {
                name: String::from_utf8_lossy(name).into_owned(),
                grid_type,
                grid_class,
                voxel_count,
                grid_size,
                file_size,
                codec,
                version,
                offset: 0,
            });
            at += meta_bytes + name_size;
        }
        for m in &mut metas {
            b.slice(at, m.file_size)?;
            m.offset = at as usize;
            at += m.file_size;
        }
        grids.extend(metas);
    }
    Ok(grids)
}

/// The decompressed buffer of grid `g` of the file `data`.
fn grid_buffer(data: &[u8], g: &GridInfo) -> Result<Vec<u8>, String> {
    if g.grid_size > MAX_GRID_BYTES {
        return Err(format!(
            "grid \"{}\" takes {} bytes (at most {MAX_GRID_BYTES})",
            g.name, g.grid_size
        ));
    }
    let stored = &data[g.offset..g.offset + g.file_size as usize];
    match g.codec {
        0 => {
            if g.file_size < g.grid_size {
                return Err(format!("grid \"{}\" is truncated", g.name));
            }
            Ok(stored[..g.grid_size as usize].to_vec())
        }
        1 => {
            let b = Bytes { data: stored };
            let n = b.u64(0)?;
            let zipped = b.slice(8, n)?;
            // No allocation from the header's claim: the buffer grows with what inflates, and
            // stops one byte past the size announced.
            let mut out = Vec::new();
            flate2::read::ZlibDecoder::new(zipped)
                .take(g.grid_size + 1)
                .read_to_end(&mut out)
                .map_err(|e| format!("grid \"{}\": ZIP data: {e}", g.name))?;
            if out.len() as u64 != g.grid_size {
                return Err(format!(
                    "grid \"{}\" inflates to {} bytes, not the {} announced",
                    g.name,
                    out.len(),
                    g.grid_size
                ));
            }
            Ok(out)
        }
        2 => Err(
            "Blosc-compressed NanoVDB grids are not supported (ZIP and uncompressed are)".into(),
        ),
        c => Err(format!("unknown NanoVDB codec {c}")),
    }
}

/// The float grid called `name` in the NanoVDB file `data`, or `None` if the file has no grid
/// of that name. Like pbrt-v4, only fog-volume (or unclassified) float grids are accepted.
pub fn read_float_grid(data: &[u8], name: &str) -> Result<Option<VdbGridDesc>, String> {
    let grids = list_grids(data)?;
    let Some(g) = grids.iter().find(|g| g.name == name) else {
        return Ok(None);
    };
    if g.grid_type != 1 {
        return Err(format!(
            "grid \"{name}\" holds values of NanoVDB type {} (lancer reads float grids)",
            g.grid_type
        ));
    }
    if g.grid_class != 0 && g.grid_class != 2 {
        return Err(format!("grid \"{name}\" isn't a FogVolume grid"));
    }
    let buf = grid_buffer(data, g)?;
    let parts = tree::read(&buf, g.version).map_err(|e| format!("grid \"{name}\": {e}"))?;
    parts
        .check()
        .map(Some)
        .map_err(|e| format!("grid \"{name}\": {e}"))
}

#[cfg(test)]
pub(crate) mod tests;
