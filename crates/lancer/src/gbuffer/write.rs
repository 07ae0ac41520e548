//! Writing a g-buffer film as pbrt-v4 does: one OpenEXR file with the 25 channels of
//! [`CHANNELS`], half floats when `savefp16` (the default of a `gbuffer` film), and
//! pbrt-v4's header attributes `renderTimeSeconds`, `samplesPerPixel`, `worldToCamera` and
//! (projective cameras) `worldToNDC`.

use crate::film::Film;
use crate::film::gsums::CHANNELS;
use crate::image_io::{ExrChannels, ImageWriteError, Planes, encode_film_layer, write_film_exr};
use crate::math::Transform;
use crate::scene::desc::{Projection, SceneDesc};
use exr::prelude::{AttributeValue, LayerAttributes, Text, Vec2};
use std::path::Path;

/// Largest finite half float: pbrt-v4 clamps colours to it before writing half floats.
pub const HALF_MAX: f32 = 65504.0;

/// The header attributes pbrt-v4 writes with a g-buffer image.
#[derive(Clone, Debug, PartialEq)]
pub struct GbufferHeader {
    /// Seconds the render took (`renderTimeSeconds`).
    pub render_time_seconds: Option<f32>,
    /// Samples per pixel (`samplesPerPixel`).
    pub samples_per_pixel: i32,
    /// World → camera, row-major (`worldToCamera`, an `m44f`).
    pub world_to_camera: [f32; 16],
    /// World → NDC, row-major (`worldToNDC`): projective cameras only, as in pbrt-v4.
    pub world_to_ndc: Option<[f32; 16]>,
    /// Write half floats (`savefp16`) rather than 32-bit floats.
    pub fp16: bool,
}

/// A transform's matrix, row-major (pbrt-v4 copies `m[i][j]` into the attribute as is).
fn row_major(t: &Transform) -> [f32; 16] {
    t.m.transpose().to_cols_array()
}

impl GbufferHeader {
    /// The attributes of a render of `desc`: pbrt-v4's NDC from world is
    /// T(½, ½, ½)·S(½, ½, ½)·screen_from_camera·camera_from_world, with its perspective
    /// projection (near 10⁻², far 1000) or its orthographic one (the identity for near 0,
    /// far 1).
    pub fn of(desc: &SceneDesc, render_time_seconds: Option<f32>) -> GbufferHeader {
        let cam = &desc.camera.camera_from_world;
        let screen_from_camera = match desc.camera.projection {
            Projection::Perspective { fov } => Transform::perspective(fov, 1e-2, 1000.0),
            Projection::Orthographic => Some(Transform::IDENTITY),
            _ => None,
        };
        let world_to_ndc = screen_from_camera.and_then(|s| {
            let half = Transform::scale(crate::math::Vec3::splat(0.5))?;
            let t = Transform::translate(crate::math::Vec3::splat(0.5)) * half * s * *cam;
            Some(row_major(&t))
        });
        GbufferHeader {
            render_time_seconds,
            samples_per_pixel: desc.sampler.spp.min(i32::MAX as u32) as i32,
            world_to_camera: row_major(cam),
            world_to_ndc,
            fp16: desc.film.save_fp16,
        }
    }
}

/// Encodes a g-buffer film as OpenEXR: colour Σw·L/Σw × `scale` (clamped to [`HALF_MAX`] in
/// half floats, as pbrt-v4 does), the auxiliary channels of [`crate::film::gsums::GPixel::channels`],
/// placed at the film's bounds within the full image, with pbrt-v4's attributes; and the
/// number of pixels whose colour was clamped.
fn gbuffer_layer(
    film: &Film,
    scale: f32,
    header: &GbufferHeader,
) -> Result<(LayerAttributes, ExrChannels, u64), String> {
    let g = film
        .gbuffer
        .as_ref()
        .ok_or("the film has no g-buffer sums")?;
    let (w, h) = (film.bounds.width() as usize, film.bounds.height() as usize);
    if w == 0 || h == 0 {
        return Err("the image holds no pixel".into());
    }
    let mut planes = Planes::new(CHANNELS.len(), w * h, header.fp16);
    let mut clamped = 0u64;
    let divisor = film.splat_divisor();
    for (i, gp) in g.pixels.iter().enumerate() {
        let mut rgb = film.pixel_rgb(i, divisor) * scale;
        if header.fp16 && rgb.max_element() > HALF_MAX {
            rgb = rgb.min(crate::math::Rgb::splat(HALF_MAX));
            clamped += 1;
        }
        for c in 0..3 {
            planes.push(c, rgb[c]);
        }
        for (c, v) in gp.channels().into_iter().enumerate() {
            planes.push(3 + c, v);
        }
    }
    let mut attrs = LayerAttributes {
        layer_position: Vec2(film.bounds.x0, film.bounds.y0),
        ..LayerAttributes::default()
    };
    let mut other = |k: &str, v: AttributeValue| {
        attrs.other.insert(Text::from(k), v);
    };
    if let Some(t) = header.render_time_seconds {
        other("renderTimeSeconds", AttributeValue::F32(t));
    }
    other(
        "samplesPerPixel",
        AttributeValue::I32(header.samples_per_pixel),
    );
    // The exr crate writes these two standard attributes under their names `worldToCamera`
    // and `worldToNDC`.
    attrs.world_to_camera = Some(header.world_to_camera);
    attrs.world_to_normalized_device = header.world_to_ndc;
    Ok((attrs, planes.named(&CHANNELS), clamped))
}

/// Encodes a g-buffer film as OpenEXR in memory (see [`write_gbuffer_exr`]): the bytes and
/// the number of pixels whose colour was clamped.
pub fn encode_gbuffer_exr(
    film: &Film,
    scale: f32,
    header: &GbufferHeader,
) -> Result<(Vec<u8>, u64), String> {
    let (attrs, channels, clamped) = gbuffer_layer(film, scale, header)?;
    Ok((
        encode_film_layer(film.layer_size(), attrs, channels)?,
        clamped,
    ))
}

/// Writes a g-buffer film to `path` atomically, streamed into the temporary file: colour
/// and the channels of [`CHANNELS`]; only `.exr`, as pbrt-v4. Returns the number of clamped
/// pixels.
pub fn write_gbuffer_exr(
    path: &Path,
    film: &Film,
    scale: f32,
    header: &GbufferHeader,
) -> Result<u64, ImageWriteError> {
    let (attrs, channels, clamped) =
        gbuffer_layer(film, scale, header).map_err(|message| ImageWriteError::Encode {
            path: path.to_path_buf(),
            message,
        })?;
    write_film_exr(path, "gbuffer", film.layer_size(), attrs, channels)?;
    Ok(clamped)
}
