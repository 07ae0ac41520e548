//! Reader of OIDN's TZA weight blobs (the format its `core/tza.cpp` reads).
//!
//! Layout (little-endian): `u16` magic 0x41D7, `u8` major version (2), `u8` minor version,
//! `u64` offset of the tensor table. The table: `u32` tensor count, then per tensor `u16`
//! name length, the name, `u8` rank n, n × `u32` dimensions, n layout letters (`x` or `oihw`),
//! one data-type letter (`h` = binary16, `f` = binary32) and the `u64` offset of its data.

use std::collections::HashMap;

/// One tensor of a blob, converted to f32 (row-major in its layout: `oihw` or `x`).
#[derive(Clone, Debug)]
pub struct TzaTensor {
    /// The dimensions, outermost first.
    pub dims: Vec<usize>,
    /// The values.
    pub data: Vec<f32>,
}

/// Why a blob could not be read.
#[derive(Debug, thiserror::Error)]
#[error("weights blob: {0}")]
pub struct TzaError(String);

/// A bounds-checked cursor over the blob.
struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], TzaError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.buf.len());
        let end = end.ok_or_else(|| TzaError(format!("truncated at byte {}", self.pos)))?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }
    fn u8(&mut self) -> Result<u8, TzaError> {
        Ok(self.take(1)?[0])
    }
    fn u16(&mut self) -> Result<u16, TzaError> {
        Ok(u16::from_le_bytes(self.take(2)?.try_into().unwrap()))
    }
    fn u32(&mut self) -> Result<u32, TzaError> {
        Ok(u32::from_le_bytes(self.take(4)?.try_into().unwrap()))
    }
    fn u64(&mut self) -> Result<u64, TzaError> {
        Ok(u64::from_le_bytes(self.take(8)?.try_into().unwrap()))
    }
}

/// IEEE 754 binary16 → binary32 (exact: every half is a float).
pub fn f16_to_f32(h: u16) -> f32 {
    let sign = ((h as u32) & 0x8000) << 16;
    let exp = ((h >> 10) & 0x1f) as u32;
    let mant = (h & 0x3ff) as u32;
    let bits = match (exp, mant) {
        (0, 0) => sign,
        // subnormal: mant · 2⁻²⁴
        (0, m) => return sign_one(sign) * (m as f32) * (1.0 / 16_777_216.0),
        (31, 0) => sign | 0x7f80_0000,
        (31, m) => sign | 0x7f80_0000 | (m << 13),
        (e, m) => sign | ((e + 127 - 15) << 23) | (m << 13),
    };
    f32::from_bits(bits)
}

/// ±1 by a float sign bit.
fn sign_one(sign: u32) -> f32 {
    if sign != 0 { -1.0 } else { 1.0 }
}

/// Parses a TZA blob into its named tensors.
pub fn parse(blob: &[u8]) -> Result<HashMap<String, TzaTensor>, TzaError> {
    let mut r = Reader { buf: blob, pos: 0 };
    let magic = r.u16()?;
    if magic != 0x41D7 {
        return Err(TzaError(format!("bad magic {magic:#x}")));
    }
    let major = r.u8()?;
    let _minor = r.u8()?;
    if major != 2 {
        return Err(TzaError(format!("unsupported version {major}")));
    }
    r.pos = usize::try_from(r.u64()?).map_err(|_| TzaError("table offset".into()))?;
    let count = r.u32()?;
    let mut map = HashMap::new();
    for _ in 0..count {
        let len = r.u16()? as usize;
        let name = String::from_utf8_lossy(r.take(len)?).into_owned();
        let rank = r.u8()? as usize;
        let dims = (0..rank)
            .map(|_| r.u32().map(|d| d as usize))
            .collect::<Result<Vec<_>, _>>()?;
        let layout = r.take(rank)?;
        if layout != b"x" && layout != b"oihw" {
            return Err(TzaError(format!("{name}: unknown layout")));
        }
        let dtype = r.u8()?;
        let offset = usize::try_from(r.u64()?).map_err(|_| TzaError("data offset".into()))?;
        let n: usize = dims.iter().product();
        let mut d = Reader {
            buf: blob,
            pos: offset,
        };
        let data = match dtype {
            b'h' => d
                .take(2 * n)?
                .chunks_exact(2)
                .map(|b| f16_to_f32(u16::from_le_bytes([b[0], b[1]])))
                .collect(),
            b'f' => d
                .take(4 * n)?
                .chunks_exact(4)
                .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
                .collect(),
            _ => return Err(TzaError(format!("{name}: unknown data type"))),
        };
        map.insert(name, TzaTensor { dims, data });
    }
    Ok(map)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_floats_decode() {
        assert_eq!(f16_to_f32(0x3c00), 1.0);
        assert_eq!(f16_to_f32(0xc000), -2.0);
        assert_eq!(f16_to_f32(0x7bff), 65504.0);
        assert_eq!(f16_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(f16_to_f32(0x8001), -(2f32.powi(-24)));
        assert_eq!(f16_to_f32(0x3555), 0.333_251_95);
        assert!(f16_to_f32(0x7c00).is_infinite());
        assert!(f16_to_f32(0x7e00).is_nan());
    }

    #[test]
    fn bad_blobs_are_refused() {
        assert!(parse(&[]).is_err());
        assert!(parse(&[0xd7, 0x41, 1, 0, 12, 0, 0, 0, 0, 0, 0, 0]).is_err());
        assert!(parse(&[0xd7, 0x41, 2, 0, 200, 0, 0, 0, 0, 0, 0, 0]).is_err());
    }
}
