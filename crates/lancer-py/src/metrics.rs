//! Image metrics, defined as the team's acceptance scripts (`imgcmp.py`) and lancer's own
//! tests define them. Images are (height, width, 3) float64 C-contiguous arrays (the Python
//! wrappers convert); non-finite values propagate (NaN in, NaN out).

use numpy::{PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The pixels of an image array, checked to be (h, w, 3) and contiguous.
fn pixels<'a>(name: &str, a: &'a PyReadonlyArray3<'_, f64>) -> PyResult<&'a [f64]> {
    let shape = a.shape();
    if shape[2] != 3 || shape[0] == 0 || shape[1] == 0 {
        return Err(PyValueError::new_err(format!(
            "{name}: an image is an array of shape (height, width, 3), not {shape:?}"
        )));
    }
    a.as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name}: the array must be C-contiguous")))
}

/// Both images' pixels, which must have the same shape.
fn same_shape<'a>(
    a: &'a PyReadonlyArray3<'_, f64>,
    b: &'a PyReadonlyArray3<'_, f64>,
) -> PyResult<(&'a [f64], &'a [f64])> {
    if a.shape() != b.shape() {
        return Err(PyValueError::new_err(format!(
            "the images differ in shape: {:?} and {:?}",
            a.shape(),
            b.shape()
        )));
    }
    Ok((pixels("image", a)?, pixels("reference", b)?))
}

/// Mean of each channel: m_c = Σ_p x_{p,c} / N.
fn channel_means(x: &[f64]) -> [f64; 3] {
    let mut m = [0.0; 3];
    for p in x.chunks_exact(3) {
        for c in 0..3 {
            m[c] += p[c];
        }
    }
    let n = (x.len() / 3) as f64;
    m.map(|v| v / n)
}

/// Mean of all values, floored at 1e-6: the scale of the normalised metrics.
fn reference_scale(r: &[f64]) -> f64 {
    (r.iter().sum::<f64>() / r.len() as f64).max(1e-6)
}

/// Mean squared difference over every pixel and channel: Σ (a − b)² / 3N.
fn mse(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum::<f64>() / a.len() as f64
}

/// The largest relative error of a channel mean, max_c |m_c(image) − m_c(ref)| / max(m_c(ref),
/// 1e-4): a bias measure, insensitive to noise; the images may differ in size.
#[pyfunction]
pub fn mean_rel_error(
    image: PyReadonlyArray3<'_, f64>,
    reference: PyReadonlyArray3<'_, f64>,
) -> PyResult<f64> {
    let (mt, mr) = (
        channel_means(pixels("image", &image)?),
        channel_means(pixels("reference", &reference)?),
    );
    Ok((0..3)
        .map(|c| (mt[c] - mr[c]).abs() / mr[c].max(1e-4))
        .fold(0.0, f64::max))
}

/// Relative mean squared error: mean over pixels and channels of (a − r)² / (r² + (0.1·m)²),
/// m the reference's mean (floored at 1e-6); the 0.1·m term keeps dark pixels from dominating.
#[pyfunction]
pub fn relmse(
    image: PyReadonlyArray3<'_, f64>,
    reference: PyReadonlyArray3<'_, f64>,
) -> PyResult<f64> {
    let (a, r) = same_shape(&image, &reference)?;
    let eps = (0.1 * reference_scale(r)).powi(2);
    Ok(a.iter()
        .zip(r)
        .map(|(x, y)| (x - y) * (x - y) / (y * y + eps))
        .sum::<f64>()
        / a.len() as f64)
}

/// Root mean squared error: √(Σ (a − b)² / 3N) over every pixel and channel.
#[pyfunction]
pub fn rmse(
    image: PyReadonlyArray3<'_, f64>,
    reference: PyReadonlyArray3<'_, f64>,
) -> PyResult<f64> {
    let (a, b) = same_shape(&image, &reference)?;
    Ok(mse(a, b).sqrt())
}

/// RMSE over the reference's mean (floored at 1e-6): a scale-free error.
#[pyfunction]
pub fn nrmse(
    image: PyReadonlyArray3<'_, f64>,
    reference: PyReadonlyArray3<'_, f64>,
) -> PyResult<f64> {
    let (a, r) = same_shape(&image, &reference)?;
    Ok(mse(a, r).sqrt() / reference_scale(r))
}
