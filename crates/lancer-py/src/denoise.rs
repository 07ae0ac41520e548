//! `lancer.denoise`: Open Image Denoise's network (lancer's own inference,
//! [`lancer_denoise`]) on float32 (height, width, 3) arrays, with the GIL released.

use numpy::ndarray::Array3;
use numpy::{PyArray3, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// The floats of a C-contiguous (height, width, 3) array of the colour's shape.
fn pixels<'a>(
    a: &'a PyReadonlyArray3<'_, f32>,
    name: &str,
    shape: &[usize],
) -> PyResult<&'a [f32]> {
    if a.shape() != shape {
        return Err(PyValueError::new_err(format!(
            "{name} has shape {:?}, the colour {shape:?}: the denoiser's images must have one size",
            a.shape()
        )));
    }
    a.as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name}: the array must be C-contiguous")))
}

/// Denoises `color`, an HDR linear RGB float32 array of shape (height, width, 3), with the
/// network for the auxiliary images given: none, `albedo`, or `albedo` and `normal` (same
/// shape; normals with components in [-1, 1]). Returns a new float32 array. The same
/// network, weights and transfer as Open Image Denoise 2.x (quality "high", hdr), so the
/// result is OIDN's up to float rounding. The Python wrapper `lancer.denoise` converts other
/// arrays.
#[pyfunction]
#[pyo3(signature = (color, albedo = None, normal = None))]
pub fn denoise<'py>(
    py: Python<'py>,
    color: PyReadonlyArray3<'py, f32>,
    albedo: Option<PyReadonlyArray3<'py, f32>>,
    normal: Option<PyReadonlyArray3<'py, f32>>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let shape = color.shape().to_vec();
    if shape[2] != 3 || shape[0] == 0 || shape[1] == 0 {
        return Err(PyValueError::new_err(format!(
            "an image is an array of shape (height, width, 3), not {shape:?}"
        )));
    }
    let c = pixels(&color, "color", &shape)?;
    let a = albedo
        .as_ref()
        .map(|a| pixels(a, "albedo", &shape))
        .transpose()?;
    let n = normal
        .as_ref()
        .map(|n| pixels(n, "normal", &shape))
        .transpose()?;
    let out = py
        .detach(|| lancer_denoise::denoise(c, a, n, shape[1], shape[0]))
        .map_err(|e| match e {
            lancer_denoise::DenoiseError::NormalWithoutAlbedo => {
                PyValueError::new_err(e.to_string())
            }
            _ => PyRuntimeError::new_err(e.to_string()),
        })?;
    let array = Array3::from_shape_vec((shape[0], shape[1], 3), out)
        .map_err(|e| PyRuntimeError::new_err(format!("image shape: {e}")))?;
    Ok(PyArray3::from_owned_array(py, array))
}
