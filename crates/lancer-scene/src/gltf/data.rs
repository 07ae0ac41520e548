//! The bytes of a glTF asset: the GLB container, buffers (the GLB's `BIN` chunk, files beside
//! the `.gltf`, `data:` URIs in base64) and typed reads of accessors, every offset checked
//! against what the file really holds.
//!
//! GLB layout (glTF 2.0 § 4.4): a 12-byte header (magic `glTF`, version 2, total length), then
//! chunks of (length, type, data): first `JSON`, then optionally `BIN`, all little endian.

use ::gltf::accessor::{DataType, Dimensions};
use ::gltf::{Accessor, Document};
use std::path::{Path, PathBuf};

/// The two chunks of a GLB file.
#[derive(Debug)]
pub struct Glb<'a> {
    /// The JSON chunk.
    pub json: &'a [u8],
    /// The binary chunk, when present.
    pub bin: Option<&'a [u8]>,
}

const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

fn le32(b: &[u8], at: usize) -> Option<u32> {
    let s = b.get(at..at + 4)?;
    Some(u32::from_le_bytes([s[0], s[1], s[2], s[3]]))
}

/// Splits a GLB file into its JSON and BIN chunks; every length is checked against the bytes
/// present, and chunks of unknown types after the first two are skipped (as the spec asks).
pub fn split_glb(bytes: &[u8]) -> Result<Glb<'_>, String> {
    if bytes.len() < 12 || &bytes[0..4] != b"glTF" {
        return Err("not a GLB file (no 12-byte header starting with 'glTF')".into());
    }
    let version = le32(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(format!("GLB version {version}: lancer reads version 2"));
    }
    let total = le32(bytes, 8).unwrap_or(0) as usize;
    if total > bytes.len() || total < 12 {
        return Err(format!(
            "the GLB header gives a length of {total} bytes but the file has {}",
            bytes.len()
        ));
    }
    let mut at = 12;
    let mut json = None;
    let mut bin = None;
    let mut index = 0;
    while at < total {
        let (Some(len), Some(kind)) = (le32(bytes, at), le32(bytes, at + 4)) else {
            return Err(format!(
                "GLB chunk {index} at byte {at}: truncated chunk header"
            ));
        };
        let start = at + 8;
        let end = start
            .checked_add(len as usize)
            .filter(|&e| e <= total)
            .ok_or_else(|| {
                format!(
                    "GLB chunk {index} at byte {at} claims {len} bytes but only {} remain",
                    total.saturating_sub(start)
                )
            })?;
        let data = &bytes[start..end];
        match (index, kind) {
            (0, CHUNK_JSON) => json = Some(data),
            (0, _) => return Err("the first GLB chunk is not the JSON chunk".into()),
            (1, CHUNK_BIN) => bin = Some(data),
            _ => {}
        }
        index += 1;
        // Chunks start on 4-byte boundaries.
        at = (end + 3) & !3;
    }
    Ok(Glb {
        json: json.ok_or("the GLB file has no JSON chunk")?,
        bin,
    })
}

/// Decodes base64 (RFC 4648, standard alphabet, `=` padding optional, whitespace ignored).
pub fn base64_decode(text: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let mut acc = 0u32;
    let mut bits = 0;
    for (i, c) in text.bytes().enumerate() {
        let v = match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' | b'-' => 62,
            b'/' | b'_' => 63,
            b'=' => break,
            c if c.is_ascii_whitespace() => continue,
            _ => return Err(format!("invalid base64 character at position {i}")),
        };
        // Each character carries 6 bits; a byte is out once 8 have gathered.
        acc = (acc << 6) | v as u32;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((acc >> bits) as u8);
        }
    }
    Ok(out)
}

/// Undoes `%XX` escapes in a relative URI (file names with spaces are written `%20`).
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        if b[i] == b'%'
            && i + 2 < b.len()
            && let (Some(h), Some(l)) = (hex(b[i + 1]), hex(b[i + 2]))
        {
            out.push((h * 16 + l) as u8);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// What a URI holds: bytes decoded from a `data:` URI, or a file (relative to `dir`) to read.
pub enum UriData {
    /// Bytes of a `data:…;base64,…` URI.
    Bytes(Vec<u8>),
    /// A file path.
    File(PathBuf),
}

/// Resolves a glTF URI: a base64 `data:` URI or a path relative to the asset's folder.
pub fn resolve_uri(uri: &str, dir: &Path) -> Result<UriData, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, payload) = rest
            .split_once(";base64,")
            .ok_or("a data: URI that is not base64")?;
        return base64_decode(payload).map(UriData::Bytes);
    }
    if uri.contains("://") {
        return Err(format!("URI {uri}: only files and data: URIs are read"));
    }
    Ok(UriData::File(dir.join(percent_decode(uri))))
}

/// Reads what a URI holds.
pub fn read_uri(uri: &str, dir: &Path) -> Result<Vec<u8>, String> {
    match resolve_uri(uri, dir)? {
        UriData::Bytes(b) => Ok(b),
        UriData::File(p) => {
            crate::files_read::record(&p);
            std::fs::read(&p).map_err(|e| format!("cannot read {}: {e}", p.display()))
        }
    }
}

