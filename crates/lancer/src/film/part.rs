//! Parts of a split render (and the film of a checkpointed one) as OpenEXR files that keep
//! the exact accumulators: a part written by one process and read by another gives back the
//! very integers, so parts merge into the image a single process would have written.

use super::gsums::{GPixel, GbufferConfig, GbufferFilm};
use super::splat::SplatPlane;
use super::{Film, PixelBounds, PixelSum};
use crate::image_io::{LayerSize, encode_film_layer, write_atomic};
use std::path::{Path, PathBuf};

/// What a partial film (a "part" of a split render) says about itself: enough to check that
/// parts belong together and to rebuild the image they make up.
#[derive(Clone, Debug, PartialEq)]
pub struct PartMeta {
    /// Hash of the scene description and of the options that change pixels.
    pub scene_hash: u64,
    /// Sampler seed.
    pub seed: u64,
    /// Samples per pixel of the whole render.
    pub spp: u32,
    /// Sample indices `[start, end)` this part took in each of its pixels.
    pub samples: std::ops::Range<u32>,
    /// The pixels of the whole render (the crop window), of which the part holds some.
    pub render_bounds: PixelBounds,
    /// The film's scale factor (pbrt's `iso`/`exposure`/`scale`), applied to the final image.
    pub scale: f32,
}

