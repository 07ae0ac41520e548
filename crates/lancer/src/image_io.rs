//! Writing images: PNG (sRGB, 8 bits) and OpenEXR (linear, 32-bit float), atomically; and
//! partial films ("parts" of a split render) as EXR files that keep the exact accumulators.
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
    encode_png_fn(width, height, |i| pixels[i])
}

/// [`encode_png`] of the pixels `pixel(i)` gives (row-major index `i`), read one by one.
fn encode_png_fn(width: u32, height: u32, pixel: impl Fn(usize) -> Rgb) -> Result<Vec<u8>, String> {
    let n = width as usize * height as usize;
    let mut data = Vec::with_capacity(n * 3);
    for p in (0..n).map(pixel) {
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
    let mut buf = std::io::Cursor::new(Vec::new());
    encode_exr_into(&mut buf, width, height, pixels)?;
    Ok(buf.into_inner())
}

/// [`encode_exr`] into a writer, so that a file can be written without holding its bytes.
pub fn encode_exr_into<W: Write + std::io::Seek>(
    out: &mut W,
    width: u32,
    height: u32,
    pixels: &[Rgb],
) -> Result<(), String> {
    encode_exr_into_fn(out, width, height, |i| pixels[i])
}

/// [`encode_exr_into`] of the pixels `pixel(i)` gives (row-major index `i`), read as the
/// encoder needs them: no image of the pixels is held besides the caller's own data.
fn encode_exr_into_fn<W: Write + std::io::Seek>(
    out: &mut W,
    width: u32,
    height: u32,
    pixel: impl Fn(usize) -> Rgb + Sync,
) -> Result<(), String> {
    use exr::prelude::*;
    let w = width as usize;
    let channels = SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
        let c = pixel(p.y() * w + p.x());
        (c.x, c.y, c.z)
    });
    let image = Image::from_channels((width as usize, height as usize), channels);
    // Sequential: the parallel encoder writes chunks in the order they finish, so the bytes of
    // the file would depend on thread timing; a render must give the same file every time.
    image
        .write()
        .non_parallel()
        .to_buffered(out)
        .map_err(|e| e.to_string())
}

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, synced, then
/// renamed over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Writes `path` atomically from `fill`, which writes the contents into a buffered temporary
/// file in the same folder; the file is synced, then renamed over `path`. On any error the
/// temporary file is removed and `path` is left as it was.
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> std::io::Result<()>,
) -> std::io::Result<()> {
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
        // Readable too, so that a writer may read back what it wrote (see `sort_exr_header`).
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(&tmp)?;
        let mut w = std::io::BufWriter::new(file);
        fill(&mut w)?;
        let f = w.into_inner().map_err(|e| e.into_error())?;
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
    write_image_fn(path, width, height, |i| pixels[i])
}

/// [`write_image`] of the pixels `pixel(i)` gives (row-major index `i`), computed as the
/// encoder reads them: a film is written without an image of it beside it in memory (a
/// small render's peak memory is its film plus that image).
pub fn write_image_fn(
    path: &Path,
    width: u32,
    height: u32,
    pixel: impl Fn(usize) -> Rgb + Sync,
) -> Result<(), ImageWriteError> {
    let format = ImageFormat::from_path(path).ok_or_else(|| ImageWriteError::UnknownFormat {
        path: path.to_path_buf(),
    })?;
    let encode_error = |message| ImageWriteError::Encode {
        path: path.to_path_buf(),
        message,
    };
    let io_error = |source| ImageWriteError::Io {
        path: path.to_path_buf(),
        source,
    };
    match format {
        ImageFormat::Png => {
            let bytes = encode_png_fn(width, height, pixel).map_err(encode_error)?;
            write_atomic(path, &bytes).map_err(io_error)
        }
        // Streamed into the temporary file: holding the encoded bytes as well as the pixels
        // raised the peak memory of a small render by a tenth.
        ImageFormat::Exr => {
            write_exr_streamed(path, |w| encode_exr_into_fn(w, width, height, pixel))
        }
    }
}

/// Writes an OpenEXR file to `path` atomically, `encode` streaming it into the temporary
/// file: an encoding error is [`ImageWriteError::Encode`], a file system one
/// [`ImageWriteError::Io`], both naming `path`.
fn write_exr_streamed(
    path: &Path,
    encode: impl FnOnce(&mut std::io::BufWriter<std::fs::File>) -> Result<(), String>,
) -> Result<(), ImageWriteError> {
    let mut failed = None;
    let written = write_atomic_with(path, |w| {
        encode(w).map_err(|message| {
            failed = Some(message);
            std::io::Error::other("EXR encoding failed")
        })
    });
    match (failed, written) {
        (Some(message), _) => Err(ImageWriteError::Encode {
            path: path.to_path_buf(),
            message,
        }),
        (None, written) => written.map_err(|source| ImageWriteError::Io {
            path: path.to_path_buf(),
            source,
        }),
    }
}