/// Loads every buffer of the document: the GLB's BIN chunk, files or data URIs; each must hold
/// at least the `byteLength` it declares.
pub fn load_buffers(
    doc: &Document,
    bin: Option<&[u8]>,
    dir: &Path,
) -> Result<Vec<Vec<u8>>, String> {
    let mut buffers = Vec::new();
    for b in doc.buffers() {
        let data = match b.source() {
            ::gltf::buffer::Source::Bin => bin
                .ok_or_else(|| {
                    format!(
                        "buffer {} refers to the GLB binary chunk, which the file does not have",
                        b.index()
                    )
                })?
                .to_vec(),
            ::gltf::buffer::Source::Uri(uri) => {
                read_uri(uri, dir).map_err(|e| format!("buffer {}: {e}", b.index()))?
            }
        };
        if data.len() < b.length() {
            return Err(format!(
                "buffer {} declares {} bytes but holds {}",
                b.index(),
                b.length(),
                data.len()
            ));
        }
        buffers.push(data);
    }
    Ok(buffers)
}

/// The bytes of buffer view `view`, checked against its buffer.
pub fn view_bytes<'b>(
    buffers: &'b [Vec<u8>],
    view: &::gltf::buffer::View,
) -> Result<&'b [u8], String> {
    let buf = buffers
        .get(view.buffer().index())
        .ok_or_else(|| format!("buffer view {}: no such buffer", view.index()))?;
    view.offset()
        .checked_add(view.length())
        .and_then(|end| buf.get(view.offset()..end))
        .ok_or_else(|| {
            format!(
                "buffer view {} spans bytes {}..{} of buffer {}, which has {}",
                view.index(),
                view.offset(),
                view.offset().saturating_add(view.length()),
                view.buffer().index(),
                buf.len()
            )
        })
}

/// Number of components of an accessor's elements.
fn components(d: Dimensions) -> usize {
    match d {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 | Dimensions::Mat2 => 4,
        Dimensions::Mat3 => 9,
        Dimensions::Mat4 => 16,
    }
}