/// Why a partial film (a split part, or `lancer render`'s checkpoint) could not be read or
/// written.
#[derive(Debug, thiserror::Error)]
pub enum PartError {
    /// The file system refused.
    #[error("{path}: {source}")]
    Io {
        /// The path.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The file is not a lancer part, or is damaged.
    #[error("{path}: {message}")]
    Format {
        /// The path.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

/// Prefix of lancer's header attributes and accumulator channels in a part EXR.
const PART_PREFIX: &str = "lancer.";

/// Names of the accumulator channels: each 64-bit fixed-point sum is split in two 32-bit
/// unsigned channels, `hi = bits >> 32` and `lo = bits & 0xffff_ffff`, so it is stored exactly.
const PART_SUMS: [&str; 4] = ["R", "G", "B", "W"];

/// Names of the denoiser's auxiliary sums a part keeps when its film gathers them
/// (`render --split … --denoise`): Σw over every sample, Σw·albedo and Σw·shading normal,
/// the [`GPixel`] fields [`super::gsums::GbufferFilm::denoiser_images`] reads, each an f64
/// stored exactly as its 64 bits ([`aux_bits`]). A checkpoint of a `--denoise` render keeps
/// the same sums, in this order, under these names.
pub const PART_AUX: [&str; 7] = [
    "aux.W", "aux.A.R", "aux.A.G", "aux.A.B", "aux.Ns.X", "aux.Ns.Y", "aux.Ns.Z",
];

/// A pixel's sum `k` of [`PART_AUX`].
fn aux_sum(p: &GPixel, k: usize) -> &f64 {
    match k {
        0 => &p.weight,
        1..=3 => &p.albedo[k - 1],
        _ => &p.ns[k - 4],
    }
}

/// A pixel's sum `k` of [`PART_AUX`], to set.
fn aux_sum_mut(p: &mut GPixel, k: usize) -> &mut f64 {
    match k {
        0 => &mut p.weight,
        1..=3 => &mut p.albedo[k - 1],
        _ => &mut p.ns[k - 4],
    }
}

/// A pixel's denoiser's sums ([`PART_AUX`], in its order) as the bits of each f64: what a
/// part's `lancer.aux.*` channels and a checkpoint keep, exactly.
pub fn aux_bits(p: &GPixel) -> [u64; PART_AUX.len()] {
    std::array::from_fn(|k| aux_sum(p, k).to_bits())
}

/// Sets a pixel's denoiser's sums from [`aux_bits`]' bits (its other sums are left as they
/// are).
pub fn set_aux_bits(p: &mut GPixel, bits: [u64; PART_AUX.len()]) {
    for (k, b) in bits.into_iter().enumerate() {
        *aux_sum_mut(p, k) = f64::from_bits(b);
    }
}

/// A g-buffer of `pixels` pixels for the denoiser's sums read back from a file (a part's or a
/// checkpoint's), to fill with [`set_aux_bits`]. Its configuration only serves merging (the
/// normals are already in the camera space the render used); a render that continues it
/// gives it the scene's ([`GbufferConfig::denoiser`]).
pub fn aux_film(pixels: usize, spp: u32) -> GbufferFilm {
    GbufferFilm::new(
        GbufferConfig::denoiser(crate::math::Transform::IDENTITY, spp),
        pixels,
    )
}

/// The smallest rectangle holding both.
fn union(a: &PixelBounds, b: &PixelBounds) -> PixelBounds {
    PixelBounds {
        x0: a.x0.min(b.x0),
        x1: a.x1.max(b.x1),
        y0: a.y0.min(b.y0),
        y1: a.y1.max(b.y1),
    }
}

/// The pixels a part's layer covers: the film's, and with splats those of their plane (the
/// whole render's: a part by tiles holds a few pixels' sums but splats on any pixel).
fn part_window(film: &Film) -> PixelBounds {
    match &film.splats {
        Some(s) => union(&film.bounds, &s.bounds),
        None => film.bounds,
    }
}

/// `values` (row-major over `from`) laid over `to`, which holds `from`; zero elsewhere.
fn widen<T: Copy + Default>(values: Vec<T>, from: &PixelBounds, to: &PixelBounds) -> Vec<T> {
    if from == to {
        return values;
    }
    let mut out = vec![T::default(); to.area() as usize];
    let (fw, tw) = (from.width() as usize, to.width() as usize);
    for (i, v) in values.into_iter().enumerate() {
        let (x, y) = (from.x0 + (i % fw) as i32, from.y0 + (i / fw) as i32);
        out[(y - to.y0) as usize * tw + (x - to.x0) as usize] = v;
    }
    out
}

/// The values of `sub`'s pixels (row-major) out of `values`, row-major over `window` ⊇ `sub`.
fn narrow<'v, T: Copy>(
    values: &'v [T],
    window: &PixelBounds,
    sub: &PixelBounds,
) -> impl Iterator<Item = T> + 'v {
    let (sw, ww) = (sub.width() as usize, window.width() as usize);
    let (dx, dy) = ((sub.x0 - window.x0) as usize, (sub.y0 - window.y0) as usize);
    (0..sub.area() as usize).map(move |i| values[(dy + i / sw) * ww + dx + i % sw])
}

/// Encodes a partial film as an OpenEXR file: viewable R, G, B channels (the film's colour
/// × scale), the exact accumulators as UINT channels `lancer.{R,G,B,W}.{hi,lo}` and
/// `lancer.N` (sample count), placed at the film's bounds within the full image (data window
/// inside the display window), and the metadata as `lancer.*` text attributes. A film with
/// splats ([`super::splat`]) also has its splat sums as `lancer.splat<k>.{hi,lo}`, k = 0 …
/// `lancer.splatChannels` − 1, over `lancer.splatBounds`; the layer then covers both
/// rectangles, the sums of each zero outside it. A film without splats is written as before
/// splats existed. A film that gathers the denoiser's auxiliary images also has their sums as
/// `lancer.aux.*.{hi,lo}` ([`PART_AUX`]).
pub fn encode_part(film: &Film, meta: &PartMeta) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    if film.bounds.is_empty() {
        return Err("the part holds no pixel".into());
    }
    let window = part_window(film);
    let wide = |v: Vec<u32>| widen(v, &film.bounds, &window);
    let wide_u64 = |v: Vec<u64>| widen(v, &film.bounds, &window);
    let mut list: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    let image = film.image(meta.scale);
    for (c, name) in ["R", "G", "B"].iter().enumerate() {
        let v = widen(image.iter().map(|p| p[c]).collect(), &film.bounds, &window);
        list.push(AnyChannel::new(*name, FlatSamples::F32(v)));
    }
    let push_u64 = |name: String, sums: Vec<u64>, list: &mut SmallVec<_>| {
        let hi = sums.iter().map(|&v| (v >> 32) as u32).collect();
        let lo = sums.iter().map(|&v| v as u32).collect();
        list.push(AnyChannel::new(
            format!("{PART_PREFIX}{name}.hi").as_str(),
            FlatSamples::U32(hi),
        ));
        list.push(AnyChannel::new(
            format!("{PART_PREFIX}{name}.lo").as_str(),
            FlatSamples::U32(lo),
        ));
    };
    for (c, name) in PART_SUMS.iter().enumerate() {
        let sum = |p: &PixelSum| if c < 3 { p.rgb[c] } else { p.weight } as u64;
        let sums = widen(film.pixels.iter().map(sum).collect(), &film.bounds, &window);
        push_u64(name.to_string(), sums, &mut list);
    }
    let n = wide(film.pixels.iter().map(|p| p.samples).collect());
    list.push(AnyChannel::new(
        format!("{PART_PREFIX}N").as_str(),
        FlatSamples::U32(n),
    ));
    let mut extra = Vec::new();
    if let Some(sp) = &film.splats {
        for k in 0..sp.channels {
            let sums = sp.sums.iter().skip(k).step_by(sp.channels);
            let sums = widen(sums.map(|&v| v as u64).collect(), &sp.bounds, &window);
            push_u64(format!("splat{k}"), sums, &mut list);
        }
        let b = &sp.bounds;
        extra.push((
            "splatBounds",
            format!("{},{},{},{}", b.x0, b.x1, b.y0, b.y1),
        ));
        extra.push(("splatChannels", sp.channels.to_string()));
    }
    if let Some(g) = film.gbuffer.as_ref().filter(|g| g.config.for_denoiser) {
        for (k, name) in PART_AUX.iter().enumerate() {
            let bits = g.pixels.iter().map(|p| aux_sum(p, k).to_bits()).collect();
            push_u64(name.to_string(), wide_u64(bits), &mut list);
        }
    }
    let b = &meta.render_bounds;
    let attrs = [
        ("sceneHash", format!("{:016x}", meta.scene_hash)),
        ("seed", meta.seed.to_string()),
        ("spp", meta.spp.to_string()),
        (
            "samples",
            format!("{}..{}", meta.samples.start, meta.samples.end),
        ),
        (
            "pixelBounds",
            format!(
                "{},{},{},{}",
                film.bounds.x0, film.bounds.x1, film.bounds.y0, film.bounds.y1
            ),
        ),
        (
            "renderBounds",
            format!("{},{},{},{}", b.x0, b.x1, b.y0, b.y1),
        ),
        (
            "resolution",
            format!("{}x{}", film.full_width, film.full_height),
        ),
        // Rust prints the shortest decimal that parses back to the same f32.
        ("scale", meta.scale.to_string()),
    ];
    let mut layer_attrs = LayerAttributes::named("lancer part");
    layer_attrs.layer_position = Vec2(window.x0, window.y0);
    for (k, v) in attrs.into_iter().chain(extra) {
        layer_attrs.other.insert(
            Text::from(format!("{PART_PREFIX}{k}").as_str()),
            AttributeValue::Text(Text::from(v.as_str())),
        );
    }
    let size = LayerSize {
        size: (window.width() as usize, window.height() as usize),
        full: (film.full_width, film.full_height),
    };
    encode_film_layer(size, layer_attrs, list)
}

