//! `pathlab study` and `pathlab advise` from Python, their results as JSON.

use std::path::PathBuf;
use std::time::Duration;

use pyo3::exceptions::{PyKeyboardInterrupt, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pathlab::display::Transfer;
use pathlab::estimate::target::Target;
use pathlab::method::Method;
use pathlab::progress::Reporter as _;
use pathlab::study::{StudyOptions, StudyOutcome};

use crate::device::device;
use crate::image_metrics::transform_of;
use crate::render_error;
use crate::scene::{rr_depth_of, type_name, PyScene};
use crate::watch::Watch;

pub(crate) fn opt<'py, T: FromPyObjectOwned<'py>>(options: &Bound<'py, PyDict>, key: &str, what: &str) -> PyResult<Option<T>> {
    match options.get_item(key)? {
        None => Ok(None),
        Some(v) if v.is_none() => Ok(None),
        Some(v) => v.extract::<T>().map(Some).map_err(|_| PyTypeError::new_err(format!("{key} must be {what}, not {}", type_name(&v)))),
    }
}

/// Runs `pathlab study` and returns its `results.json`.
#[pyfunction]
#[pyo3(signature = (scene, out, options, progress))]
pub(crate) fn study_json(py: Python<'_>, scene: &PyScene, out: PathBuf, options: &Bound<'_, PyDict>, progress: Option<Py<PyAny>>) -> PyResult<String> {
    const KNOWN: [&str; 15] = [
        "methods", "spp", "time", "seeds", "reference", "reference_spp", "reference_method", "size", "max_depth", "rr_depth",
        "display", "target", "regions", "checkpoint_every", "quick",
    ];
    for key in options.keys() {
        let key: String = key.extract()?;
        if !KNOWN.contains(&key.as_str()) {
            return Err(PyTypeError::new_err(format!("study() got an unexpected keyword argument '{key}' (options: {})", KNOWN.join(", "))));
        }
    }
    let rr_depth = options.get_item("rr_depth")?.map(|v| rr_depth_of("study()", &v)).transpose()?;
    let display = opt::<String>(options, "display", "a str such as 'srgb' or 'gamma:2.2'")?
        .map(|d| d.parse::<Transfer>().map_err(|e| PyValueError::new_err(format!("display: {}", e.0))))
        .transpose()?;
    let checkpoint_every = opt::<f64>(options, "checkpoint_every", "a number of seconds")?;
    if checkpoint_every.is_some_and(|s| !(s.is_finite() && s > 0.0)) {
        return Err(PyValueError::new_err("checkpoint_every must be a positive number of seconds"));
    }
    let o = StudyOptions {
        methods: opt::<Vec<String>>(options, "methods", "a list of method names")?,
        spp: opt::<Vec<u64>>(options, "spp", "a list of positive ints")?,
        times: opt::<Vec<f64>>(options, "time", "a list of seconds")?,
        seeds: opt::<u32>(options, "seeds", "an int")?,
        reference: opt::<PathBuf>(options, "reference", "a path")?,
        reference_spp: opt::<u64>(options, "reference_spp", "a positive int")?,
        reference_method: opt::<String>(options, "reference_method", "a method name")?,
        size: opt::<(u32, u32)>(options, "size", "a (width, height) tuple")?,
        max_depth: opt::<u32>(options, "max_depth", "a positive int")?,
        rr_depth,
        display,
        target: opt::<f64>(options, "target", "a relative MSE")?,
        regions: opt::<PathBuf>(options, "regions", "a path")?,
        checkpoint_every: checkpoint_every.map(Duration::from_secs_f64),
        quick: opt::<bool>(options, "quick", "a bool")?.unwrap_or(false),
    };
    let s = &scene.scene;
    let command = format!("pathlab.study({:?}, {:?}, ...) from Python", s.path.display().to_string(), out.display().to_string());
    let study = o.study(s.clone(), s.path.clone(), out.clone(), command).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let loaded = study.validate().map_err(|e| PyValueError::new_err(e.to_string()))?;
    let device = device(py)?;
    // Techniques are proven first; rows of one allowed unproven are marked as the biased
    // demonstrations are.
    let mut study = study;
    for m in study.methods.iter_mut() {
        let verdict = py.detach(|| pathlab::technique::prove(&device.gpu, &study.scene, &m.method)).map_err(crate::render_error)?;
        if verdict.is_some_and(|v| v.starts_with("UNPROVEN")) {
            m.biased = true;
        }
    }
    let watch = Watch::new(progress);
    let result = py.detach(|| study.run(loaded, &device.gpu, &device.pipelines, &watch.cancel, &watch));
    if let Some(e) = watch.take_error() {
        return Err(e);
    }
    match result.map_err(render_error)? {
        StudyOutcome::Finished { .. } => std::fs::read_to_string(out.join("results.json")).map_err(render_error),
        StudyOutcome::Interrupted => Err(PyKeyboardInterrupt::new_err("the study was interrupted; finished steps are kept: call again to continue")),
    }
}

/// Runs `pathlab advise`'s pilots and returns its table (JSON).
#[pyfunction]
#[pyo3(signature = (scene, methods, target_rel_error, target_psnr, pilot_seconds, display, progress))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn advise_json(
    py: Python<'_>,
    scene: &PyScene,
    methods: Option<Vec<String>>,
    target_rel_error: Option<f64>,
    target_psnr: Option<f64>,
    pilot_seconds: f64,
    display: Option<&str>,
    progress: Option<Py<PyAny>>,
) -> PyResult<String> {
    let target = match (target_rel_error, target_psnr) {
        (Some(e), None) => Target::RelMse(e),
        (None, Some(db)) => Target::Psnr(db),
        _ => return Err(PyValueError::new_err("advise(): give target_rel_error or target_psnr (one of them)")),
    };
    // Default: as the CLI's (every preset; under an environment map its strategies too).
    let methods = methods.unwrap_or_else(|| pathlab::study::default_methods(&scene.scene));
    let mut list = Vec::new();
    for name in &methods {
        let m = Method::from_name(name).map_err(|e| PyValueError::new_err(format!("methods: {e}")))?;
        if m.is_biased() {
            return Err(PyValueError::new_err(format!("methods: {name} is a biased demonstration: its error does not fall to any target")));
        }
        list.push(m);
    }
    let s = &scene.scene;
    let transform = transform_of(display, s.display.exposure)?.unwrap_or(s.display);
    let device = device(py)?;
    let watch = Watch::new(progress);
    let result = py.detach(|| {
        watch.stage(&format!("piloting {} methods for {pilot_seconds} s each", list.len()));
        pathlab::advise::advise(&device.gpu, &device.pipelines, s, &list, target, &transform, Duration::from_secs_f64(pilot_seconds), &watch.cancel)
    });
    if let Some(e) = watch.take_error() {
        return Err(e);
    }
    let advice = result.map_err(render_error)?;
    serde_json::to_string(&advice).map_err(render_error)
}

