//! `lancer.write_image` and `lancer.read_image`: PNG (8-bit sRGB) and OpenEXR (32-bit float
//! linear), as `lancer render` writes them and as its texture reader reads them.

use lancer::image_io::ImageWriteError;
use lancer::math::Rgb;
use lancer_scene::image_read::{Encoding, read_image as read_file};
use numpy::ndarray::Array3;
use numpy::{PyArray3, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;

/// Writes a (height, width, 3) float32 C-contiguous array of linear RGB, row 0 at the top, to
/// `path`, the format chosen by the extension: `.exr` keeps the floats, `.png` clamps to
/// [0, 1], sRGB-encodes and rounds to 8 bits. Written atomically (a temporary file renamed
/// over the destination). The Python wrapper `lancer.write_image` converts other arrays.
#[pyfunction]
pub fn write_image(
    py: Python<'_>,
    path: PathBuf,
    pixels: PyReadonlyArray3<'_, f32>,
) -> PyResult<()> {
    let shape = pixels.shape();
    let (h, w) = (shape[0], shape[1]);
    if shape[2] != 3 || h == 0 || w == 0 {
        return Err(PyValueError::new_err(format!(
            "an image is an array of shape (height, width, 3), not {shape:?}"
        )));
    }
    let data = pixels
        .as_slice()
        .map_err(|_| PyValueError::new_err("the array must be C-contiguous"))?;
    let rgb: Vec<Rgb> = data
        .chunks_exact(3)
        .map(|c| Rgb::new(c[0], c[1], c[2]))
        .collect();
    let (w, h) = (
        u32::try_from(w).map_err(|_| PyValueError::new_err("image too wide"))?,
        u32::try_from(h).map_err(|_| PyValueError::new_err("image too tall"))?,
    );
    py.detach(|| lancer::image_io::write_image(&path, w, h, &rgb))
        .map_err(|e| match e {
            ImageWriteError::Io { .. } => PyOSError::new_err(e.to_string()),
            _ => PyValueError::new_err(e.to_string()),
        })
}

/// Reads an image (`.exr`, `.png`, `.jpg`) as a (height, width, 3) float32 array of linear
/// RGB, row 0 at the top: EXR values as stored, PNG and JPEG decoded from sRGB (so a PNG
/// written by `write_image` reads back within 8-bit rounding). Alpha is dropped; a grey image
/// gives its value in all three channels. FileNotFoundError for a missing file, ValueError
/// for one lancer cannot decode.
#[pyfunction]
pub fn read_image(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyArray3<f32>>> {
    if !path.exists() {
        return Err(PyFileNotFoundError::new_err(format!(
            "{}: no such file",
            path.display()
        )));
    }
    let decoded = py
        .detach(|| read_file(&path, Encoding::Srgb))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let img = &decoded.rgb;
    let flat: Vec<f32> = img.texels.iter().flat_map(|t| [t.x, t.y, t.z]).collect();
    let array = Array3::from_shape_vec((img.height as usize, img.width as usize, 3), flat)
        .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
    Ok(PyArray3::from_owned_array(py, array))
}
