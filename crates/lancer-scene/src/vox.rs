//! MagicaVoxel `.vox` models read into a [`VoxelGrid`], for lancer's `Shape "voxels"`.
//!
//! The format (little-endian throughout): the magic `VOX `, a version (150 or 200), then RIFF-
//! style chunks, each a 4-byte id, the byte size N of its content, the byte size M of its
//! children, the content, the children. The root `MAIN` chunk has no content; its children are
//! an optional `PACK` (model count), one `SIZE` (x, y, z as three i32; z is up) and `XYZI`
//! (a count n, then n × (x, y, z, colour index) bytes) per model, an optional `RGBA` palette
//! (256 × (r, g, b, a) bytes, entry i giving colour index i + 1), and scene-graph and material
//! chunks (`nTRN`, `nGRP`, `nSHP`, `MATL`, `LAYR`, `rOBJ`, …) that lancer skips. Without
//! `RGBA` the default MagicaVoxel palette applies ([`default_palette`]).
//!
//! lancer keeps the first model; a file with several warns that the others are left out (the
//! `nTRN`/`nSHP` scene graph that places them is not composed). Palette colours are sRGB and
//! become linear reflectances.
//!
//! Nothing is allocated on a header's word alone: every chunk must fit in its parent and in
//! the file, the voxel count must fit in its chunk, and a model is at most 256 cells on a
//! side (MagicaVoxel's own limit), so the dense grid is at most 16 MiB.

use lancer::math::Rgb;
use lancer::shape::{VoxelGrid, srgb8_to_linear};
use std::path::Path;

/// Largest model side lancer reads, in cells (MagicaVoxel's limit).
pub const MAX_SIDE: u32 = 256;

/// Why a `.vox` file could not be read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{file}: {message}")]
pub struct VoxError {
    /// The file, as named to the reader.
    pub file: String,
    /// What is wrong, one line.
    pub message: String,
}

/// A model read from a `.vox` file, and what the reader left out.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxModel {
    /// The first model's voxels, with the file's palette made linear.
    pub grid: VoxelGrid,
    /// What was read but not used (further models, voxels of colour 0, an unknown version).
    pub warnings: Vec<String>,
}

/// MagicaVoxel's default palette, as (r, g, b, a) per colour index (index 0, empty, is
/// transparent black): indices 1–215 are the 6×6×6 colour cube on the levels
/// ff, cc, 99, 66, 33, 00 (red slowest, blue fastest, black left out), then ramps of ten
/// levels (ee, dd, bb, aa, 88, 77, 55, 44, 22, 11) of red (216–225), green (226–235),
/// blue (236–245) and grey (246–255).
pub fn default_palette() -> [[u8; 4]; 256] {
    const CUBE: [u8; 6] = [0xff, 0xcc, 0x99, 0x66, 0x33, 0x00];
    const RAMP: [u8; 10] = [0xee, 0xdd, 0xbb, 0xaa, 0x88, 0x77, 0x55, 0x44, 0x22, 0x11];
    let mut p = [[0u8; 4]; 256];
    let mut i = 1;
    for r in CUBE {
        for g in CUBE {
            for b in CUBE {
                if (r, g, b) != (0, 0, 0) {
                    p[i] = [r, g, b, 0xff];
                    i += 1;
                }
            }
        }
    }
    for channel in 0..4 {
        for v in RAMP {
            p[i] = match channel {
                0 => [v, 0, 0, 0xff],
                1 => [0, v, 0, 0xff],
                2 => [0, 0, v, 0xff],
                _ => [v, v, v, 0xff],
            };
            i += 1;
        }
    }
    debug_assert_eq!(i, 256);
    p
}

/// An 8-bit sRGB palette (per colour index) made linear: each channel by
/// [`srgb8_to_linear`]; alpha is ignored.
pub fn linear_palette(p: &[[u8; 4]; 256]) -> [Rgb; 256] {
    std::array::from_fn(|i| {
        Rgb::new(
            srgb8_to_linear(p[i][0]),
            srgb8_to_linear(p[i][1]),
            srgb8_to_linear(p[i][2]),
        )
    })
}