fn component_size(t: DataType) -> usize {
    match t {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// One component as a float; normalized integers map to [0, 1] or [−1, 1] as the spec says:
/// u8 c/255, u16 c/65535, i8 max(c/127, −1), i16 max(c/32767, −1).
fn component_f32(b: &[u8], t: DataType, normalized: bool) -> f32 {
    match t {
        DataType::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
        DataType::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f32,
        DataType::U8 if normalized => b[0] as f32 / 255.0,
        DataType::U8 => b[0] as f32,
        DataType::I8 if normalized => (b[0] as i8 as f32 / 127.0).max(-1.0),
        DataType::I8 => b[0] as i8 as f32,
        DataType::U16 => {
            let v = u16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized { v / 65535.0 } else { v }
        }
        DataType::I16 => {
            let v = i16::from_le_bytes([b[0], b[1]]) as f32;
            if normalized {
                (v / 32767.0).max(-1.0)
            } else {
                v
            }
        }
    }
}

/// One unsigned integer component (indices).
fn component_u32(b: &[u8], t: DataType) -> Option<u32> {
    match t {
        DataType::U8 => Some(b[0] as u32),
        DataType::U16 => Some(u16::from_le_bytes([b[0], b[1]]) as u32),
        DataType::U32 => Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        _ => None,
    }
}

/// Largest accessor read, in bytes (1 GiB): an accessor without a buffer view is zeros that
/// a hostile count could make enormous.
const MAX_ACCESSOR_BYTES: usize = 1 << 30;

/// The raw elements of an accessor: for each of `count` elements, the bytes of its components
/// (`ncomp × size` bytes), read from its buffer view with its stride, then sparse substitution.
/// Returns the component type, the component count and a flat byte vector.
fn element_bytes(buffers: &[Vec<u8>], a: &Accessor) -> Result<(DataType, usize, Vec<u8>), String> {
    let t = a.data_type();
    let ncomp = components(a.dimensions());
    let elem = ncomp * component_size(t);
    let count = a.count();
    let total = count
        .checked_mul(elem)
        .filter(|&n| n <= MAX_ACCESSOR_BYTES)
        .ok_or_else(|| format!("accessor {}: {count} elements is too many", a.index()))?;
    // The view's bytes are checked before anything is allocated for them.
    let view = match a.view() {
        Some(view) => {
            let bytes = view_bytes(buffers, &view)?;
            let stride = view.stride().unwrap_or(elem).max(elem);
            // The last element ends at offset + stride·(count − 1) + element size.
            let need = stride
                .checked_mul(count.saturating_sub(1))
                .and_then(|n| n.checked_add(a.offset()))
                .and_then(|n| n.checked_add(elem));
            match need {
                Some(need) if count == 0 || need <= bytes.len() => Some((bytes, stride)),
                _ => {
                    return Err(format!(
                        "accessor {} reads {count} elements of {elem} bytes every {stride} from byte {} of buffer view {}, which has {} bytes",
                        a.index(),
                        a.offset(),
                        view.index(),
                        bytes.len()
                    ));
                }
            }
        }
        None => None,
    };
    let mut out = vec![0u8; total];
    if let Some((bytes, stride)) = view {
        for i in 0..count {
            let s = a.offset() + i * stride;
            out[i * elem..(i + 1) * elem].copy_from_slice(&bytes[s..s + elem]);
        }
    }
    if let Some(sparse) = a.sparse() {
        let n = sparse.count();
        let idx = sparse.indices();
        let idx_bytes = view_bytes(buffers, &idx.view())?;
        let idx_t = match idx.index_type() {
            ::gltf::accessor::sparse::IndexType::U8 => DataType::U8,
            ::gltf::accessor::sparse::IndexType::U16 => DataType::U16,
            ::gltf::accessor::sparse::IndexType::U32 => DataType::U32,
        };
        let isz = component_size(idx_t);
        let vals = sparse.values();
        let val_bytes = view_bytes(buffers, &vals.view())?;
        let short = |what: &str| {
            format!(
                "accessor {}: the sparse {what} run past the end of their buffer view",
                a.index()
            )
        };
        let fits = |offset: usize, size: usize, len: usize| {
            n.checked_mul(size)
                .and_then(|b| b.checked_add(offset))
                .is_some_and(|end| end <= len)
        };
        if !fits(idx.offset(), isz, idx_bytes.len()) {
            return Err(short("indices"));
        }
        if !fits(vals.offset(), elem, val_bytes.len()) {
            return Err(short("values"));
        }
        for k in 0..n {
            let s = idx.offset() + k * isz;
            let target = component_u32(&idx_bytes[s..s + isz], idx_t).unwrap_or(0) as usize;
            if target >= count {
                return Err(format!(
                    "accessor {}: sparse index {target} is out of range for {count} elements",
                    a.index()
                ));
            }
            let v = vals.offset() + k * elem;
            out[target * elem..(target + 1) * elem].copy_from_slice(&val_bytes[v..v + elem]);
        }
    }
    Ok((t, ncomp, out))
}

/// Reads an accessor of `N`-component float vectors (positions, normals, texture coordinates).
pub fn read_vecs<const N: usize>(
    buffers: &[Vec<u8>],
    a: &Accessor,
) -> Result<Vec<[f32; N]>, String> {
    let (t, ncomp, bytes) = element_bytes(buffers, a)?;
    if ncomp != N {
        return Err(format!(
            "accessor {} has {ncomp} components per element, {N} expected",
            a.index()
        ));
    }
    let csize = component_size(t);
    Ok(bytes
        .chunks_exact(N * csize)
        .map(|e| std::array::from_fn(|c| component_f32(&e[c * csize..], t, a.normalized())))
        .collect())
}

/// Reads an accessor of unsigned integer scalars (vertex indices).
pub fn read_indices(buffers: &[Vec<u8>], a: &Accessor) -> Result<Vec<u32>, String> {
    let (t, ncomp, bytes) = element_bytes(buffers, a)?;
    let csize = component_size(t);
    if ncomp != 1 || !matches!(t, DataType::U8 | DataType::U16 | DataType::U32) {
        return Err(format!(
            "accessor {}: indices must be unsigned integer scalars",
            a.index()
        ));
    }
    Ok(bytes
        .chunks_exact(csize)
        .map(|e| component_u32(e, t).unwrap_or(0))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_known_strings() {
        assert_eq!(base64_decode("TWFu").unwrap(), b"Man");
        assert_eq!(base64_decode("TWE=").unwrap(), b"Ma");
        assert_eq!(base64_decode("TQ==").unwrap(), b"M");
        assert_eq!(base64_decode("AAABAAIA").unwrap(), [0, 0, 1, 0, 2, 0]);
        assert!(base64_decode("TW*u").is_err());
    }

    #[test]
    fn percent_escapes_are_undone() {
        assert_eq!(percent_decode("my%20file.bin"), "my file.bin");
        assert_eq!(percent_decode("100%"), "100%");
    }

    #[test]
    fn glb_chunk_lengths_are_checked() {
        let mut glb = b"glTF".to_vec();
        glb.extend(2u32.to_le_bytes());
        glb.extend(24u32.to_le_bytes());
        glb.extend(4u32.to_le_bytes());
        glb.extend(CHUNK_JSON.to_le_bytes());
        glb.extend(b"{}  ");
        let ok = split_glb(&glb).unwrap();
        assert_eq!(ok.json, b"{}  ");
        assert!(ok.bin.is_none());
        // A JSON chunk claiming more bytes than the file has.
        let mut bad = glb.clone();
        bad[12..16].copy_from_slice(&400u32.to_le_bytes());
        assert!(split_glb(&bad).unwrap_err().contains("claims 400 bytes"));
        // A header length shorter than the header itself.
        let mut bad = glb.clone();
        bad[8..12].copy_from_slice(&3u32.to_le_bytes());
        assert!(split_glb(&bad).is_err());
        assert!(split_glb(b"glTF").is_err());
    }
}
