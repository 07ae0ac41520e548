//! The "tensor file" container of RGL's `.bsdf` files (Dupuy & Jakob 2018), written from the
//! format's description (as pbrt-v4 reads it), all little-endian:
//!
//! - 12 bytes `tensor_file\0`, 2 bytes version (1, 0), u32 number of fields;
//! - per field: u16 name length, the name, u16 rank, u8 type (1 u8, 2 i8, 3 u16, 4 i16,
//!   5 u32, 6 i32, 7 u64, 8 i64, 9 f16, 10 f32, 11 f64), u64 offset of its data from the
//!   file's start, then `rank` u64 sizes;
//! - the fields' data, row-major, at their offsets.
//!
//! Every size and offset is checked against the file before anything is allocated: a bad
//! file is an error saying what is wrong, never a panic.

use std::collections::HashMap;

/// Largest rank a field may have.
const MAX_RANK: usize = 8;

/// Largest number of fields.
const MAX_FIELDS: u32 = 256;

/// A field's element type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dtype {
    /// Unsigned and signed integers of 8, 16, 32, 64 bits.
    U8,
    /// Signed 8-bit.
    I8,
    /// Unsigned 16-bit.
    U16,
    /// Signed 16-bit.
    I16,
    /// Unsigned 32-bit.
    U32,
    /// Signed 32-bit.
    I32,
    /// Unsigned 64-bit.
    U64,
    /// Signed 64-bit.
    I64,
    /// IEEE half.
    F16,
    /// IEEE single.
    F32,
    /// IEEE double.
    F64,
}

impl Dtype {
    fn from_code(c: u8) -> Option<Dtype> {
        use Dtype::*;
        Some(match c {
            1 => U8,
            2 => I8,
            3 => U16,
            4 => I16,
            5 => U32,
            6 => I32,
            7 => U64,
            8 => I64,
            9 => F16,
            10 => F32,
            11 => F64,
            _ => return None,
        })
    }

    /// The code this type has in a file.
    pub fn code(self) -> u8 {
        self as u8 + 1
    }

    /// Bytes per element.
    pub fn size(self) -> usize {
        use Dtype::*;
        match self {
            U8 | I8 => 1,
            U16 | I16 | F16 => 2,
            U32 | I32 | F32 => 4,
            U64 | I64 | F64 => 8,
        }
    }
}

/// One field of a tensor file.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Element type.
    pub dtype: Dtype,
    /// Size along each dimension (the rank is its length).
    pub shape: Vec<usize>,
    /// The raw little-endian bytes.
    pub bytes: Vec<u8>,
}

impl Field {
    /// The elements as f32, for f32 and f64 fields (`None` for other types).
    pub fn to_f32(&self) -> Option<Vec<f32>> {
        match self.dtype {
            Dtype::F32 => Some(
                self.bytes
                    .chunks_exact(4)
                    .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
                    .collect(),
            ),
            Dtype::F64 => Some(
                self.bytes
                    .chunks_exact(8)
                    .map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0; 8])) as f32)
                    .collect(),
            ),
            _ => None,
        }
    }
}

/// A parsed tensor file: its fields by name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tensor {
    /// The fields.
    pub fields: HashMap<String, Field>,
}

/// A little-endian reader over the header, failing with what it was reading.
struct Cursor<'a> {
    b: &'a [u8],
    at: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize, what: &str) -> Result<&[u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.b.len());
        let Some(end) = end else {
            return Err(format!(
                "truncated: the file ends at byte {} while reading {what}",
                self.b.len()
            ));
        };
        let s = &self.b[self.at..end];
        self.at = end;
        Ok(s)
    }
    fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.take(1, what)?[0])
    }
    fn u16(&mut self, what: &str) -> Result<u16, String> {
        let b = self.take(2, what)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }
    fn u32(&mut self, what: &str) -> Result<u32, String> {
        let b = self.take(4, what)?;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self, what: &str) -> Result<u64, String> {
        let b = self.take(8, what)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
}

/// The magic bytes a tensor file starts with.
pub const MAGIC: &[u8; 12] = b"tensor_file\0";