/// Reads a `.vox` file.
pub fn read_vox(path: &Path) -> Result<VoxModel, VoxError> {
    crate::files_read::record(path);
    let name = path.display().to_string();
    let data = std::fs::read(path).map_err(|e| VoxError {
        file: name.clone(),
        message: format!("cannot read the file: {e}"),
    })?;
    parse_vox(&data, &name)
}

/// Reads `.vox` data held in memory; `name` names it in messages.
pub fn parse_vox(data: &[u8], name: &str) -> Result<VoxModel, VoxError> {
    parse(data).map_err(|message| VoxError {
        file: name.to_string(),
        message,
    })
}

fn u32_at(data: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]])
}

/// A chunk's header: id, where its content starts, content and children sizes.
struct Chunk {
    id: [u8; 4],
    content: usize,
    n: usize,
    m: usize,
}

/// The chunk whose header starts at `at`, checked to fit before `end`.
fn chunk_at(data: &[u8], at: usize, end: usize) -> Result<Chunk, String> {
    if end - at < 12 {
        return Err(format!(
            "truncated: a chunk header at byte {at} needs 12 bytes, {} left",
            end - at
        ));
    }
    let id = [data[at], data[at + 1], data[at + 2], data[at + 3]];
    let (n, m) = (u32_at(data, at + 4) as usize, u32_at(data, at + 8) as usize);
    let content = at + 12;
    if (n as u64 + m as u64) > (end - content) as u64 {
        return Err(format!(
            "truncated: chunk '{}' at byte {at} claims {n} + {m} bytes, only {} left",
            String::from_utf8_lossy(&id),
            end - content
        ));
    }
    Ok(Chunk { id, content, n, m })
}

fn parse(data: &[u8]) -> Result<VoxModel, String> {
    if data.len() < 8 || &data[0..4] != b"VOX " {
        return Err("not a MagicaVoxel file (it does not start with \"VOX \")".into());
    }
    let mut warnings = Vec::new();
    let version = u32_at(data, 4);
    if version != 150 && version != 200 {
        warnings.push(format!(
            "version {version} is not one lancer knows (150, 200); read as 150"
        ));
    }
    let main = chunk_at(data, 8, data.len())?;
    if &main.id != b"MAIN" {
        return Err(format!(
            "the first chunk is '{}', not 'MAIN'",
            String::from_utf8_lossy(&main.id)
        ));
    }
    let mut at = main.content + main.n;
    let end = at + main.m;
    let mut dims: Option<[u32; 3]> = None;
    let mut cells: Option<Vec<u8>> = None;
    let mut models = 0usize;
    let mut palette = default_palette();
    let mut zero_colour = 0usize;
    while at < end {
        let c = chunk_at(data, at, end)?;
        let body = &data[c.content..c.content + c.n];
        match &c.id {
            b"SIZE" => {
                models += 1;
                if body.len() < 12 {
                    return Err(format!(
                        "chunk 'SIZE' at byte {at} holds {} bytes, not 12",
                        body.len()
                    ));
                }
                if models == 1 {
                    let d = [0, 4, 8].map(|o| u32_at(body, o));
                    if d.iter().any(|&s| s == 0 || s > MAX_SIDE) {
                        return Err(format!(
                            "model size {}×{}×{} at byte {at}: each side must be 1 to {MAX_SIDE}",
                            d[0] as i32, d[1] as i32, d[2] as i32
                        ));
                    }
                    dims = Some(d);
                }
            }
            b"XYZI" => {
                let Some(d) = dims else {
                    return Err(format!("chunk 'XYZI' at byte {at} comes before any 'SIZE'"));
                };
                if body.len() < 4 {
                    return Err(format!(
                        "chunk 'XYZI' at byte {at} holds {} bytes, too few for its count",
                        body.len()
                    ));
                }
                let count = u32_at(body, 0) as u64;
                if 4 + 4 * count > body.len() as u64 {
                    return Err(format!(
                        "chunk 'XYZI' at byte {at} claims {count} voxels but holds room for {}",
                        (body.len() - 4) / 4
                    ));
                }
                if models == 1 && cells.is_none() {
                    let mut grid = vec![0u8; d.iter().map(|&s| s as usize).product()];
                    for v in body[4..4 + 4 * count as usize].chunks_exact(4) {
                        let (x, y, z, ci) = (v[0] as u32, v[1] as u32, v[2] as u32, v[3]);
                        if x >= d[0] || y >= d[1] || z >= d[2] {
                            return Err(format!(
                                "voxel ({x}, {y}, {z}) in chunk 'XYZI' at byte {at} is outside the model's size {}×{}×{}",
                                d[0], d[1], d[2]
                            ));
                        }
                        if ci == 0 {
                            zero_colour += 1;
                            continue;
                        }
                        grid[(x + d[0] * (y + d[1] * z)) as usize] = ci;
                    }
                    cells = Some(grid);
                }
            }
            b"RGBA" => {
                if body.len() < 1024 {
                    return Err(format!(
                        "chunk 'RGBA' at byte {at} holds {} bytes, not 1024",
                        body.len()
                    ));
                }
                // Entry i is colour index i + 1; the last entry has no index.
                for i in 0..255 {
                    let e = &body[4 * i..4 * i + 4];
                    palette[i + 1] = [e[0], e[1], e[2], e[3]];
                }
            }
            // PACK, the scene graph (nTRN, nGRP, nSHP), materials, layers, cameras, notes.
            _ => {}
        }
        at = c.content + c.n + c.m;
    }
    let (Some(dims), Some(cells)) = (dims, cells) else {
        return Err(if dims.is_none() {
            "no model: the file has no 'SIZE' chunk".into()
        } else {
            "no model: the file has a 'SIZE' but no 'XYZI' chunk".into()
        });
    };
    if models > 1 {
        warnings.push(format!(
            "the file holds {models} models; lancer uses the first and leaves the others out"
        ));
    }
    if zero_colour > 0 {
        warnings.push(format!(
            "{zero_colour} voxels of colour index 0 (empty) skipped"
        ));
    }
    let grid = VoxelGrid::new(dims, cells, linear_palette(&palette))?;
    Ok(VoxModel { grid, warnings })
}

