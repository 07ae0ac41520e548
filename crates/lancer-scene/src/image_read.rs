//! Reading the images that textures and environment lights name: PNG (8 or 16 bits per
//! channel), JPEG, OpenEXR and PFM ([`pfm`]), decoded to linear RGB texels ([`Image`], row 0 at the top).
//!
//! What pbrt-v4 does, and so what lancer does:
//! - 8- and 16-bit PNG values go through the texture's `encoding` (sRGB by default for `.png`),
//!   alpha included: pbrt-v4 stores the PNG's channels with one encoding and decodes them all.
//! - JPEG is always sRGB (pbrt-v4 reads it through stb_image, which ignores `encoding`).
//! - OpenEXR holds linear values already; `encoding` does not apply. Channels `R`, `G`, `B`
//!   (and `A`) are used, or a lone `Y` (or any single channel) as grey. RGB in other primaries
//!   than sRGB's (a `chromaticities` attribute) is converted to linear sRGB, as a reflectance
//!   ([`lancer::spectrum::colorspace::chromaticities_to_srgb`]).
//! - A one-channel (grey) image gives the same value in R, G and B.
//!
//! The size a header claims is checked against [`MAX_SIDE`] and [`MAX_TEXELS`] before any
//! buffer is allocated, so a corrupt or hostile file cannot ask for gigabytes.

use lancer::image::Image;
use lancer::image_io::srgb_to_linear;
use lancer::math::PackedRgb;
use std::cell::RefCell;
use std::collections::HashMap;
use std::fmt;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::Arc;

mod pfm;

/// Largest width or height accepted.
pub const MAX_SIDE: u32 = 1 << 16;
/// Largest number of texels accepted (2²⁸: 3 GiB of linear RGB floats).
pub const MAX_TEXELS: u64 = 1 << 28;

/// Why an image could not be read; the message names the file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ImageReadError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl fmt::Display for ImageReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for ImageReadError {}

