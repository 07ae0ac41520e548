//! The data after the header, in either encoding, read value by value: [`Binary`] and
//! [`Ascii`] behind the one [`Body`] trait.

use super::header::{Element, Kind, Scalar};

/// Why reading a value failed: the data ended, or (ASCII) a word is not a number.
pub(super) enum ReadError {
    End,
    Bad(String),
}

impl ReadError {
    /// The message, naming record `i` of element `el`, which has `n` records.
    pub(super) fn describe(self, el: &str, i: u64, n: u64) -> String {
        match self {
            ReadError::End => {
                format!("the data ends inside {el} {i} of {n}: the file is truncated")
            }
            ReadError::Bad(m) => format!("{el} {i}: {m}"),
        }
    }
}

/// The data after the header, in one of the encodings.
pub(super) trait Body {
    /// A number of type `t`.
    fn float(&mut self, t: Scalar) -> Result<f64, ReadError>;
    /// A whole number of the integer type `t`.
    fn int(&mut self, t: Scalar) -> Result<i64, ReadError>;
    /// Skips `n` numbers of type `t`.
    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), ReadError>;
    /// Skips records of fixed size: `bytes` in binary, `words` in ASCII.
    fn skip_fixed(&mut self, bytes: u64, words: u64) -> Result<(), ReadError>;
}

pub(super) struct Binary<'a> {
    pub(super) data: &'a [u8],
    pub(super) pos: usize,
    pub(super) big: bool,
}

impl Binary<'_> {
    #[inline]
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], ReadError> {
        let b = self
            .data
            .get(self.pos..self.pos + N)
            .ok_or(ReadError::End)?;
        self.pos += N;
        let mut out = [0; N];
        out.copy_from_slice(b);
        Ok(out)
    }

    fn skip_bytes(&mut self, n: u64) -> Result<(), ReadError> {
        let left = (self.data.len() - self.pos) as u64;
        if n > left {
            return Err(ReadError::End);
        }
        self.pos += n as usize;
        Ok(())
    }
}

/// A number of type `$t` in the body's byte order.
macro_rules! binary_number {
    ($body:expr, $t:ty) => {{
        let b = $body.bytes::<{ std::mem::size_of::<$t>() }>()?;
        if $body.big {
            <$t>::from_be_bytes(b)
        } else {
            <$t>::from_le_bytes(b)
        }
    }};
}

impl Body for Binary<'_> {
    #[inline]
    fn float(&mut self, t: Scalar) -> Result<f64, ReadError> {
        Ok(match t {
            Scalar::F32 => f64::from(binary_number!(self, f32)),
            Scalar::F64 => binary_number!(self, f64),
            _ => self.int(t)? as f64,
        })
    }

    #[inline]
    fn int(&mut self, t: Scalar) -> Result<i64, ReadError> {
        Ok(match t {
            Scalar::I8 => i64::from(binary_number!(self, i8)),
            Scalar::U8 => i64::from(binary_number!(self, u8)),
            Scalar::I16 => i64::from(binary_number!(self, i16)),
            Scalar::U16 => i64::from(binary_number!(self, u16)),
            Scalar::I32 => i64::from(binary_number!(self, i32)),
            Scalar::U32 => i64::from(binary_number!(self, u32)),
            Scalar::F32 | Scalar::F64 => {
                let v = self.float(t)?;
                if v.fract() != 0.0 || !v.is_finite() || v.abs() > 1e18 {
                    return Err(ReadError::Bad(format!("{v} is not a whole number")));
                }
                v as i64
            }
        })
    }

    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), ReadError> {
        self.skip_bytes(n.saturating_mul(t.size() as u64))
    }

    fn skip_fixed(&mut self, bytes: u64, _words: u64) -> Result<(), ReadError> {
        self.skip_bytes(bytes)
    }
}

pub(super) struct Ascii<'a> {
    pub(super) data: &'a [u8],
    pub(super) pos: usize,
}

impl<'a> Ascii<'a> {
    /// The next whitespace-separated word.
    fn word(&mut self) -> Result<&'a [u8], ReadError> {
        let data = self.data;
        while self.pos < data.len() && data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if self.pos == data.len() {
            return Err(ReadError::End);
        }
        let start = self.pos;
        while self.pos < data.len() && !data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        Ok(&data[start..self.pos])
    }
}

pub(super) fn not_a_number(word: &[u8], what: &str) -> ReadError {
    ReadError::Bad(format!(
        "\"{}\" is not {what}",
        String::from_utf8_lossy(word)
    ))
}

impl Body for Ascii<'_> {
    fn float(&mut self, _t: Scalar) -> Result<f64, ReadError> {
        let w = self.word()?;
        std::str::from_utf8(w)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .ok_or_else(|| not_a_number(w, "a number"))
    }

    fn int(&mut self, _t: Scalar) -> Result<i64, ReadError> {
        let w = self.word()?;
        std::str::from_utf8(w)
            .ok()
            .and_then(|s| s.parse::<i64>().ok())
            .ok_or_else(|| not_a_number(w, "a whole number"))
    }

    fn skip(&mut self, _t: Scalar, n: u64) -> Result<(), ReadError> {
        for _ in 0..n {
            self.word()?;
        }
        Ok(())
    }

    fn skip_fixed(&mut self, _bytes: u64, words: u64) -> Result<(), ReadError> {
        self.skip(Scalar::F32, words)
    }
}

/// A list's length, which must not be negative.
pub(super) fn list_len<B: Body>(body: &mut B, count: Scalar) -> Result<u64, ReadError> {
    let n = body.int(count)?;
    u64::try_from(n).map_err(|_| ReadError::Bad(format!("a list has negative length {n}")))
}

/// Skips one property of one record.
pub(super) fn skip_property<B: Body>(body: &mut B, kind: Kind) -> Result<(), ReadError> {
    match kind {
        Kind::Scalar(t) => body.skip(t, 1),
        Kind::List { count, item } => {
            let n = list_len(body, count)?;
            body.skip(item, n)
        }
    }
}

pub(super) fn skip_element<B: Body>(body: &mut B, el: &Element) -> Result<(), String> {
    if el.props.is_empty() || el.count == 0 {
        return Ok(());
    }
    let scalars: Option<Vec<Scalar>> = el
        .props
        .iter()
        .map(|p| match p.kind {
            Kind::Scalar(t) => Some(t),
            Kind::List { .. } => None,
        })
        .collect();
    if let Some(scalars) = scalars {
        // Fixed-size records: skipped at once.
        let bytes: u64 = scalars.iter().map(|t| t.size() as u64).sum();
        let words = scalars.len() as u64;
        return body
            .skip_fixed(
                bytes.saturating_mul(el.count),
                words.saturating_mul(el.count),
            )
            .map_err(|e| e.describe(&el.name, 0, el.count));
    }
    for i in 0..el.count {
        for p in &el.props {
            skip_property(body, p.kind).map_err(|e| e.describe(&el.name, i, el.count))?;
        }
    }
    Ok(())
}
