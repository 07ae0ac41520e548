//! `lancer.render`: a scene to a float32 numpy array, with the GIL released and Ctrl-C
//! honoured between units of work (a tile × 16 samples).

use crate::SceneError;
use crate::scene::PyScene;
use lancer::SceneDesc;
use lancer::film::{Film, PixelBounds};
use lancer::gbuffer::{GbufferConfig, GbufferFilm};
use lancer::render::{RenderJob, RenderSettings, RenderStats, render_units, work_units};
use numpy::PyArray3;
use numpy::ndarray::Array3;
use pyo3::exceptions::{PyRuntimeError, PyRuntimeWarning, PyValueError};
use pyo3::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

// The tile edge and the samples of one unit of work are `lancer render`'s: a cancelled render
// stops after the units in flight (a tile × 16 samples), so Ctrl-C is honoured quickly
// whatever the sample count; the image does not depend on them (the film's sums are exact).
use lancer_cli::split::{SAMPLES_PER_PASS, TILE_SIZE};

/// Largest image side accepted, as the scene reader's.
const MAX_RESOLUTION: u32 = lancer_scene::pbrt::convert::MAX_RESOLUTION as u32;

/// Largest film accepted, in bytes of accumulators (`lancer render`'s default limit, 16 GiB).
const MAX_FILM_BYTES: u64 = 16 << 30;

/// How often the waiting Python thread looks for a pending signal during a render.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// The render settings of a scene description, as `lancer render` makes them: the pixels are
/// pbrt's `pixelbounds`, else its crop window rounded as pbrt does (⌈res·min⌉ to ⌈res·max⌉);
/// every sample index `0..spp`; the scene's sampler, seed, filter, integrator and
/// `maxcomponentvalue`; spectral or RGB as asked.
pub fn settings_from_desc(desc: &SceneDesc, spectral: bool) -> RenderSettings {
    RenderSettings {
        tile_size: TILE_SIZE,
        spectral,
        ..RenderSettings::from_desc(desc)
    }
}

/// The caller's overrides, checked, applied to a copy of the scene's description (as
/// `lancer render --spp --resolution --seed --crop` do).
pub fn with_overrides(
    desc: &SceneDesc,
    spp: Option<u32>,
    resolution: Option<Vec<u32>>,
    seed: u64,
    crop: Option<Vec<f32>>,
) -> PyResult<SceneDesc> {
    let mut d = desc.clone();
    if let Some(spp) = spp {
        if spp == 0 {
            return Err(PyValueError::new_err("spp must be at least 1"));
        }
        d.sampler.spp = spp;
        // As `lancer render --spp`: mlt's mutations per pixel.
        if let lancer::integrator::Integrator::Mlt(o) = &mut d.integrator {
            o.mutations_per_pixel = spp;
        }
    }
    if d.sampler.spp == 0 {
        return Err(PyValueError::new_err(
            "the scene asks for 0 samples per pixel; pass spp",
        ));
    }
    d.sampler.seed = seed;
    if let Some(res) = resolution {
        let &[w, h] = res.as_slice() else {
            return Err(PyValueError::new_err(format!(
                "resolution is (width, height), not {res:?}"
            )));
        };
        for (name, v) in [("width", w), ("height", h)] {
            if v == 0 || v > MAX_RESOLUTION {
                return Err(PyValueError::new_err(format!(
                    "resolution: {name} {v} is outside 1..={MAX_RESOLUTION}"
                )));
            }
        }
        d.film.xresolution = w;
        d.film.yresolution = h;
        d.film.pixel_bounds = None;
    }
    if let Some(crop) = crop {
        let &[x0, x1, y0, y1] = crop.as_slice() else {
            return Err(PyValueError::new_err(format!(
                "crop is (x0, x1, y0, y1), not {crop:?}"
            )));
        };
        let inside = |v: f32| (0.0..=1.0).contains(&v);
        if !([x0, x1, y0, y1].into_iter().all(inside) && x0 < x1 && y0 < y1) {
            return Err(PyValueError::new_err(format!(
                "crop ({x0}, {x1}, {y0}, {y1}) must be fractions x0 < x1, y0 < y1 in [0, 1], \
                 as pbrt's cropwindow"
            )));
        }
        d.film.crop_window = [x0, x1, y0, y1];
        d.film.pixel_bounds = None;
    }
    Ok(d)
}

