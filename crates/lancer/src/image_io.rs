//! Writing images: PNG (sRGB, 8 bits) and OpenEXR (linear, 32-bit float), atomically.
//!
//! An image is encoded in memory first, written to a temporary file next to its destination,
//! flushed to disk and renamed over it: a reader (or a crash) sees either the old file or the
//! new one, never a truncated mix.

use crate::math::Rgb;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ImageWriteError {
    /// The extension names no format lancer writes.
    #[error("{path}: unknown image format (use .png or .exr)")]
    UnknownFormat {
        /// The path.
        path: PathBuf,
    },
    /// Encoding failed.
    #[error("{path}: cannot encode image: {message}")]
    Encode {
        /// The path.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// The file system refused.
    #[error("{path}: cannot write: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
}

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// 8-bit sRGB PNG.
    Png,
    /// Linear float OpenEXR.
    Exr,
}

impl ImageFormat {
    /// The format named by a path's extension.
    pub fn from_path(path: &Path) -> Option<ImageFormat> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "png" => Some(ImageFormat::Png),
            "exr" => Some(ImageFormat::Exr),
            _ => None,
        }
    }
}

/// The sRGB transfer function (linear → encoded), IEC 61966-2-1.
#[inline]
pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.0031308 {
        12.92 * v.max(0.0)
    } else {
        1.055 * v.min(1.0).powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse sRGB transfer function (encoded → linear).
#[inline]
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.04045 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Encodes pixels (row-major, row 0 at the top, linear RGB) as a PNG: clamped to [0, 1],
/// sRGB-encoded, rounded to 8 bits.
pub fn encode_png(width: u32, height: u32, pixels: &[Rgb]) -> Result<Vec<u8>, String> {
    let mut data = Vec::with_capacity(pixels.len() * 3);
    for p in pixels {
        for c in 0..3 {
            let v = if p[c].is_finite() { p[c] } else { 0.0 };
            data.push((linear_to_srgb(v) * 255.0 + 0.5).clamp(0.0, 255.0) as u8);
        }
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        let mut w = enc.write_header().map_err(|e| e.to_string())?;
        w.write_image_data(&data).map_err(|e| e.to_string())?;
    }
    Ok(out)
}

/// Encodes pixels as an OpenEXR file with 32-bit float R, G, B channels.
pub fn encode_exr(width: u32, height: u32, pixels: &[Rgb]) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    let w = width as usize;
    let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
        let c = pixels[p.y() * w + p.x()];
        (c.x, c.y, c.z)
    });
    let image = Image::from_channels((width as usize, height as usize), channels);
    let mut buf = std::io::Cursor::new(Vec::new());
    // Sequential: the parallel encoder writes chunks in the order they finish, so the bytes of
    // the file would depend on thread timing; a render must give the same file every time.
    image
        .write()
        .non_parallel()
        .to_buffered(&mut buf)
        .map_err(|e| e.to_string())?;
    Ok(buf.into_inner())
}

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, synced, then
/// renamed over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Encodes and writes an image, the format chosen by the extension, atomically.
pub fn write_image(
    path: &Path,
    width: u32,
    height: u32,
    pixels: &[Rgb],
) -> Result<(), ImageWriteError> {
    let format = ImageFormat::from_path(path).ok_or_else(|| ImageWriteError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let bytes = match format {
        ImageFormat::Png => encode_png(width, height, pixels),
        ImageFormat::Exr => encode_exr(width, height, pixels),
    }
    .map_err(|message| ImageWriteError::Encode {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomic(path, &bytes).map_err(|source| ImageWriteError::Io {
        path: path.to_path_buf(),
        source,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips() {
        for i in 0..=100 {
            let v = i as f32 / 100.0;
            assert!((srgb_to_linear(linear_to_srgb(v)) - v).abs() < 1e-5);
        }
    }

    #[test]
    fn png_and_exr_encode() {
        let px = vec![Rgb::new(0.2, 0.5, 1.5); 6];
        let png = encode_png(3, 2, &px).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        let exr = encode_exr(3, 2, &px).unwrap();
        assert_eq!(&exr[..4], &[0x76, 0x2f, 0x31, 0x01]);
        // Deterministic bytes, whatever the encoder's scheduling.
        let big: Vec<Rgb> = (0..256 * 256)
            .map(|i| Rgb::splat((i % 251) as f32))
            .collect();
        let first = encode_exr(256, 256, &big).unwrap();
        for _ in 0..4 {
            assert_eq!(encode_exr(256, 256, &big).unwrap(), first);
        }
    }
}