/// Where an EXR layer's pixels lie: a data window of `size` (width, height) pixels inside a
/// display window of `full` (width, height) pixels; the window's position is the layer
/// attributes' `layer_position`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LayerSize {
    /// Width and height of the data window.
    pub size: (usize, usize),
    /// Width and height of the full image.
    pub full: (u32, u32),
}

/// Writes one layer of a film's channels (see [`write_film_layer`]) to `path` atomically,
/// streamed into the temporary file. `film_kind` names the film in the error when `path` is
/// not an `.exr`: pbrt-v4 writes its spectral and g-buffer films only as OpenEXR.
pub fn write_film_exr(
    path: &Path,
    film_kind: &str,
    film: LayerSize,
    attributes: exr::prelude::LayerAttributes,
    channels: ExrChannels,
) -> Result<(), ImageWriteError> {
    if ImageFormat::from_path(path) != Some(ImageFormat::Exr) {
        return Err(ImageWriteError::Encode {
            path: path.to_path_buf(),
            message: format!("a {film_kind} film is written only as OpenEXR (.exr), as in pbrt-v4"),
        });
    }
    write_exr_streamed(path, |w| {
        write_film_layer(w, film, attributes, channels)?;
        w.flush().map_err(|e| e.to_string())?;
        sort_exr_header(w.get_mut()).map_err(|e| e.to_string())
    })
}

/// The channels of one EXR layer.
pub type ExrChannels =
    exr::prelude::SmallVec<[exr::prelude::AnyChannel<exr::prelude::FlatSamples>; 4]>;

/// The channel planes of an EXR layer filled pixel by pixel, each in half or 32-bit floats
/// from the start (a half-float image never has a 32-bit copy beside it).
pub struct Planes(Vec<exr::prelude::FlatSamples>);

impl Planes {
    /// `channels` empty planes with room for `pixels` values each.
    pub fn new(channels: usize, pixels: usize, fp16: bool) -> Planes {
        use exr::prelude::FlatSamples;
        let plane = || {
            if fp16 {
                FlatSamples::F16(Vec::with_capacity(pixels))
            } else {
                FlatSamples::F32(Vec::with_capacity(pixels))
            }
        };
        Planes((0..channels).map(|_| plane()).collect())
    }

    /// Appends `v` to channel `c`, rounded to the plane's type.
    #[inline]
    pub fn push(&mut self, c: usize, v: f32) {
        use exr::prelude::FlatSamples;
        match &mut self.0[c] {
            FlatSamples::F16(p) => p.push(exr::prelude::f16::from_f32(v)),
            FlatSamples::F32(p) => p.push(v),
            FlatSamples::U32(p) => p.push(v as u32),
        }
    }

    /// The planes as channels named `names`, in order.
    pub fn named<S: AsRef<str>>(self, names: &[S]) -> ExrChannels {
        names
            .iter()
            .zip(self.0)
            .map(|(n, s)| exr::prelude::AnyChannel::new(n.as_ref(), s))
            .collect()
    }
}

/// Encodes one EXR layer of `channels` over the window `film` in memory (see
/// [`write_film_layer`]).
pub fn encode_film_layer(
    film: LayerSize,
    attributes: exr::prelude::LayerAttributes,
    channels: ExrChannels,
) -> Result<Vec<u8>, String> {
    let mut buf = std::io::Cursor::new(Vec::new());
    write_film_layer(&mut buf, film, attributes, channels)?;
    sort_exr_header(&mut buf).map_err(|e| e.to_string())?;
    Ok(buf.into_inner())
}

