//! Portable Float Map (`.pfm`), as pbrt-v4's `ReadPFM` reads it: a text header `PF` (RGB) or
//! `Pf` (grey), the width and the height, then a scale whose sign gives the byte order of the
//! data (negative: little-endian) and whose magnitude multiplies every value when it is not 1;
//! one whitespace byte; then 32-bit floats, rows from the bottom of the image to its top.

use super::{Decoded, ImageReadError, check_size, err, split_channels};
use std::path::Path;

/// True when `bytes` start like a PFM file (`PF` or `Pf`, then whitespace).
pub(super) fn is_pfm(bytes: &[u8]) -> bool {
    matches!(bytes, [b'P', b'F' | b'f', c, ..] if c.is_ascii_whitespace())
}

/// The next whitespace-separated word of the header at `*pos`, and `*pos` after it.
fn word<'a>(bytes: &'a [u8], pos: &mut usize) -> Option<&'a str> {
    while bytes.get(*pos).is_some_and(u8::is_ascii_whitespace) {
        *pos += 1;
    }
    let start = *pos;
    // A header word is short: a bound keeps a file of garbage from being scanned whole.
    while *pos < bytes.len() && *pos - start < 64 && !bytes[*pos].is_ascii_whitespace() {
        *pos += 1;
    }
    std::str::from_utf8(&bytes[start..*pos])
        .ok()
        .filter(|w| !w.is_empty())
}

/// Decodes a PFM file held in `bytes`; `path` names it in messages.
pub(super) fn read_pfm(path: &Path, bytes: &[u8]) -> Result<Decoded, ImageReadError> {
    let mut pos = 0;
    let channels = match word(bytes, &mut pos) {
        Some("PF") => 3,
        Some("Pf") => 1,
        _ => return Err(err(path, "not a PFM file (it must start with PF or Pf)")),
    };
    let mut number = |what: &str| {
        word(bytes, &mut pos).ok_or_else(|| err(path, format!("PFM header: the {what} is missing")))
    };
    let (w, h) = (number("width")?, number("height")?);
    let dims = w.parse::<u64>().ok().zip(h.parse::<u64>().ok());
    let Some((w, h)) = dims else {
        return Err(err(path, format!("PFM header: bad size \"{w} {h}\"")));
    };
    let scale_word = number("scale")?;
    let scale = scale_word
        .parse::<f32>()
        .ok()
        .filter(|s| s.is_finite() && *s != 0.0)
        .ok_or_else(|| err(path, format!("PFM header: bad scale \"{scale_word}\"")))?;
    let (width, height) = check_size(path, w, h)?;
    // One whitespace byte ends the header.
    let data = bytes.get(pos + 1..).unwrap_or_default();
    let row = width as usize * channels;
    let needed = row * height as usize * 4;
    if data.len() < needed {
        return Err(err(
            path,
            format!(
                "PFM data too short: {width}×{height}×{channels} floats need {needed} bytes, \
                 the file has {}",
                data.len()
            ),
        ));
    }
    let little = scale < 0.0;
    let magnitude = scale.abs();
    let value = |b: &[u8]| {
        let b = [b[0], b[1], b[2], b[3]];
        let v = if little {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        };
        if magnitude != 1.0 { v * magnitude } else { v }
    };
    // The file's first row is the image's bottom one: rows are taken in reverse.
    let samples: Vec<f32> = data[..needed]
        .chunks_exact(row * 4)
        .rev()
        .flat_map(|r| r.chunks_exact(4).map(value))
        .collect();
    Ok(split_channels(width, height, channels, &samples))
}

#[cfg(test)]
mod tests {
    use super::*;
    use lancer::math::PackedRgb;

    fn pfm(header: &str, values: &[f32], little: bool) -> Vec<u8> {
        let mut out = header.as_bytes().to_vec();
        for v in values {
            out.extend_from_slice(&if little {
                v.to_le_bytes()
            } else {
                v.to_be_bytes()
            });
        }
        out
    }

    #[test]
    fn rgb_little_endian_rows_bottom_to_top() {
        // 2×2: the file's first row (1, 2) is the image's bottom row.
        let values = [1.0, 1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 0.5, 0.25, 4.0, 4.0, 4.0];
        let bytes = pfm("PF\n2 2\n-1.0\n", &values, true);
        assert!(is_pfm(&bytes));
        let (w, h, rgb, alpha) = read_pfm(Path::new("a.pfm"), &bytes).unwrap();
        assert_eq!((w, h), (2, 2));
        assert!(alpha.is_none());
        assert_eq!(
            rgb,
            [
                PackedRgb::new(3.0, 0.5, 0.25),
                PackedRgb::splat(4.0),
                PackedRgb::splat(1.0),
                PackedRgb::splat(2.0),
            ]
        );
    }

    #[test]
    fn grey_big_endian_with_a_scale() {
        // Scale 2 (positive: big-endian) multiplies every value.
        let bytes = pfm("Pf 3 1 2.0\n", &[0.5, 1.0, 1.5], false);
        let (w, h, rgb, _) = read_pfm(Path::new("g.pfm"), &bytes).unwrap();
        assert_eq!((w, h), (3, 1));
        assert_eq!(
            rgb,
            [
                PackedRgb::splat(1.0),
                PackedRgb::splat(2.0),
                PackedRgb::splat(3.0)
            ]
        );
    }

    #[test]
    fn bad_headers_and_short_data_are_errors_before_allocating() {
        let e = |bytes: &[u8]| read_pfm(Path::new("b.pfm"), bytes).unwrap_err().to_string();
        assert!(e(b"P6\n1 1\n255\n").contains("must start with PF or Pf"));
        assert!(e(b"PF\n1 x\n-1\n").contains("bad size \"1 x\""));
        assert!(e(b"PF\n1 1\n").contains("the scale is missing"));
        assert!(e(b"PF\n1 1\nnan\n").contains("bad scale \"nan\""));
        // A header claiming 4 billion texels is refused by size, with no buffer made for it.
        assert!(e(b"PF\n65536 65536\n-1\n").contains("more than lancer accepts"));
        assert!(e(b"PF\n0 1\n-1\n").contains("empty"));
        let short = pfm("PF\n2 1\n-1\n", &[1.0, 2.0, 3.0], true);
        assert_eq!(
            e(&short),
            "b.pfm: PFM data too short: 2×1×3 floats need 24 bytes, the file has 12"
        );
        assert!(!is_pfm(b"PFX"));
    }
}