/// Renders `scene` and returns the image as a float32 array of shape (height, width, 3),
/// linear RGB, rows from the top of the image down (the crop window's pixels only when `crop`
/// or the scene selects some).
///
/// `spp`, `resolution` (width, height) and `crop` (x0, x1, y0, y1 as fractions of the image,
/// pbrt's cropwindow), as tuples or lists, override the scene's; `seed` replaces the scene's
/// sampler seed; `threads` limits the worker threads (all cores by default); `spectral`
/// renders with sampled wavelengths as pbrt-v4 does (True) or in plain RGB (False). The same
/// arguments give the same pixels as `lancer render --seed` with the same options, whatever
/// the thread count.
///
/// The GIL is released while rendering; Ctrl-C (or any signal whose Python handler raises)
/// stops the render between units of work (a tile × 16 samples) and raises here
/// (KeyboardInterrupt for Ctrl-C).
///
/// `denoise=True` also renders the albedo and shading normal of the first non-specular
/// surface in the same pass and returns the image denoised by Open Image Denoise's network
/// (as `lancer render --denoise`).
#[pyfunction]
#[pyo3(signature = (scene, spp = None, resolution = None, seed = 0, threads = None, spectral = true, crop = None, denoise = false))]
#[allow(clippy::too_many_arguments)] // the Python signature the issue asks for
pub fn render<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyScene>,
    spp: Option<u32>,
    resolution: Option<Vec<u32>>,
    seed: u64,
    threads: Option<usize>,
    spectral: bool,
    crop: Option<Vec<f32>>,
    denoise: bool,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let this = scene.get();
    let desc = with_overrides(&this.desc, spp, resolution, seed, crop)?;
    let settings = settings_from_desc(&desc, spectral);
    check_film(&settings.bounds)?;
    let film = render_film(py, this, &desc, &settings, threads, denoise)?;
    let Some(g) = &film.gbuffer else {
        return image_array(py, &film, desc.film.scale);
    };
    let bounds = film.bounds;
    let rgb =
        |v: &[lancer::math::Rgb]| v.iter().flat_map(|p| [p.x, p.y, p.z]).collect::<Vec<f32>>();
    let flat = rgb(&film.image(desc.film.scale));
    let (albedo, normal) = g.denoiser_images();
    let (w, h) = (bounds.width() as usize, bounds.height() as usize);
    let (a, n) = (rgb(&albedo), rgb(&normal));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start worker threads: {e}")))?;
    let flat = py
        .detach(|| pool.install(|| lancer_denoise::denoise(&flat, Some(&a), Some(&n), w, h)))
        .map_err(|e| PyRuntimeError::new_err(format!("denoiser: {e}")))?;
    let shape = (bounds.height() as usize, bounds.width() as usize, 3);
    let array = Array3::from_shape_vec(shape, flat)
        .map_err(|e| PyRuntimeError::new_err(format!("image shape: {e}")))?;
    Ok(PyArray3::from_owned_array(py, array))
}

/// Refuses a render of no pixel, or one whose film would not fit in [`MAX_FILM_BYTES`].
pub fn check_film(bounds: &PixelBounds) -> PyResult<()> {
    if bounds.is_empty() {
        return Err(PyValueError::new_err("the crop window selects no pixel"));
    }
    let film_bytes = bounds.area()
        * (std::mem::size_of::<lancer::film::PixelSum>() + std::mem::size_of::<lancer::math::Rgb>())
            as u64;
    if film_bytes > MAX_FILM_BYTES {
        return Err(PyValueError::new_err(format!(
            "a {}x{} image would need {:.1} GiB for its film (more than 16 GiB); render it in \
             parts with crop",
            bounds.width(),
            bounds.height(),
            film_bytes as f64 / (1u64 << 30) as f64
        )));
    }
    Ok(())
}