/// Puts the attributes of a single-part OpenEXR file's header in name order, in place. The
/// exr crate writes custom attributes in the order of a hash map, which changes from one
/// process to the next: the same render gave files of different bytes. The header keeps its
/// length, so the chunk offsets after it stay right. Anything but a single-part header it
/// can read whole in its first 64 KiB is left as it is.
fn sort_exr_header<F: std::io::Read + Write + std::io::Seek>(f: &mut F) -> std::io::Result<()> {
    use std::io::{Read, SeekFrom};
    f.seek(SeekFrom::Start(0))?;
    let mut head = Vec::new();
    Read::by_ref(f).take(1 << 16).read_to_end(&mut head)?;
    // Magic number, then the version field; bit 12 marks a multi-part file.
    if head.len() < 8 || head[..4] != [0x76, 0x2f, 0x31, 0x01] || head[5] & 0x10 != 0 {
        return Ok(());
    }
    // Each attribute: name\0 type\0, a 4-byte little-endian size, the value; a lone \0 ends
    // the header.
    let zero_after = |i: usize| head[i..].iter().position(|&b| b == 0).map(|k| i + k);
    let mut attrs = Vec::new();
    let mut i = 8;
    loop {
        let Some(name_end) = zero_after(i) else {
            return Ok(());
        };
        if name_end == i {
            break;
        }
        let Some(type_end) = zero_after(name_end + 1) else {
            return Ok(());
        };
        let Some(size) = head.get(type_end + 1..type_end + 5) else {
            return Ok(());
        };
        let size = u32::from_le_bytes([size[0], size[1], size[2], size[3]]) as usize;
        let end = type_end + 5 + size;
        if end >= head.len() {
            return Ok(());
        }
        attrs.push((i, name_end, end));
        i = end;
    }
    let mut sorted = attrs.clone();
    sorted.sort_by(|a, b| head[a.0..a.1].cmp(&head[b.0..b.1]));
    if sorted == attrs {
        return Ok(());
    }
    let bytes: Vec<u8> = sorted
        .iter()
        .flat_map(|&(start, _, end)| head[start..end].iter().copied())
        .collect();
    f.seek(SeekFrom::Start(8))?;
    f.write_all(&bytes)?;
    f.seek(SeekFrom::End(0))?;
    Ok(())
}

/// Writes one EXR layer of `channels` over the window `film` (its data window), inside the
/// full image as display window, losslessly compressed, into `out`; the layer's attributes
/// are the caller's. OpenEXR keeps a file's channels sorted by name, so they are sorted here.
pub fn write_film_layer<W: Write + std::io::Seek>(
    out: &mut W,
    film: LayerSize,
    attributes: exr::prelude::LayerAttributes,
    channels: ExrChannels,
) -> Result<(), String> {
    use exr::prelude::*;
    let (w, h) = film.size;
    let layer = Layer::new(
        (w, h),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let mut image = Image::from_layer(layer);
    image.attributes.display_window =
        IntegerBounds::from_dimensions((film.full.0 as usize, film.full.1 as usize));
    image
        .write()
        .non_parallel()
        .to_buffered(out)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One header attribute's bytes: name\0 type\0 size value.
    fn attribute(name: &str, kind: &str, value: &[u8]) -> Vec<u8> {
        let mut b = Vec::new();
        for s in [name, kind] {
            b.extend_from_slice(s.as_bytes());
            b.push(0);
        }
        b.extend_from_slice(&(value.len() as u32).to_le_bytes());
        b.extend_from_slice(value);
        b
    }

    #[test]
    fn exr_header_attributes_are_put_in_name_order_in_place() {
        let file = |flags: u8, attrs: &[Vec<u8>]| {
            let mut b = vec![0x76, 0x2f, 0x31, 0x01, 2, flags, 0, 0];
            attrs.iter().for_each(|a| b.extend_from_slice(a));
            // End of header, then an offset table and data that must not move.
            b.extend_from_slice(&[0, 9, 8, 7, 6]);
            b
        };
        let z = attribute("zeta", "int", &7i32.to_le_bytes());
        let a = attribute("alpha", "string", b"x\0y");
        let m = attribute("mid", "float", &1.5f32.to_le_bytes());
        let mut c = std::io::Cursor::new(file(0, &[z.clone(), a.clone(), m.clone()]));
        sort_exr_header(&mut c).unwrap();
        assert_eq!(c.into_inner(), file(0, &[a.clone(), m.clone(), z.clone()]));
        // A multi-part file (version bit 12) is left alone.
        let multi = file(0x10, &[z.clone(), a.clone()]);
        let mut c = std::io::Cursor::new(multi.clone());
        sort_exr_header(&mut c).unwrap();
        assert_eq!(c.into_inner(), multi);
        // So is a header cut short (its end not within the bytes).
        let mut cut = file(0, &[z, a]);
        cut.truncate(20);
        let mut c = std::io::Cursor::new(cut.clone());
        sort_exr_header(&mut c).unwrap();
        assert_eq!(c.into_inner(), cut);
    }

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

    /// An EXR streamed into its file holds the bytes `encode_exr` gives, and leaves no
    /// temporary file beside it.
    #[test]
    fn streamed_exr_file_equals_encoded_bytes() {
        let dir = lancer_testing::ScratchDir::new("streamed-exr");
        let px: Vec<Rgb> = (0..40 * 30)
            .map(|i| Rgb::new(i as f32, 0.5, -1.0))
            .collect();
        let path = dir.join("a.exr");
        write_image(&path, 40, 30, &px).unwrap();
        assert_eq!(
            std::fs::read(&path).unwrap(),
            encode_exr(40, 30, &px).unwrap()
        );
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.exr")]);
    }
}