fn err(path: &Path, message: impl Into<String>) -> ImageReadError {
    ImageReadError {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// How stored 8- or 16-bit values map to linear ones (pbrt's `encoding`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Encoding {
    /// The sRGB curve: v ≤ 0.04045 ? v/12.92 : ((v + 0.055)/1.055)^2.4.
    Srgb,
    /// Values are linear already.
    Linear,
    /// A power law: linear = v^γ (`"gamma γ"`).
    Gamma(f32),
}

impl Encoding {
    /// pbrt-v4's names: `"sRGB"`, `"linear"` or `"gamma G"` with G positive.
    pub fn parse(s: &str) -> Option<Encoding> {
        match s {
            "sRGB" => Some(Encoding::Srgb),
            "linear" => Some(Encoding::Linear),
            _ => {
                let g: f32 = s.strip_prefix("gamma ")?.trim().parse().ok()?;
                (g.is_finite() && g > 0.0).then_some(Encoding::Gamma(g))
            }
        }
    }

    /// The linear value of an encoded value `v` in [0, 1].
    #[inline]
    pub fn to_linear(self, v: f32) -> f32 {
        match self {
            Encoding::Srgb => srgb_to_linear(v),
            Encoding::Linear => v,
            Encoding::Gamma(g) => v.powf(g),
        }
    }

    /// A key that can be hashed (the gamma's bits).
    fn key(self) -> (u8, u32) {
        match self {
            Encoding::Srgb => (0, 0),
            Encoding::Linear => (1, 0),
            Encoding::Gamma(g) => (2, g.to_bits()),
        }
    }
}

/// A decoded image: linear colour, and alpha when the file has one that is not 1 everywhere.
#[derive(Debug)]
pub struct DecodedImage {
    /// Linear RGB (a grey image has its value in all three channels).
    pub rgb: Arc<Image>,
    /// Alpha per texel, same order as the texels; `None` when absent or 1 everywhere.
    pub alpha: Option<Vec<f32>>,
    /// The matrix that took the file's own RGB (an EXR's `chromaticities`) to linear sRGB;
    /// `None` for sRGB files. A MIP pyramid clamps its resampled texels in the file's space,
    /// as pbrt-v4 does ([`lancer::texture::ImageTextureDesc::to_srgb`]).
    pub to_srgb: Option<lancer::math::Mat3>,
}

impl DecodedImage {
    /// The image a float texture looks up, the value in all three channels, chosen as pbrt-v4's
    /// `MIPMap` does: for bilinear filtering the alpha when there is one (not all 1), else the
    /// average of R, G and B (the grey value itself for a grey image); for point sampling the
    /// first channel (R, or grey).
    pub fn float_image(&self, nearest: bool) -> Image {
        let rgb = &self.rgb;
        let texels = match (&self.alpha, nearest) {
            (Some(a), false) => a.iter().map(|&v| PackedRgb::splat(v)).collect(),
            (_, true) => rgb.texels.iter().map(|c| PackedRgb::splat(c.x)).collect(),
            (None, false) => rgb
                .texels
                .iter()
                .map(|c| PackedRgb::splat((c.x + c.y + c.z) / 3.0))
                .collect(),
        };
        Image::new(rgb.width, rgb.height, texels).expect("same size as the decoded image")
    }
}

/// Refuses sizes that are empty or absurd before anything is allocated for them.
fn check_size(path: &Path, width: u64, height: u64) -> Result<(u32, u32), ImageReadError> {
    if width == 0 || height == 0 {
        return Err(err(path, format!("the image is empty ({width}×{height})")));
    }
    if width > MAX_SIDE as u64 || height > MAX_SIDE as u64 || width * height > MAX_TEXELS {
        return Err(err(
            path,
            format!(
                "the header claims {width}×{height} texels, more than lancer accepts (at most {MAX_SIDE} a side and {MAX_TEXELS} in all)"
            ),
        ));
    }
    Ok((width as u32, height as u32))
}

/// The image formats lancer reads.
#[derive(Clone, Copy)]
enum Format {
    Png,
    Jpeg,
    Exr,
    Pfm,
}

/// The format named by `path`'s extension.
fn format_of(path: &Path) -> Result<Format, ImageReadError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("png") => Ok(Format::Png),
        Some("jpg") | Some("jpeg") => Ok(Format::Jpeg),
        Some("exr") => Ok(Format::Exr),
        Some("pfm") => Ok(Format::Pfm),
        _ => Err(err(
            path,
            "unknown image format (lancer reads .png, .jpg, .jpeg, .exr and .pfm)",
        )),
    }
}

/// Reads an image file, its format chosen by the extension (`.png`, `.jpg`/`.jpeg`, `.exr`,
/// `.pfm`);
/// `encoding` applies to PNG only (see the module's notes).
pub fn read_image(path: &Path, encoding: Encoding) -> Result<DecodedImage, ImageReadError> {
    let format = format_of(path)?;
    crate::files_read::record(path);
    let bytes = std::fs::read(path).map_err(|e| err(path, format!("cannot read: {e}")))?;
    decode(path, &bytes, format, encoding)
}

/// Decodes an image held in memory (a glTF file's embedded image, a fuzzer's input), its
/// format told by its first bytes (PNG, JPEG, OpenEXR or PFM signature), else by `name`'s extension;
/// `name` names it in messages and `encoding` applies to PNG only, as in [`read_image`].
pub fn decode_image(
    name: &Path,
    bytes: &[u8],
    encoding: Encoding,
) -> Result<DecodedImage, ImageReadError> {
    let format = if bytes.starts_with(&[0x89, b'P', b'N', b'G']) {
        Format::Png
    } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        Format::Jpeg
    } else if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
        Format::Exr
    } else if pfm::is_pfm(bytes) {
        Format::Pfm
    } else {
        format_of(name)?
    };
    decode(name, bytes, format, encoding)
}

