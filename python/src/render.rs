//! Renders: `render` (one `RenderJob`, as `pathlab render`) and the progressive `NativeRenderer`
//! behind `pathlab.Renderer`, their films as numpy arrays.

use std::sync::{Arc, Mutex};
use std::time::Duration;

use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use pathlab::estimate::target::Target;
use pathlab::film::Film;
use pathlab::method::{BsdfSampling, LightSampling, Method, MethodParts, Sampler};
use pathlab::names::Named;
use pathlab::render::{Budget, ErrorPlan, RenderJob, RenderOutcome, RenderStats, Renderer, MAX_SPP};

use crate::device::{device, Device};
use crate::scene::PyScene;
use crate::watch::Watch;
use crate::{render_error, DEFAULT_SPP};

pub(crate) fn choice<T: Named>(argument: &'static str, name: &str) -> PyResult<T> {
    pathlab::names::parse_name::<T>(argument, name).map_err(|e| PyValueError::new_err(format!("{argument}: {e}")))
}

/// The method named `method` (`Method::from_name`, the CLI's parser) with the parts given.
pub(crate) fn method_of(method: &str, sampler: Option<&str>, bsdf: Option<&str>, lights: Option<&str>) -> PyResult<Method> {
    let named = Method::from_name(method).map_err(|e| PyValueError::new_err(format!("method: {e}")))?;
    let parts = MethodParts {
        sampler: sampler.map(|s| choice::<Sampler>("sampler", s)).transpose()?,
        bsdf: bsdf.map(|b| choice::<BsdfSampling>("bsdf", b)).transpose()?,
        lights: lights.map(|l| choice::<LightSampling>("lights", l)).transpose()?,
        ..MethodParts::default()
    };
    Ok(parts.apply(named))
}

/// (H, W, 3) float32 arrays of a film's mean and variance of the mean.
pub(crate) fn film_arrays<'py>(py: Python<'py>, film: &Film) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let shape = [film.height as usize, film.width as usize, 3];
    let flat = |v: &[[f32; 3]]| PyArray1::from_vec(py, v.iter().flatten().copied().collect()).reshape(shape).map(Bound::into_any);
    Ok((flat(&film.mean)?, flat(&film.variance)?))
}

pub(crate) type RenderTuple<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>, u64, f64, u64, Vec<(String, String)>, bool, Option<String>);

/// What `Render` is made of: image, variance, spp, seconds, rays, metadata, interrupted, and
/// the error estimates of a render to a target (JSON).
pub(crate) fn outcome_tuple<'py>(py: Python<'py>, job: &RenderJob, outcome: &RenderOutcome, adapter: &str) -> PyResult<RenderTuple<'py>> {
    let (image, variance) = film_arrays(py, &outcome.film)?;
    let error = outcome.error.as_ref().map(|t| {
        serde_json::json!({
            "rel_mse": t.estimate.rel_mse,
            "psnr": t.estimate.psnr,
            "estimator": t.estimator.describe(),
            "reached": t.reached,
            "checks": t.checks,
            "check_seconds": t.check_seconds,
            "history": t.history.iter().map(|(s, spp, e)| serde_json::json!({"seconds": s, "spp": spp, "rel_mse": e.rel_mse, "psnr": e.psnr})).collect::<Vec<_>>(),
        })
        .to_string()
    });
    Ok((image, variance, outcome.stats.spp, outcome.stats.seconds, outcome.rays, job.metadata(outcome, adapter), outcome.stats.interrupted, error))
}

/// The method a render of `scene` uses when none is named, as every command's
/// (`Scene::default_method_name`: `best`, and `best+env` under an environment map).
#[pyfunction]
pub(crate) fn default_method(scene: &PyScene) -> &'static str {
    scene.scene.default_method_name()
}

