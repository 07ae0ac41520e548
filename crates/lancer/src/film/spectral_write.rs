//! Writing a `spectral` film as pbrt-v4's `SpectralFilm::GetImage` does: one OpenEXR layer
//! with `R G B` and one channel per wavelength bucket ([`SpectralDesc::channel_names`]), the
//! header attributes `spectralLayoutVersion` = "1.0" and `emissiveUnits` =
//! "W.m^-2.sr^-1", half floats when `savefp16` (pbrt-v4's default for this film) with every
//! value clamped to the largest half, 65504.

use super::Film;
use super::spectral::SpectralDesc;
use crate::image_io::{ExrChannels, ImageWriteError, Planes, encode_film_layer, write_film_exr};
use exr::prelude::{AttributeValue, LayerAttributes, Text, Vec2};
use std::path::Path;

/// Largest finite half float.
const HALF_MAX: f32 = 65504.0;

/// The channel names of a spectral film: `R`, `G`, `B`, then the buckets'.
pub fn channel_names(desc: &SpectralDesc) -> Vec<String> {
    let mut names: Vec<String> = ["R", "G", "B"].map(String::from).into();
    names.extend(desc.channel_names());
    names
}

/// The layer of a spectral film: colour Σw·L/Σw × `scale` and the bucket values (see
/// [`super::spectral`]), placed at the film's bounds within the full image, with pbrt-v4's
/// attributes; and the number of values clamped to 65504 (half floats only).
fn spectral_layer(
    film: &Film,
    scale: f32,
    fp16: bool,
) -> Result<(LayerAttributes, ExrChannels, u64), String> {
    let s = film
        .spectral
        .as_ref()
        .ok_or("the film has no wavelength buckets")?;
    let n = film.pixels.len();
    if n == 0 {
        return Err("the image holds no pixel".into());
    }
    let names = channel_names(&s.desc);
    let mut planes = Planes::new(names.len(), n, fp16);
    let mut clamped = 0u64;
    let mut put = |c: usize, v: f32, planes: &mut Planes| {
        let v = if fp16 && v > HALF_MAX {
            clamped += 1;
            HALF_MAX
        } else {
            v
        };
        planes.push(c, v);
    };
    let divisor = film.splat_divisor();
    for i in 0..n {
        let rgb = film.pixel_rgb(i, divisor) * scale;
        for c in 0..3 {
            put(c, rgb[c], &mut planes);
        }
        for (b, v) in film.bucket_values(i, divisor).into_iter().enumerate() {
            put(3 + b, v, &mut planes);
        }
    }
    let mut attrs = LayerAttributes {
        layer_position: Vec2(film.bounds.x0, film.bounds.y0),
        ..LayerAttributes::default()
    };
    for (k, v) in [
        ("spectralLayoutVersion", "1.0"),
        ("emissiveUnits", "W.m^-2.sr^-1"),
    ] {
        attrs
            .other
            .insert(Text::from(k), AttributeValue::Text(Text::from(v)));
    }
    Ok((attrs, planes.named(&names), clamped))
}

/// Encodes a spectral film as OpenEXR in memory (see [`write_spectral_exr`]): the bytes and
/// the number of values clamped to 65504.
pub fn encode_spectral_exr(film: &Film, scale: f32, fp16: bool) -> Result<(Vec<u8>, u64), String> {
    let (attrs, channels, clamped) = spectral_layer(film, scale, fp16)?;
    Ok((
        encode_film_layer(film.layer_size(), attrs, channels)?,
        clamped,
    ))
}