fn decode(
    path: &Path,
    bytes: &[u8],
    format: Format,
    encoding: Encoding,
) -> Result<DecodedImage, ImageReadError> {
    let mut to_srgb = None;
    let (width, height, texels, alpha) = match format {
        Format::Png => read_png(path, bytes, encoding)?,
        Format::Jpeg => read_jpeg(path, bytes)?,
        Format::Exr => {
            let (decoded, m) = read_exr(path, bytes)?;
            to_srgb = m;
            decoded
        }
        Format::Pfm => pfm::read_pfm(path, bytes)?,
    };
    let alpha = alpha.filter(|a| a.iter().any(|&v| v != 1.0));
    let rgb =
        Image::new(width, height, texels).ok_or_else(|| err(path, "decoded size mismatch"))?;
    Ok(DecodedImage {
        rgb: Arc::new(rgb),
        alpha,
        to_srgb,
    })
}

type Decoded = (u32, u32, Vec<PackedRgb>, Option<Vec<f32>>);

/// Width and height from a PNG's IHDR chunk, which the format puts first.
fn png_header_size(path: &Path, bytes: &[u8]) -> Result<(u32, u32), ImageReadError> {
    const SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    if bytes.len() < 24 || bytes[..8] != SIGNATURE || &bytes[12..16] != b"IHDR" {
        return Err(err(path, "not a PNG file (no PNG signature and header)"));
    }
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    check_size(path, be(16) as u64, be(20) as u64)
}

fn read_png(path: &Path, bytes: &[u8], encoding: Encoding) -> Result<Decoded, ImageReadError> {
    let (width, height) = png_header_size(path, bytes)?;
    // Enough for the largest accepted image at 16 bits × 4 channels.
    let limits = png::Limits {
        bytes: (width as usize * height as usize * 8).max(1 << 20) + (1 << 20),
    };
    let mut decoder = png::Decoder::new_with_limits(Cursor::new(bytes), limits);
    // Palettes and low bit depths become 8-bit grey or RGB; transparency becomes alpha.
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder
        .read_info()
        .map_err(|e| err(path, format!("bad PNG: {e}")))?;
    let size = reader
        .output_buffer_size()
        .ok_or_else(|| err(path, "PNG too large"))?;
    let mut buf = vec![0u8; size];
    let info = reader
        .next_frame(&mut buf)
        .map_err(|e| err(path, format!("bad PNG: {e}")))?;
    let (w, h) = (info.width, info.height);
    let channels = match info.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => return Err(err(path, "palette PNG was not expanded")),
    };
    let n = w as usize * h as usize;
    let samples: Vec<f32> = match info.bit_depth {
        png::BitDepth::Eight => {
            let lut: Vec<f32> = (0..256)
                .map(|v| encoding.to_linear(v as f32 / 255.0))
                .collect();
            buf[..n * channels]
                .iter()
                .map(|&v| lut[v as usize])
                .collect()
        }
        png::BitDepth::Sixteen => buf[..n * channels * 2]
            .chunks_exact(2)
            .map(|b| encoding.to_linear(u16::from_be_bytes([b[0], b[1]]) as f32 / 65535.0))
            .collect(),
        d => return Err(err(path, format!("unexpected PNG bit depth {d:?}"))),
    };
    Ok(split_channels(w, h, channels, &samples))
}

/// Interleaved samples (grey, grey+alpha, RGB or RGBA) to colour and alpha.
fn split_channels(w: u32, h: u32, channels: usize, samples: &[f32]) -> Decoded {
    let px = samples.chunks_exact(channels);
    let rgb = px
        .clone()
        .map(|s| match channels {
            1 | 2 => PackedRgb::splat(s[0]),
            _ => PackedRgb::new(s[0], s[1], s[2]),
        })
        .collect();
    let alpha = matches!(channels, 2 | 4).then(|| px.map(|s| s[channels - 1]).collect());
    (w, h, rgb, alpha)
}