/// One render of `scene`, as `pathlab render` does it (one `RenderJob`).
#[pyfunction]
#[pyo3(signature = (scene, method, seed, spp, time, target_rel_error, sampler, bsdf, lights, progress))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn render<'py>(
    py: Python<'py>,
    scene: &PyScene,
    method: &str,
    seed: u32,
    spp: Option<u64>,
    time: Option<f64>,
    target_rel_error: Option<f64>,
    sampler: Option<&str>,
    bsdf: Option<&str>,
    lights: Option<&str>,
    progress: Option<Py<PyAny>>,
) -> PyResult<RenderTuple<'py>> {
    let method = method_of(method, sampler, bsdf, lights)?;
    let s = &scene.scene;
    let budget = match (time, target_rel_error) {
        (Some(t), _) => Budget::Time(Duration::from_secs_f64(t)),
        (None, Some(_)) => Budget::Samples(spp.unwrap_or(MAX_SPP)),
        (None, None) => Budget::Samples(spp.or(s.render.spp).unwrap_or(DEFAULT_SPP)),
    };
    let mut job = RenderJob::new(s.clone(), s.path.clone(), method, seed, budget);
    if let Some(e) = target_rel_error {
        job.error = Some(ErrorPlan { target: Some(Target::RelMse(e)), every: None, display: s.display, check_pixels: None });
    }
    let device = device(py)?;
    // A researcher's technique renders only once proven (README: "Your own technique").
    job.technique_verdict = py.detach(|| pathlab::technique::prove(&device.gpu, s, &method)).map_err(render_error)?;
    let watch = Watch::new(progress);
    let result = py.detach(|| job.run(&device.gpu, &device.pipelines, &watch.cancel, |p| watch.frame(&p, 0, budget)));
    if let Some(e) = watch.take_error() {
        return Err(e);
    }
    let outcome = result.map_err(render_error)?;
    outcome_tuple(py, &job, &outcome, &device.gpu.info.name)
}

/// A progressive render: `add` samples, read the image, add more. The same image, bit for
/// bit, as one render of the same total spp.
#[pyclass(frozen, module = "pathlab._pathlab")]
pub(crate) struct NativeRenderer {
    state: Mutex<RendererState>,
}

pub(crate) struct RendererState {
    renderer: Renderer,
    job: RenderJob,
    device: Arc<Device>,
    /// Seconds of rendering over all `add`s.
    seconds: f64,
}

#[pymethods]
impl NativeRenderer {
    #[new]
    #[pyo3(signature = (scene, method, seed, sampler, bsdf, lights))]
    fn new(py: Python<'_>, scene: &PyScene, method: &str, seed: u32, sampler: Option<&str>, bsdf: Option<&str>, lights: Option<&str>) -> PyResult<NativeRenderer> {
        let method = method_of(method, sampler, bsdf, lights)?;
        let device = device(py)?;
        let s = scene.scene.clone();
        let mut job = RenderJob::new(s.clone(), s.path.clone(), method, seed, Budget::Samples(0));
        job.technique_verdict = py.detach(|| pathlab::technique::prove(&device.gpu, &s, &method)).map_err(render_error)?;
        let renderer = py.detach(|| Renderer::new(&device.gpu, &device.pipelines, &s, method, seed)).map_err(render_error)?;
        Ok(NativeRenderer { state: Mutex::new(RendererState { renderer, job, device, seconds: 0.0 }) })
    }

    /// Adds `spp` samples per pixel; returns the total. Interrupted (Ctrl-C), it keeps the
    /// samples finished so far (the total says how many) and raises KeyboardInterrupt.
    #[pyo3(signature = (spp, progress))]
    fn add(&self, py: Python<'_>, spp: u64, progress: Option<Py<PyAny>>) -> PyResult<u64> {
        let watch = Watch::new(progress);
        let result = py.detach(|| {
            let mut st = self.state.lock().unwrap_or_else(|e| e.into_inner());
            let start = st.renderer.spp();
            let r = st.renderer.render(Budget::Samples(spp), &watch.cancel, |p| watch.frame(&p, start, Budget::Samples(spp)));
            if let Ok(stats) = &r {
                st.seconds += stats.seconds;
            }
            r.map(|stats| stats.spp)
        });
        if let Some(e) = watch.take_error() {
            return Err(e);
        }
        result.map_err(render_error)
    }

    /// Samples per pixel so far.
    #[getter]
    fn spp(&self) -> u64 {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).renderer.spp()
    }

    /// Seconds of rendering over all `add`s.
    #[getter]
    fn seconds(&self) -> f64 {
        self.state.lock().unwrap_or_else(|e| e.into_inner()).seconds
    }

    /// Reads the accumulators back: the parts of a `Render`.
    fn film<'py>(&self, py: Python<'py>) -> PyResult<RenderTuple<'py>> {
        let (readback, st_seconds, job, adapter) = py.detach(|| {
            let st = self.state.lock().unwrap_or_else(|e| e.into_inner());
            (st.renderer.readback(), st.seconds, st.job.clone(), st.device.gpu.info.name.clone())
        });
        let readback = readback.map_err(render_error)?;
        let stats = RenderStats { spp: readback.film.spp, seconds: st_seconds, frames: 0, interrupted: false };
        let outcome = RenderOutcome { film: readback.film, rays: readback.rays, faults: readback.faults, stats, error: None };
        outcome_tuple(py, &job, &outcome, &adapter)
    }
}
