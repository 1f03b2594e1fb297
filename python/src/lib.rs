//! `pathlab._pathlab`: the native half of the Python package. It holds the library's objects
//! (a loaded `Scene`, a progressive `Renderer`, the one device of the process) and turns its
//! results into numpy arrays; `pathlab/__init__.py` checks arguments, builds `Render`s and
//! draws progress. Renders release the GIL and come back to it between frames, to run
//! Python's signal handlers (Ctrl-C stops a render within a dispatch) and the progress callback.
//!
//! - `device`: the one device of the process, and the adapters;
//! - `watch`: signals, progress and cancellation while a render runs without the GIL;
//! - `scene`: `pathlab.Scene` and the keyword overrides;
//! - `render`: `render` and the progressive `NativeRenderer`, films as numpy arrays;
//! - `files`: EXR files;
//! - `metrics`: metrics on arrays, and `compare`;
//! - `study`: the study and the advice.

mod device;
mod files;
mod image_metrics;
mod render;
mod scene;
mod study;
mod watch;

use std::time::Duration;

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use pathlab::method::{BsdfSampling, LightSampling, Sampler};
use pathlab::names::Named;
use pathlab::render::MAX_SPP;

create_exception!(
    _pathlab,
    SceneError,
    PyValueError,
    "A scene file that cannot be read or is invalid; the message is the CLI's `file:line:column: error: ...`."
);
create_exception!(
    _pathlab,
    GpuError,
    PyRuntimeError,
    "No usable GPU adapter (the message says how to install a Vulkan driver), or the device failed."
);
create_exception!(_pathlab, RenderError, PyRuntimeError, "A render, study or file operation that failed.");

/// Samples per pixel when neither `spp`, `time` nor the scene's `render.spp` says (as the CLI).
pub(crate) const DEFAULT_SPP: u64 = 64;
/// Shortest interval between two calls of a progress callback.
pub(crate) const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

pub(crate) fn render_error(e: impl std::fmt::Display) -> PyErr {
    RenderError::new_err(e.to_string())
}

/// The names a method, sampler, BSDF strategy or light strategy may take.
#[pyfunction]
fn names() -> Vec<(String, Vec<String>)> {
    let presets: Vec<String> = pathlab::method::method_names().iter().map(|s| s.to_string()).collect();
    let all = |v: Vec<&'static str>| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    vec![
        ("method".into(), presets),
        ("sampler".into(), all(Sampler::names())),
        ("bsdf".into(), all(BsdfSampling::names())),
        ("lights".into(), all(LightSampling::names())),
    ]
}

#[pymodule]
fn _pathlab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("GpuError", m.py().get_type::<GpuError>())?;
    m.add("RenderError", m.py().get_type::<RenderError>())?;
    m.add("VERSION", pathlab::VERSION)?;
    m.add("MAX_SPP", MAX_SPP)?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<render::NativeRenderer>()?;
    m.add_function(wrap_pyfunction!(scene::load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(render::default_method, m)?)?;
    m.add_function(wrap_pyfunction!(files::write_exr, m)?)?;
    m.add_function(wrap_pyfunction!(files::read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(image_metrics::metric, m)?)?;
    m.add_function(wrap_pyfunction!(image_metrics::compare_json, m)?)?;
    m.add_function(wrap_pyfunction!(image_metrics::to_display, m)?)?;
    m.add_function(wrap_pyfunction!(study::study_json, m)?)?;
    m.add_function(wrap_pyfunction!(study::advise_json, m)?)?;
    m.add_function(wrap_pyfunction!(device::adapters_json, m)?)?;
    m.add_function(wrap_pyfunction!(device::device_info, m)?)?;
    m.add_function(wrap_pyfunction!(names, m)?)?;
    Ok(())
}