fn read_jpeg(path: &Path, bytes: &[u8]) -> Result<Decoded, ImageReadError> {
    use zune_jpeg::zune_core::bytestream::ZCursor;
    use zune_jpeg::zune_core::colorspace::ColorSpace;
    use zune_jpeg::zune_core::options::DecoderOptions;
    let options = DecoderOptions::default()
        .set_max_width(MAX_SIDE as usize)
        .set_max_height(MAX_SIDE as usize)
        .jpeg_set_out_colorspace(ColorSpace::RGB);
    let mut decoder = zune_jpeg::JpegDecoder::new_with_options(ZCursor::new(bytes), options);
    decoder
        .decode_headers()
        .map_err(|e| err(path, format!("bad JPEG: {e:?}")))?;
    let info = decoder
        .info()
        .ok_or_else(|| err(path, "bad JPEG: no header"))?;
    let (width, height) = check_size(path, info.width as u64, info.height as u64)?;
    let data = decoder
        .decode()
        .map_err(|e| err(path, format!("bad JPEG: {e:?}")))?;
    let n = width as usize * height as usize;
    if data.len() < 3 * n {
        return Err(err(path, "bad JPEG: fewer pixels than its header says"));
    }
    let lut: Vec<f32> = (0..256).map(|v| srgb_to_linear(v as f32 / 255.0)).collect();
    let samples: Vec<f32> = data[..3 * n].iter().map(|&v| lut[v as usize]).collect();
    Ok(split_channels(width, height, 3, &samples))
}

fn read_exr(
    path: &Path,
    bytes: &[u8],
) -> Result<(Decoded, Option<lancer::math::Mat3>), ImageReadError> {
    use exr::prelude::{ReadChannels, ReadLayers, read};
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| err(path, format!("bad OpenEXR header: {e}")))?;
    let Some(header) = meta.headers.first() else {
        return Err(err(path, "OpenEXR file without a layer"));
    };
    for h in &meta.headers {
        check_size(path, h.layer_size.0 as u64, h.layer_size.1 as u64)?;
    }
    if header.deep {
        return Err(err(path, "deep OpenEXR images are not supported"));
    }
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| err(path, format!("bad OpenEXR: {e}")))?;
    let layer = image.layer_data;
    let (w, h) = (layer.size.0, layer.size.1);
    let (width, height) = check_size(path, w as u64, h as u64)?;
    let list = &layer.channel_data.list;
    let find = |name: &str| list.iter().position(|c| c.name.eq(name));
    let (colour, alpha): (Vec<usize>, Option<usize>) =
        match (find("R"), find("G"), find("B"), find("Y")) {
            (Some(r), Some(g), Some(b), _) => (vec![r, g, b], find("A")),
            (_, _, _, Some(y)) => (vec![y], find("A")),
            _ if list.len() == 1 => (vec![0], None),
            _ => {
                let names: Vec<String> = list.iter().map(|c| c.name.to_string()).collect();
                return Err(err(
                    path,
                    format!(
                        "OpenEXR image has no R, G, B or Y channels (it has {})",
                        names.join(", ")
                    ),
                ));
            }
        };
    let n = w * h;
    let channel = |i: usize| -> std::result::Result<Vec<f32>, ImageReadError> {
        let v: Vec<f32> = list[i].sample_data.values_as_f32().collect();
        if v.len() == n {
            Ok(v)
        } else {
            Err(err(path, "OpenEXR channel of the wrong size"))
        }
    };
    let planes: Vec<Vec<f32>> = colour
        .iter()
        .map(|&i| channel(i))
        .collect::<std::result::Result<_, _>>()?;
    // pbrt-v4 takes an image's colour space from its `chromaticities` attribute (sRGB without
    // one); lancer converts such texels to linear sRGB once, here.
    let to_srgb = image
        .attributes
        .chromaticities
        .and_then(|c| {
            let xy = |v: exr::math::Vec2<f32>| [v.0 as f64, v.1 as f64];
            lancer::spectrum::colorspace::chromaticities_to_srgb(
                [xy(c.red), xy(c.green), xy(c.blue)],
                xy(c.white),
            )
        })
        .filter(|_| planes.len() == 3);
    let rgb = (0..n)
        .map(|k| match planes.len() {
            1 => PackedRgb::splat(planes[0][k]),
            _ => {
                let c = PackedRgb::new(planes[0][k], planes[1][k], planes[2][k]);
                match &to_srgb {
                    Some(m) => *m * c,
                    None => c,
                }
            }
        })
        .collect();
    let alpha = alpha.map(channel).transpose()?;
    Ok(((width, height, rgb, alpha), to_srgb))
}