/// Writes a partial film as an EXR part (see [`encode_part`]), atomically.
pub fn write_part(path: &Path, film: &Film, meta: &PartMeta) -> Result<(), PartError> {
    let bytes = encode_part(film, meta).map_err(|message| PartError::Format {
        path: path.to_path_buf(),
        message: format!("cannot encode part: {message}"),
    })?;
    write_atomic(path, &bytes).map_err(|source| PartError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a part written by [`write_part`]: the film with its exact accumulators, and its
/// metadata. Any other file (or a damaged one) is an error naming the file and what is wrong.
pub fn read_part(path: &Path) -> Result<(Film, PartMeta), PartError> {
    let bytes = std::fs::read(path).map_err(|source| PartError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode_part(path, bytes)
}

/// Decodes the bytes of a part ([`encode_part`]'s), as [`read_part`] reads a file; `name` is
/// what errors call it (the file, or a label for a part that travelled in memory).
pub fn decode_part(name: &Path, bytes: Vec<u8>) -> Result<(Film, PartMeta), PartError> {
    use exr::prelude::{AttributeValue, FlatSamples, ReadChannels, ReadLayers, Text, read};
    let path = name;
    let err = |message: String| PartError::Format {
        path: path.to_path_buf(),
        message,
    };
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .map_err(|e| err(format!("not a readable EXR file: {e}")))?;
    let layer = &image.layer_data;
    let attr = |k: &str| -> Result<String, PartError> {
        match layer
            .attributes
            .other
            .get(&Text::from(format!("{PART_PREFIX}{k}").as_str()))
        {
            Some(AttributeValue::Text(t)) => Ok(t.to_string()),
            _ => Err(err(format!(
                "not a lancer part: no '{PART_PREFIX}{k}' attribute (render it with --split)"
            ))),
        }
    };
    let bad = |k: &str, v: &str| err(format!("bad '{PART_PREFIX}{k}' attribute '{v}'"));
    let num = |k: &str| -> Result<u64, PartError> {
        let v = attr(k)?;
        v.parse().map_err(|_| bad(k, &v))
    };
    let rect = |k: &str| -> Result<PixelBounds, PartError> {
        let v = attr(k)?;
        let n: Vec<i32> = v
            .split(',')
            .map(|x| x.trim().parse())
            .collect::<Result<_, _>>()
            .map_err(|_| bad(k, &v))?;
        match n[..] {
            [x0, x1, y0, y1] if x0 <= x1 && y0 <= y1 => Ok(PixelBounds { x0, x1, y0, y1 }),
            _ => Err(bad(k, &v)),
        }
    };
    let hash_text = attr("sceneHash")?;
    let scene_hash =
        u64::from_str_radix(&hash_text, 16).map_err(|_| bad("sceneHash", &hash_text))?;
    let spp =
        u32::try_from(num("spp")?).map_err(|_| bad("spp", &attr("spp").unwrap_or_default()))?;
    let samples_text = attr("samples")?;
    let samples = samples_text
        .split_once("..")
        .and_then(|(a, b)| Some(a.parse::<u32>().ok()?..b.parse::<u32>().ok()?))
        .filter(|r| r.start < r.end)
        .ok_or_else(|| bad("samples", &samples_text))?;
    let res_text = attr("resolution")?;
    let (full_width, full_height) = res_text
        .split_once('x')
        .and_then(|(a, b)| Some((a.parse::<u32>().ok()?, b.parse::<u32>().ok()?)))
        .ok_or_else(|| bad("resolution", &res_text))?;
    let scale_text = attr("scale")?;
    let scale: f32 = scale_text.parse().map_err(|_| bad("scale", &scale_text))?;
    let bounds = rect("pixelBounds")?;
    let meta = PartMeta {
        scene_hash,
        seed: num("seed")?,
        spp,
        samples,
        render_bounds: rect("renderBounds")?,
        scale,
    };
    // With splats, the layer covers the film's pixels and the splat plane's.
    let splat_bounds = match layer
        .attributes
        .other
        .contains_key(&Text::from(format!("{PART_PREFIX}splatBounds").as_str()))
    {
        true => {
            let channels_text = attr("splatChannels")?;
            let channels = channels_text
                .parse::<usize>()
                .ok()
                .filter(|&c| c > 0 && c <= 1024)
                .ok_or_else(|| bad("splatChannels", &channels_text))?;
            Some((rect("splatBounds")?, channels))
        }
        false => None,
    };
    let window = match &splat_bounds {
        Some((sb, _)) => union(&bounds, sb),
        None => bounds,
    };
    let size = layer.size;
    if size.width() != window.width() as usize || size.height() != window.height() as usize {
        return Err(err(format!(
            "the image is {}x{} pixels but its pixel (and splat) bounds say {}x{}",
            size.width(),
            size.height(),
            window.width(),
            window.height()
        )));
    }
    let n = size.area();
    let channel = |name: &str| -> Result<&Vec<u32>, PartError> {
        let full = format!("{PART_PREFIX}{name}");
        let c = layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.eq(full.as_str()))
            .ok_or_else(|| err(format!("not a lancer part: no channel '{full}'")))?;
        match &c.sample_data {
            FlatSamples::U32(v) if v.len() == n => Ok(v),
            _ => Err(err(format!("channel '{full}' is not {n} UINT samples"))),
        }
    };
    // A 64-bit sum from its two halves, over `sub`.
    let sums = |name: &str, sub: &PixelBounds| -> Result<Vec<i64>, PartError> {
        let hi = narrow(channel(&format!("{name}.hi"))?, &window, sub);
        let lo = narrow(channel(&format!("{name}.lo"))?, &window, sub);
        Ok(hi
            .zip(lo)
            .map(|(h, l)| ((h as u64) << 32 | l as u64) as i64)
            .collect())
    };
    let mut film = Film::new(full_width, full_height, bounds);
    for (c, name) in PART_SUMS.iter().enumerate() {
        for (p, v) in film.pixels.iter_mut().zip(sums(name, &bounds)?) {
            if c < 3 {
                p.rgb[c] = v;
            } else {
                p.weight = v;
            }
        }
    }
    for (p, s) in film
        .pixels
        .iter_mut()
        .zip(narrow(channel("N")?, &window, &bounds))
    {
        p.samples = s;
    }
    if let Some((sb, channels)) = splat_bounds {
        let mut plane = SplatPlane::new(sb, channels);
        for k in 0..channels {
            let v = sums(&format!("splat{k}"), &sb)?;
            for (i, v) in v.into_iter().enumerate() {
                plane.sums[i * channels + k] = v;
            }
        }
        film.splats = Some(Box::new(plane));
    }
    // The denoiser's sums, when the part has them.
    let aux_w = format!("{PART_PREFIX}{}.hi", PART_AUX[0]);
    if layer
        .channel_data
        .list
        .iter()
        .any(|c| c.name.eq(aux_w.as_str()))
    {
        let mut g = aux_film(bounds.area() as usize, spp);
        for (k, name) in PART_AUX.iter().enumerate() {
            for (p, v) in g.pixels.iter_mut().zip(sums(name, &bounds)?) {
                *aux_sum_mut(p, k) = f64::from_bits(v as u64);
            }
        }
        film.gbuffer = Some(Box::new(g));
    }
    Ok((film, meta))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image_io::write_image;
    use crate::math::Rgb;

    #[test]
    fn parts_round_trip_exactly() {
        let bounds = PixelBounds {
            x0: 3,
            x1: 8,
            y0: 2,
            y1: 5,
        };
        let mut film = Film::new(10, 6, bounds);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            let i = i as i64;
            // Values that use both halves and the sign bit of the 64-bit sums.
            p.rgb = [i * 0x1_0000_0007, -i * 12345, (1 << 40) + i];
            p.weight = i << 33 | 0xffff_ffff;
            p.samples = i as u32 * 3 + 1;
        }
        let meta = PartMeta {
            scene_hash: 0xdead_beef_0123_4567,
            seed: u64::MAX - 2,
            spp: 64,
            samples: 16..48,
            render_bounds: PixelBounds {
                x0: 0,
                x1: 10,
                y0: 1,
                y1: 6,
            },
            scale: 0.1,
        };
        let dir = lancer_testing::ScratchDir::new("part");
        let path = dir.join("p.exr");
        write_part(&path, &film, &meta).unwrap();
        let (f2, m2) = read_part(&path).unwrap();
        assert_eq!(f2, film);
        assert_eq!(m2, meta);
        // With the denoiser's sums (any f64, sign and all, comes back bit for bit).
        let config = GbufferConfig::denoiser(crate::math::Transform::IDENTITY, 64);
        let mut g = GbufferFilm::new(config, film.pixels.len());
        for (i, p) in g.pixels.iter_mut().enumerate() {
            for k in 0..PART_AUX.len() {
                *aux_sum_mut(p, k) = (i * 7 + k) as f64 * -0.1 + 1e-300;
            }
        }
        film.gbuffer = Some(Box::new(g));
        write_part(&path, &film, &meta).unwrap();
        let (f3, _) = read_part(&path).unwrap();
        assert_eq!(f3, film);
        // An ordinary image is refused with a message naming the file.
        let plain = dir.join("plain.exr");
        write_image(&plain, 2, 2, &[Rgb::splat(1.0); 4]).unwrap();
        let e = read_part(&plain).unwrap_err().to_string();
        assert!(
            e.contains("plain.exr") && e.contains("not a lancer part"),
            "{e}"
        );
    }

    /// A part with splats keeps every splat sum bit for bit and in its place: a plane over
    /// the whole render (a crop, wider than the part's band of rows), with more channels than
    /// the colour's three (a spectral film's buckets), every value distinct, so that a
    /// channel dropped, swapped or shifted, or a pixel misplaced, fails.
    #[test]
    fn parts_with_splats_round_trip_exactly() {
        let render = PixelBounds {
            x0: 1,
            x1: 7,
            y0: 1,
            y1: 5,
        };
        let band = PixelBounds {
            y0: 2,
            y1: 4,
            ..render
        };
        let mut film = Film::new(8, 6, band);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            let i = i as i64 + 1;
            p.rgb = [i * 0x1_0000_0007, -i * 12345, (1 << 40) + i];
            p.weight = i << 33 | 0xffff_ffff;
            p.samples = 4;
        }
        let channels = 5;
        let mut plane = SplatPlane::new(render, channels);
        for (i, v) in plane.sums.iter_mut().enumerate() {
            let i = i as i64 + 1;
            *v = if i % 3 == 0 { -i } else { i } * 0x1_0000_0003;
        }
        film.splats = Some(Box::new(plane));
        let meta = PartMeta {
            scene_hash: 1,
            seed: 2,
            spp: 8,
            samples: 0..4,
            render_bounds: render,
            scale: 1.0,
        };
        let dir = lancer_testing::ScratchDir::new("part-splats");
        let path = dir.join("p.exr");
        write_part(&path, &film, &meta).unwrap();
        let (f2, m2) = read_part(&path).unwrap();
        assert_eq!(f2.splats, film.splats);
        assert_eq!(f2, film);
        assert_eq!(m2, meta);
    }
}