/// Renders the pixels and samples of `settings` of `desc` (a description of `scene` with a
/// render's overrides) into a fresh film, with the GIL released and Ctrl-C honoured between
/// units of work; warns (`RuntimeWarning`) when samples were not finite. With `denoise` the
/// film also gathers the denoiser's albedo and normal images.
pub fn render_film(
    py: Python<'_>,
    this: &PyScene,
    desc: &SceneDesc,
    settings: &RenderSettings,
    threads: Option<usize>,
    denoise: bool,
) -> PyResult<Film> {
    // sppm's iterations depend on those before them: all of them, in one render (a part by
    // tiles is exact), and no denoiser images (lancer render refuses the same).
    if matches!(settings.integrator, lancer::integrator::Integrator::Sppm(_)) {
        if settings.samples != (0..settings.spp) {
            return Err(PyValueError::new_err(
                "integrator \"sppm\" cannot render a range of samples: each iteration depends \
                 on those before it; split it by tiles",
            ));
        }
        if denoise {
            return Err(PyValueError::new_err(
                "integrator \"sppm\" gathers no albedo and normal images for the denoiser",
            ));
        }
    }
    let bounds = settings.bounds;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start worker threads: {e}")))?;
    let built = py
        .detach(|| pool.install(|| this.built(desc)))
        .map_err(SceneError::new_err)?;

    let mut film = Film::new(desc.film.xresolution, desc.film.yresolution, bounds);
    if denoise {
        let config = GbufferConfig::denoiser(desc.camera.camera_from_world, desc.sampler.spp);
        film.gbuffer = Some(Box::new(GbufferFilm::new(config, bounds.area() as usize)));
    }
    let cancel = AtomicBool::new(false);
    let (done_tx, done_rx) = mpsc::channel::<RenderStats>();
    // Behind a lock so that the waits below, run without the GIL, may borrow it.
    let done_rx = std::sync::Mutex::new(done_rx);
    let wait = |timeout: Option<Duration>| {
        let rx = done_rx.lock().unwrap_or_else(|e| e.into_inner());
        match timeout {
            Some(t) => rx.recv_timeout(t),
            None => rx.recv().map_err(|_| mpsc::RecvTimeoutError::Disconnected),
        }
    };
    let stats = std::thread::scope(|s| -> PyResult<RenderStats> {
        let film = &mut film;
        let (cancel, built, pool) = (&cancel, &built, &pool);
        s.spawn(move || {
            let units = work_units(
                &settings.bounds,
                settings.tile_size,
                settings.samples.clone(),
                SAMPLES_PER_PASS,
            );
            let mut done = vec![false; units.len()];
            let stats = pool.install(|| {
                render_units(RenderJob {
                    stop: &|| cancel.load(Ordering::Relaxed),
                    ..RenderJob::new(built, settings, film, &units, &mut done)
                })
            });
            let _ = done_tx.send(stats);
        });
        // This (Python) thread waits without the GIL, taking it back every SIGNAL_POLL to run
        // Python's signal handlers: an exception from one (KeyboardInterrupt) cancels the
        // render, which stops once the tiles in flight are done.
        loop {
            match py.detach(|| wait(Some(SIGNAL_POLL))) {
                Ok(stats) => return Ok(stats),
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    if let Err(e) = py.check_signals() {
                        cancel.store(true, Ordering::Relaxed);
                        let _ = py.detach(|| wait(None));
                        return Err(e);
                    }
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => {
                    return Err(PyRuntimeError::new_err("the render thread failed"));
                }
            }
        }
    })?;
    if stats.nonfinite > 0 {
        let message = std::ffi::CString::new(format!(
            "{} camera sample(s) gave NaN or infinite radiance and were dropped (`lancer render \
             --check-nan` shows the path of the first)",
            stats.nonfinite
        ))
        .unwrap_or_default();
        PyErr::warn(py, py.get_type::<PyRuntimeWarning>().as_any(), &message, 1)?;
    }
    Ok(film)
}

/// The image of `film` (`film.image(scale)`) as a float32 array (height, width, 3), rows from
/// the top down.
pub fn image_array<'py>(
    py: Python<'py>,
    film: &Film,
    scale: f32,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let bounds = film.bounds;
    let pixels = film.image(scale);
    let flat: Vec<f32> = pixels.iter().flat_map(|p| [p.x, p.y, p.z]).collect();
    let shape = (bounds.height() as usize, bounds.width() as usize, 3);
    let array = Array3::from_shape_vec(shape, flat)
        .map_err(|e| PyRuntimeError::new_err(format!("image shape: {e}")))?;
    Ok(PyArray3::from_owned_array(py, array))
}