/// Images decoded during one scene load, by file and encoding, so that a file many textures
/// name is decoded once (and its float version made once per filter): the textures share its
/// texels, and the scene build makes one MIP pyramid per distinct image and settings.
#[derive(Default)]
pub struct ImageCache {
    entries: RefCell<HashMap<CacheKey, CacheEntry>>,
}

/// A file and its encoding's key.
type CacheKey = (PathBuf, (u8, u32));

struct CacheEntry {
    decoded: Arc<DecodedImage>,
    /// Float images: [bilinear, point].
    floats: [Option<Arc<Image>>; 2],
}

impl ImageCache {
    /// The decoded image of `path`, read on first use.
    pub fn decoded(
        &self,
        path: &Path,
        encoding: Encoding,
    ) -> Result<Arc<DecodedImage>, ImageReadError> {
        let key = (path.to_path_buf(), encoding.key());
        if let Some(e) = self.entries.borrow().get(&key) {
            return Ok(e.decoded.clone());
        }
        let decoded = Arc::new(read_image(path, encoding)?);
        self.entries.borrow_mut().insert(
            key,
            CacheEntry {
                decoded: decoded.clone(),
                floats: [None, None],
            },
        );
        Ok(decoded)
    }

    /// The linear RGB image of `path`.
    pub fn rgb(&self, path: &Path, encoding: Encoding) -> Result<Arc<Image>, ImageReadError> {
        Ok(self.decoded(path, encoding)?.rgb.clone())
    }

    /// The float-texture image of `path` (see [`DecodedImage::float_image`]).
    pub fn float(
        &self,
        path: &Path,
        encoding: Encoding,
        nearest: bool,
    ) -> Result<Arc<Image>, ImageReadError> {
        let decoded = self.decoded(path, encoding)?;
        let key = (path.to_path_buf(), encoding.key());
        let mut entries = self.entries.borrow_mut();
        let entry = entries.get_mut(&key).expect("just decoded");
        let slot = &mut entry.floats[nearest as usize];
        Ok(slot
            .get_or_insert_with(|| Arc::new(decoded.float_image(nearest)))
            .clone())
    }

    /// How many distinct files (and encodings) were decoded.
    pub fn len(&self) -> usize {
        self.entries.borrow().len()
    }

    /// True before any image is read.
    pub fn is_empty(&self) -> bool {
        self.entries.borrow().is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lancer_testing::ScratchDir;

    /// Writes a PNG of `w × h` texels with the given colour type, depth and raw samples.
    fn write_png(
        path: &Path,
        w: u32,
        h: u32,
        color: png::ColorType,
        depth: png::BitDepth,
        data: &[u8],
    ) {
        let file = std::fs::File::create(path).unwrap();
        let mut enc = png::Encoder::new(std::io::BufWriter::new(file), w, h);
        enc.set_color(color);
        enc.set_depth(depth);
        enc.write_header().unwrap().write_image_data(data).unwrap();
    }

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6 * b.abs().max(1.0)
    }

    #[test]
    fn png_8_bit_goes_through_its_encoding() {
        let dir = ScratchDir::new("imgread-png8");
        let path = dir.join("t.png");
        // 2×1: (0, 128, 255) then (64, 32, 200).
        let data = [0u8, 128, 255, 64, 32, 200];
        write_png(
            &path,
            2,
            1,
            png::ColorType::Rgb,
            png::BitDepth::Eight,
            &data,
        );
        let srgb = read_image(&path, Encoding::Srgb).unwrap();
        assert_eq!((srgb.rgb.width, srgb.rgb.height), (2, 1));
        let t = &srgb.rgb.texels;
        assert_eq!(t[0].x, 0.0);
        // sRGB 128/255 is 0.21586 linear, far from the 0.502 a linear read would give.
        assert!(close(t[0].y, 0.215_860_5), "{}", t[0].y);
        assert!(close(t[0].z, 1.0));
        assert!(close(t[1].x, srgb_to_linear(64.0 / 255.0)));
        assert!(srgb.alpha.is_none());

        let lin = read_image(&path, Encoding::Linear).unwrap();
        assert!(close(lin.rgb.texels[0].y, 128.0 / 255.0));
        assert!(close(lin.rgb.texels[1].z, 200.0 / 255.0));

        let gamma = read_image(&path, Encoding::parse("gamma 2.2").unwrap()).unwrap();
        assert!(close(gamma.rgb.texels[0].y, (128.0f32 / 255.0).powf(2.2)));
    }