/// Writes a one-model `.vox` file (version 150): `dims` and `cells` as in [`VoxelGrid::new`]
/// (x fastest; 0 = empty), and an `RGBA` palette chunk when `palette` (per colour index,
/// entry 0 unused) is given. Dimensions must be at most 256 so that coordinates fit in a byte.
pub fn write_vox(dims: [u32; 3], cells: &[u8], palette: Option<&[[u8; 4]; 256]>) -> Vec<u8> {
    let mut voxels = Vec::new();
    for z in 0..dims[2] {
        for y in 0..dims[1] {
            for x in 0..dims[0] {
                let c = cells[(x + dims[0] * (y + dims[1] * z)) as usize];
                if c != 0 {
                    voxels.extend_from_slice(&[x as u8, y as u8, z as u8, c]);
                }
            }
        }
    }
    let chunk = |out: &mut Vec<u8>, id: &[u8; 4], content: &[u8], children: usize| {
        out.extend_from_slice(id);
        out.extend_from_slice(&(content.len() as u32).to_le_bytes());
        out.extend_from_slice(&(children as u32).to_le_bytes());
        out.extend_from_slice(content);
    };
    let mut children = Vec::new();
    let size: Vec<u8> = dims.iter().flat_map(|d| d.to_le_bytes()).collect();
    chunk(&mut children, b"SIZE", &size, 0);
    let mut xyzi = ((voxels.len() / 4) as u32).to_le_bytes().to_vec();
    xyzi.extend_from_slice(&voxels);
    chunk(&mut children, b"XYZI", &xyzi, 0);
    if let Some(p) = palette {
        let mut rgba: Vec<u8> = p[1..].iter().flatten().copied().collect();
        rgba.extend_from_slice(&[0; 4]);
        chunk(&mut children, b"RGBA", &rgba, 0);
    }
    let mut out = b"VOX ".to_vec();
    out.extend_from_slice(&150u32.to_le_bytes());
    chunk(&mut out, b"MAIN", &[], children.len());
    out.extend_from_slice(&children);
    out
}