/// Writes a spectral film to `path` atomically, streamed into the temporary file: colour
/// Σw·L/Σw × `scale` and one channel per wavelength bucket; only `.exr`, as pbrt-v4. Returns
/// the number of values clamped to 65504 (half floats only).
pub fn write_spectral_exr(
    path: &Path,
    film: &Film,
    scale: f32,
    fp16: bool,
) -> Result<u64, ImageWriteError> {
    let (attrs, channels, clamped) =
        spectral_layer(film, scale, fp16).map_err(|message| ImageWriteError::Encode {
            path: path.to_path_buf(),
            message,
        })?;
    write_film_exr(path, "spectral", film.layer_size(), attrs, channels)?;
    Ok(clamped)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::PixelBounds;
    use crate::film::spectral::SpectralSums;
    use crate::math::{Rgb, SampledSpectrum};

    /// The first layer of an EXR file's bytes, every channel and attribute.
    fn read(
        bytes: Vec<u8>,
    ) -> exr::prelude::Image<
        exr::prelude::Layer<exr::prelude::AnyChannels<exr::prelude::FlatSamples>>,
    > {
        use exr::prelude::{ReadChannels, ReadLayers};
        exr::prelude::read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .from_buffered(std::io::Cursor::new(bytes))
            .unwrap()
    }

    #[test]
    fn writes_rgb_and_bucket_channels_with_pbrt_v4_names() {
        let bounds = PixelBounds {
            x0: 0,
            x1: 2,
            y0: 0,
            y1: 1,
        };
        let mut film = Film::new(2, 1, bounds);
        let desc = SpectralDesc {
            nbuckets: 2,
            lambda_min: 400.0,
            lambda_max: 700.0,
        };
        let mut s = SpectralSums::new(desc, 2);
        let lambda = desc.sample_wavelengths(0.0); // 400, 475 | 550, 625
        s.add(
            1,
            SampledSpectrum::new(1.0, 1.0, 2.0, 2.0),
            &lambda,
            1.0,
            f32::INFINITY,
        );
        film.spectral = Some(Box::new(s));
        film.pixels[1].add(Rgb::new(0.5, 0.25, 1.0), 1.0);
        let (bytes, clamped) = encode_spectral_exr(&film, 2.0, false).unwrap();
        assert_eq!(clamped, 0);
        let img = read(bytes.clone());
        let layer = &img.layer_data;
        let value = |name: &str, i: usize| {
            let c = layer
                .channel_data
                .list
                .iter()
                .find(|c| c.name.eq(name))
                .unwrap_or_else(|| panic!("no channel {name}"));
            c.sample_data.value_by_flat_index(i).to_f32()
        };
        assert_eq!(value("R", 1), 1.0);
        assert_eq!(value("B", 1), 2.0);
        assert_eq!(value("S0.475,000nm", 1), 1.0);
        assert_eq!(value("S0.625,000nm", 1), 2.0);
        assert_eq!(value("S0.475,000nm", 0), 0.0);
        let other = &layer.attributes.other;
        assert_eq!(
            other.get(&exr::prelude::Text::from("spectralLayoutVersion")),
            Some(&exr::prelude::AttributeValue::Text("1.0".into()))
        );
        // The same bytes every time (the header's attributes in name order, not in a hash
        // map's), and the same streamed into a file.
        for _ in 0..8 {
            assert_eq!(encode_spectral_exr(&film, 2.0, false).unwrap().0, bytes);
        }
        let dir = lancer_testing::ScratchDir::new("spectral-film");
        let path = dir.join("s.exr");
        assert_eq!(write_spectral_exr(&path, &film, 2.0, false).unwrap(), 0);
        assert_eq!(std::fs::read(&path).unwrap(), bytes);
        assert!(write_spectral_exr(&dir.join("s.png"), &film, 2.0, false).is_err());
        // Half floats clamp at 65504: the three colour channels of pixel 0 (its buckets are
        // empty), read back as that value.
        film.pixels[0].add(Rgb::splat(1e6), 1.0);
        let (half, clamped) = encode_spectral_exr(&film, 1.0, true).unwrap();
        assert_eq!(clamped, 3);
        let img = read(half);
        for c in &img.layer_data.channel_data.list {
            let v = c.sample_data.value_by_flat_index(0).to_f32();
            let want = if ["R", "G", "B"].contains(&c.name.to_string().as_str()) {
                HALF_MAX
            } else {
                0.0
            };
            assert_eq!(v, want, "channel {}", c.name);
        }
    }
}