    #[test]
    fn png_16_bit_grey_and_alpha() {
        let dir = ScratchDir::new("imgread-png16");
        let path = dir.join("g.png");
        // 2×1 grey + alpha, 16 bits big-endian: (32768, 65535) then (65535, 16384).
        let data = [0x80u8, 0x00, 0xff, 0xff, 0xff, 0xff, 0x40, 0x00];
        write_png(
            &path,
            2,
            1,
            png::ColorType::GrayscaleAlpha,
            png::BitDepth::Sixteen,
            &data,
        );
        let lin = read_image(&path, Encoding::Linear).unwrap();
        let v = 32768.0 / 65535.0;
        assert!(close(lin.rgb.texels[0].x, v) && close(lin.rgb.texels[0].z, v));
        assert!(close(lin.rgb.texels[1].y, 1.0));
        let alpha = lin.alpha.as_ref().expect("alpha below 1 is kept");
        assert!(close(alpha[0], 1.0) && close(alpha[1], 16384.0 / 65535.0));
        // Float textures read alpha when bilinear (pbrt-v4's MIPMap), the first channel when
        // point-sampled.
        assert!(close(lin.float_image(false).texels[1].x, 16384.0 / 65535.0));
        assert!(close(lin.float_image(true).texels[0].x, v));
        // 16-bit PNGs are sRGB-decoded by default too, like pbrt-v4.
        let srgb = read_image(&path, Encoding::Srgb).unwrap();
        assert!(close(srgb.rgb.texels[0].x, srgb_to_linear(v)));
    }

    #[test]
    fn opaque_alpha_is_dropped_and_float_is_the_average() {
        let dir = ScratchDir::new("imgread-rgba");
        let path = dir.join("a.png");
        let data = [255u8, 0, 0, 255, 0, 0, 255, 255];
        write_png(
            &path,
            2,
            1,
            png::ColorType::Rgba,
            png::BitDepth::Eight,
            &data,
        );
        let d = read_image(&path, Encoding::Linear).unwrap();
        assert!(d.alpha.is_none());
        let f = d.float_image(false);
        assert!(close(f.texels[0].x, 1.0 / 3.0) && close(f.texels[1].y, 1.0 / 3.0));
        assert!(close(d.float_image(true).texels[1].x, 0.0));
    }

    #[test]
    fn exr_float_values_are_read_as_they_are() {
        let dir = ScratchDir::new("imgread-exr");
        let path = dir.join("e.exr");
        let values = [(2.5f32, 0.125f32, 1000.0f32), (0.0, 7.0, 0.001)];
        exr::prelude::write_rgb_file(&path, 2, 1, |x, _| values[x]).unwrap();
        // The encoding does not apply to EXR.
        let d = read_image(&path, Encoding::Srgb).unwrap();
        assert_eq!((d.rgb.width, d.rgb.height), (2, 1));
        for (t, v) in d.rgb.texels.iter().zip(values) {
            assert_eq!((t.x, t.y, t.z), v);
        }
        assert!(d.alpha.is_none());

        let path = dir.join("a.exr");
        exr::prelude::write_rgba_file(&path, 1, 2, |_, y| (1.0f32, 2.0f32, 3.0f32, y as f32))
            .unwrap();
        let d = read_image(&path, Encoding::Linear).unwrap();
        assert_eq!(d.alpha.as_deref(), Some(&[0.0f32, 1.0][..]));
        // Row 0 is the top: the first texel is y = 0.
        assert_eq!(d.float_image(false).texels[0].x, 0.0);
    }