impl Tensor {
    /// Parses a whole tensor file.
    pub fn parse(b: &[u8]) -> Result<Tensor, String> {
        let mut c = Cursor { b, at: 0 };
        if c.take(12, "the header")? != MAGIC {
            return Err("not a tensor file (it does not start with \"tensor_file\")".into());
        }
        let (major, minor) = (c.u8("the version")?, c.u8("the version")?);
        if (major, minor) != (1, 0) {
            return Err(format!(
                "tensor file version {major}.{minor}; only 1.0 is known"
            ));
        }
        let n = c.u32("the number of fields")?;
        if n > MAX_FIELDS {
            return Err(format!("{n} fields (at most {MAX_FIELDS} are read)"));
        }
        let mut fields = HashMap::new();
        for k in 0..n {
            let what = format!("field {k}'s header");
            let len = c.u16(&what)? as usize;
            let name = String::from_utf8_lossy(c.take(len, &what)?).into_owned();
            let what = format!("field \"{name}\"'s header");
            let rank = c.u16(&what)? as usize;
            let code = c.u8(&what)?;
            let dtype = Dtype::from_code(code)
                .ok_or_else(|| format!("field \"{name}\" has unknown type code {code}"))?;
            let offset = c.u64(&what)?;
            if rank > MAX_RANK {
                return Err(format!(
                    "field \"{name}\" has rank {rank} (at most {MAX_RANK})"
                ));
            }
            let mut shape = Vec::with_capacity(rank);
            let mut bytes = dtype.size() as u64;
            for _ in 0..rank {
                let s = c.u64(&what)?;
                bytes = bytes.saturating_mul(s);
                shape.push(s as usize);
            }
            if shape
                .iter()
                .try_fold(1usize, |a, &s| a.checked_mul(s))
                .is_none()
            {
                return Err(format!(
                    "field \"{name}\" has an impossible shape {shape:?}"
                ));
            }
            let end = offset.saturating_add(bytes);
            if end > b.len() as u64 {
                return Err(format!(
                    "field \"{name}\" (shape {shape:?}, {bytes} bytes at offset {offset}) \
                     runs past the end of the file ({} bytes)",
                    b.len()
                ));
            }
            let data = b[offset as usize..end as usize].to_vec();
            fields.insert(
                name,
                Field {
                    dtype,
                    shape,
                    bytes: data,
                },
            );
        }
        Ok(Tensor { fields })
    }

    /// Writes a tensor file of `fields` (in the given order): what [`Tensor::parse`] reads.
    pub fn write(fields: &[(&str, &Field)]) -> Vec<u8> {
        let mut out = MAGIC.to_vec();
        out.extend([1u8, 0]);
        out.extend((fields.len() as u32).to_le_bytes());
        let header: usize = fields
            .iter()
            .map(|(n, f)| 2 + n.len() + 2 + 1 + 8 + 8 * f.shape.len())
            .sum();
        let mut offset = (out.len() + header) as u64;
        for (name, f) in fields {
            out.extend((name.len() as u16).to_le_bytes());
            out.extend(name.as_bytes());
            out.extend((f.shape.len() as u16).to_le_bytes());
            out.push(f.dtype.code());
            out.extend(offset.to_le_bytes());
            for &s in &f.shape {
                out.extend((s as u64).to_le_bytes());
            }
            offset += f.bytes.len() as u64;
        }
        for (_, f) in fields {
            out.extend(&f.bytes);
        }
        out
    }
}

impl Field {
    /// An f32 field of `shape` holding `v`.
    pub fn f32(shape: &[usize], v: &[f32]) -> Field {
        Field {
            dtype: Dtype::F32,
            shape: shape.to_vec(),
            bytes: v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        }
    }

    /// A u8 field of `shape` holding `v`.
    pub fn u8(shape: &[usize], v: &[u8]) -> Field {
        Field {
            dtype: Dtype::U8,
            shape: shape.to_vec(),
            bytes: v.to_vec(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_come_back_as_written() {
        let a = Field::f32(&[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.5]);
        let d = Field::u8(&[5], b"hello");
        let bytes = Tensor::write(&[("a", &a), ("description", &d)]);
        // Header 12 + 2 + 4; field a's 2 + 1 + 2 + 1 + 8 + 2·8, description's 2 + 11 + 2 + 1 + 8
        // + 8; then 6 f32 and 5 bytes.
        assert_eq!(bytes.len(), 18 + 30 + 32 + 24 + 5);
        let t = Tensor::parse(&bytes).unwrap();
        assert_eq!(t.fields["a"], a);
        assert_eq!(
            t.fields["a"].to_f32().unwrap(),
            [1.0, 2.0, 3.0, 4.0, 5.0, 6.5]
        );
        assert_eq!(t.fields["description"].bytes, b"hello");
        assert_eq!(t.fields["description"].to_f32(), None);
    }

    #[test]
    fn bad_files_say_what_is_wrong() {
        let a = Field::f32(&[4], &[1.0, 2.0, 3.0, 4.0]);
        let good = Tensor::write(&[("a", &a)]);
        let err = |b: &[u8]| Tensor::parse(b).unwrap_err();
        assert_eq!(
            err(b"PK\x03\x04 not a tensor"),
            "not a tensor file (it does not start with \"tensor_file\")"
        );
        assert_eq!(
            err(b"tensor"),
            "truncated: the file ends at byte 6 while reading the header"
        );
        let mut v = good.clone();
        v[12] = 2;
        assert_eq!(err(&v), "tensor file version 2.0; only 1.0 is known");
        // Data cut short: the field runs past the end.
        assert_eq!(
            err(&good[..good.len() - 1]),
            format!(
                "field \"a\" (shape [4], 16 bytes at offset 40) runs past the end of the file ({} bytes)",
                good.len() - 1
            )
        );
        // Header cut inside the field's shape.
        assert_eq!(
            err(&good[..35]),
            "truncated: the file ends at byte 35 while reading field \"a\"'s header"
        );
        // An absurd shape does not allocate: its byte count overflows past the file.
        let mut v = good.clone();
        v[32..40].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(
            err(&v).contains("runs past the end of the file"),
            "{}",
            err(&v)
        );
        let mut v = good.clone();
        v[23] = 42;
        assert_eq!(err(&v), "field \"a\" has unknown type code 42");
    }
}
