//! lancer's Python module: the native half, `lancer._lancer`, of the package `lancer`
//! (python/lancer wraps it and checks the CPU before loading it).
//!
//! Scenes are loaded from files or text into a [`scene::PyScene`]; [`render::render`] renders
//! one to a float32 numpy array (rows top to bottom) with the GIL released, stopping between
//! tiles when Python has a pending signal (Ctrl-C); images are read and written as lancer does
//! ([`images`]), and compared with the team's metrics ([`metrics`]). [`parts`] renders one part
//! of a split render to its exact sums and merges parts (for `lancer.distributed`), and runs
//! the command line itself (the wheel's `lancer` command). Scene errors are
//! `lancer.SceneError` (a `ValueError`) carrying `file:line:column` as the command line prints
//! them.

mod denoise;
mod images;
mod metrics;
mod parts;
mod render;
mod scene;

use pyo3::prelude::*;

pyo3::create_exception!(
    lancer,
    SceneError,
    pyo3::exceptions::PyValueError,
    "A scene could not be read or built. The message starts with `file:line:column` (as \
     lancer's command line prints it) followed by the offending line and a caret; the attributes \
     `file`, `line` and `column` hold the place, or None when the error has none."
);

pyo3::create_exception!(
    lancer,
    SceneWarning,
    pyo3::exceptions::PyUserWarning,
    "Something a scene asks for that lancer reads but does differently (the message says what \
     it does instead), as `lancer render` prints as `warning:`."
);

/// 1 when this library was compiled for x86-64-v3 (AVX2 and FMA), else 0. The package's
/// `__init__` reads it with ctypes (a data read: no code of this library runs) when the CPU
/// lacks AVX2 or FMA, to refuse the import with advice instead of dying of an illegal
/// instruction.
#[unsafe(no_mangle)]
pub static LANCER_NEEDS_X86_64_V3: u8 =
    if cfg!(all(target_feature = "avx2", target_feature = "fma")) {
        1
    } else {
        0
    };

/// The module `lancer._lancer`.
#[pymodule]
fn _lancer(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("SceneWarning", py.get_type::<SceneWarning>())?;
    m.add_class::<scene::PyScene>()?;
    m.add_function(wrap_pyfunction!(scene::load_file, m)?)?;
    m.add_function(wrap_pyfunction!(scene::load_string, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(denoise::denoise, m)?)?;
    m.add_function(wrap_pyfunction!(parts::render_part, m)?)?;
    m.add_function(wrap_pyfunction!(parts::merge_parts, m)?)?;
    m.add_function(wrap_pyfunction!(parts::cli_main, m)?)?;
    m.add_function(wrap_pyfunction!(images::write_image, m)?)?;
    m.add_function(wrap_pyfunction!(images::read_image, m)?)?;
    m.add_function(wrap_pyfunction!(metrics::mean_rel_error, m)?)?;
    m.add_function(wrap_pyfunction!(metrics::relmse, m)?)?;
    m.add_function(wrap_pyfunction!(metrics::rmse, m)?)?;
    m.add_function(wrap_pyfunction!(metrics::nrmse, m)?)?;
    Ok(())
}