    #[test]
    fn absurd_headers_are_refused_before_allocating() {
        let dir = ScratchDir::new("imgread-absurd");
        let path = dir.join("huge.png");
        // A PNG signature and an IHDR that claims 100000 × 100000 texels, and nothing else.
        let mut b = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a, 0, 0, 0, 13];
        b.extend_from_slice(b"IHDR");
        b.extend_from_slice(&100_000u32.to_be_bytes());
        b.extend_from_slice(&100_000u32.to_be_bytes());
        b.extend_from_slice(&[8, 2, 0, 0, 0, 0, 0, 0, 0]);
        std::fs::write(&path, &b).unwrap();
        let e = read_image(&path, Encoding::Srgb).unwrap_err();
        assert_eq!(e.path, path);
        assert!(e.to_string().contains("100000×100000"), "{e}");
        // Sides within the limit but too many texels in all.
        b[16..20].copy_from_slice(&65536u32.to_be_bytes());
        b[20..24].copy_from_slice(&65536u32.to_be_bytes());
        std::fs::write(&path, &b).unwrap();
        let e = read_image(&path, Encoding::Srgb).unwrap_err();
        assert!(e.message.contains("more than lancer accepts"), "{e}");
        // Zero-sized.
        b[16..20].copy_from_slice(&0u32.to_be_bytes());
        std::fs::write(&path, &b).unwrap();
        assert!(read_image(&path, Encoding::Srgb).is_err());
    }

    #[test]
    fn bad_files_give_errors_naming_them() {
        let dir = ScratchDir::new("imgread-bad");
        let missing = dir.join("nowhere.png");
        let e = read_image(&missing, Encoding::Srgb).unwrap_err();
        assert!(
            e.to_string().contains(&missing.display().to_string()),
            "{e}"
        );
        let jpg = dir.join("junk.jpg");
        std::fs::write(&jpg, b"this is not a JPEG").unwrap();
        let e = read_image(&jpg, Encoding::Srgb).unwrap_err();
        assert!(e.to_string().starts_with(&jpg.display().to_string()), "{e}");
        assert!(e.message.contains("JPEG"), "{e}");
        let exr = dir.join("junk.exr");
        std::fs::write(&exr, [0u8; 64]).unwrap();
        assert!(read_image(&exr, Encoding::Linear).unwrap_err().path == exr);
        let tga = dir.join("a.tga");
        std::fs::write(&tga, [0u8; 4]).unwrap();
        assert!(
            read_image(&tga, Encoding::Linear)
                .unwrap_err()
                .message
                .contains("unknown image format")
        );
        // A truncated PNG: the header is fine, the data is missing.
        let png = dir.join("cut.png");
        write_png(
            &png,
            4,
            4,
            png::ColorType::Rgb,
            png::BitDepth::Eight,
            &[7u8; 48],
        );
        let bytes = std::fs::read(&png).unwrap();
        std::fs::write(&png, &bytes[..bytes.len() - 20]).unwrap();
        assert!(read_image(&png, Encoding::Srgb).unwrap_err().path == png);
    }

    #[test]
    fn encodings_parse_as_pbrt_names_them() {
        assert_eq!(Encoding::parse("sRGB"), Some(Encoding::Srgb));
        assert_eq!(Encoding::parse("linear"), Some(Encoding::Linear));
        assert_eq!(Encoding::parse("gamma 2.2"), Some(Encoding::Gamma(2.2)));
        assert_eq!(Encoding::parse("gamma -1"), None);
        assert_eq!(Encoding::parse("srgb"), None);
    }

    #[test]
    fn the_cache_decodes_a_file_once() {
        let dir = ScratchDir::new("imgread-cache");
        let path = dir.join("c.png");
        write_png(
            &path,
            1,
            1,
            png::ColorType::Rgb,
            png::BitDepth::Eight,
            &[1, 2, 3],
        );
        let cache = ImageCache::default();
        let a = cache.rgb(&path, Encoding::Srgb).unwrap();
        let b = cache.rgb(&path, Encoding::Srgb).unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        let f1 = cache.float(&path, Encoding::Srgb, false).unwrap();
        let f2 = cache.float(&path, Encoding::Srgb, false).unwrap();
        assert!(Arc::ptr_eq(&f1, &f2));
        assert_eq!(cache.len(), 1);
        // A different encoding is a different decode.
        let c = cache.rgb(&path, Encoding::Linear).unwrap();
        assert!(!Arc::ptr_eq(&a, &c));
        assert_eq!(cache.len(), 2);
    }
}
