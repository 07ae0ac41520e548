//! The parts of a render split over processes (`lancer.distributed`): one part rendered to
//! its exact accumulators, and parts merged into the image, with the command line's own
//! split and merge logic (`lancer render --split`, `lancer merge`), so that the merged image
//! is bit for bit `lancer.render`'s.
//!
//! A part travels as the bytes of the command line's part file (an OpenEXR image whose
//! channels hold each pixel's 64-bit fixed-point sums Σw·R, Σw·G, Σw·B, Σw exactly, with the
//! scene hash, seed, samples and pixels as attributes): integer sums add up to the same bits
//! in any order, rounded images would not.

use crate::render::{check_film, image_array, render_film, settings_from_desc, with_overrides};
use crate::scene::PyScene;
use lancer::film::part::{decode_part, encode_part};
use lancer_cli::split::{self, Split, SplitBy};
use numpy::PyArray3;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use std::path::PathBuf;

/// Renders part `part` of `parts` (0-based) of the render `lancer.render(scene, …)` would make
/// with the same options, and returns it as bytes (a part file of `lancer render --split`).
/// `split_by` is "tiles" (bands of whole tile rows, every sample) or "samples" (ranges of
/// sample indices, every pixel), as `--split-by`.
#[pyfunction]
#[pyo3(signature = (scene, part, parts, split_by = "tiles", spp = None, resolution = None, seed = 0, threads = None, spectral = true, crop = None))]
#[allow(clippy::too_many_arguments)] // lancer.render's options, and which part
pub fn render_part<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    part: u32,
    parts: u32,
    split_by: &str,
    spp: Option<u32>,
    resolution: Option<Vec<u32>>,
    seed: u64,
    threads: Option<usize>,
    spectral: bool,
    crop: Option<Vec<f32>>,
) -> PyResult<Bound<'py, PyBytes>> {
    let by = match split_by {
        "tiles" => SplitBy::Tiles,
        "samples" => SplitBy::Samples,
        other => {
            return Err(PyValueError::new_err(format!(
                "split_by is \"tiles\" or \"samples\", not {other:?}"
            )));
        }
    };
    if parts == 0 || part >= parts {
        return Err(PyValueError::new_err(format!(
            "part {part} of {parts} does not exist (0 <= part < parts)"
        )));
    }
    let this = scene.get();
    let desc = with_overrides(&this.desc, spp, resolution, seed, crop)?;
    let mut settings = settings_from_desc(&desc, spectral);
    let render_bounds = desc.film.render_bounds();
    check_film(&render_bounds)?;
    let split = Split {
        index: part,
        count: parts,
    };
    split::check_split(&desc, Some((split, by))).map_err(|e| PyValueError::new_err(e.message))?;
    let plan = split::plan(
        render_bounds,
        desc.integrator.sample_indices(desc.sampler.spp),
        None,
        Some((split, by)),
    )
    .map_err(|e| PyValueError::new_err(e.message))?;
    settings.bounds = plan.bounds;
    settings.samples = plan.samples.clone();
    let film = render_film(py, this, &desc, &settings, threads, false)?;
    let meta = plan.part_meta(&desc, spectral);
    let bytes = py
        .detach(|| encode_part(&film, &meta))
        .map_err(|e| PyRuntimeError::new_err(format!("cannot encode the part: {e}")))?;
    Ok(PyBytes::new(py, &bytes))
}

/// Merges parts made by `render_part` (their bytes, in any order) into the image, a float32
/// array (height, width, 3), after checking, as `lancer merge` does, that they are parts of
/// one render that together hold every pixel's every sample once.
#[pyfunction]
pub fn merge_parts<'py>(
    py: Python<'py>,
    parts: Vec<Vec<u8>>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let merged = py.detach(|| {
        let decoded = parts
            .into_iter()
            .enumerate()
            .map(|(i, bytes)| {
                let name = PathBuf::from(format!("part {i}"));
                let (film, meta) = decode_part(&name, bytes).map_err(|e| e.to_string())?;
                Ok((name, film, meta))
            })
            .collect::<Result<Vec<_>, String>>()?;
        lancer_cli::merge::merge_parts(&decoded)
    });
    let (film, scale) = merged.map_err(|e| PyValueError::new_err(format!("cannot merge: {e}")))?;
    image_array(py, &film, scale)
}

/// Runs the `lancer` command line with `argv` (the program name first) in this process, as
/// the binary does, and returns its exit status: the wheel's `lancer` command.
#[pyfunction]
pub fn cli_main(py: Python<'_>, argv: Vec<std::ffi::OsString>) -> i32 {
    py.detach(|| lancer_cli::run(argv))
}
