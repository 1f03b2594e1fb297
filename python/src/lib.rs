//! `pathlab._pathlab`: the native half of the Python package. It holds the library's objects
//! (a loaded `Scene`, a progressive `Renderer`, the one device of the process) and turns its
//! results into numpy arrays; `pathlab/__init__.py` checks arguments, builds `Render`s and
//! draws progress. Renders release the GIL and come back to it between frames, to run
//! Python's signal handlers (Ctrl-C stops a render within a dispatch) and the progress callback.

use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pathlab::display::{DisplayImage, DisplayTransform, Transfer};
use pathlab::estimate::target::Target;
use pathlab::film::Film;
use pathlab::gpu::{Gpu, PathTracerPipelines};
use pathlab::method::{BsdfSampling, LightSampling, Method, Sampler};
use pathlab::names::Named;
use pathlab::progress::Reporter;
use pathlab::render::{Budget, ErrorPlan, RenderJob, RenderOutcome, RenderStats, Renderer, MAX_SPP};
use pathlab::scene::{Light, Overrides, Scene};
use pathlab::study::{StudyOptions, StudyOutcome};

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
const DEFAULT_SPP: u64 = 64;
/// Shortest interval between two calls of a progress callback.
const PROGRESS_INTERVAL: Duration = Duration::from_millis(100);

fn render_error(e: impl std::fmt::Display) -> PyErr {
    RenderError::new_err(e.to_string())
}

// ---------------------------------------------------------------------------------------------
// The device: one per process, opened at the first render and reused.

struct Device {
    gpu: Gpu,
    pipelines: PathTracerPipelines,
}

static DEVICE: Mutex<Option<Arc<Device>>> = Mutex::new(None);

/// The process's device, opened on first use (a failure is not remembered: installing a
/// driver and calling again works).
fn device(py: Python<'_>) -> PyResult<Arc<Device>> {
    py.detach(|| {
        let mut slot = DEVICE.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(d) = slot.as_ref() {
            return Ok(d.clone());
        }
        let gpu = Gpu::new(None).map_err(|e| GpuError::new_err(e.to_string()))?;
        let pipelines = PathTracerPipelines::new(&gpu.device);
        let d = Arc::new(Device { gpu, pipelines });
        *slot = Some(d.clone());
        Ok(d)
    })
}

/// The adapter a render would use (opening the device if needed): a dict of its details.
#[pyfunction]
fn device_info(py: Python<'_>) -> PyResult<String> {
    let d = device(py)?;
    Ok(adapter_json(&d.gpu.info).to_string())
}

fn adapter_json(info: &wgpu::AdapterInfo) -> serde_json::Value {
    serde_json::json!({
        "name": info.name,
        "device_type": format!("{:?}", info.device_type),
        "backend": format!("{:?}", info.backend),
        "driver": info.driver,
        "driver_info": info.driver_info,
        "summary": pathlab::gpu::adapter_summary(info),
    })
}

/// Every adapter wgpu can see, best first, as JSON.
#[pyfunction]
fn adapters_json(py: Python<'_>) -> String {
    py.detach(|| {
        let list: Vec<serde_json::Value> = pathlab::gpu::list_adapters().iter().map(|a| adapter_json(&a.get_info())).collect();
        serde_json::Value::Array(list).to_string()
    })
}

// ---------------------------------------------------------------------------------------------
// Watching a render from Python: signals, progress, cancellation.

/// Comes back to Python between frames: runs its signal handlers (a KeyboardInterrupt sets
/// `cancel` and is kept to be raised once the device is idle) and calls the progress callback
/// at most every `PROGRESS_INTERVAL`.
struct Watch {
    cancel: AtomicBool,
    error: Mutex<Option<PyErr>>,
    callback: Option<Py<PyAny>>,
    last: Mutex<Option<Instant>>,
}

impl Watch {
    fn new(callback: Option<Py<PyAny>>) -> Watch {
        Watch { cancel: AtomicBool::new(false), error: Mutex::new(None), callback, last: Mutex::new(None) }
    }

    /// Runs Python's signal handlers, then the callback with `(kind, position, total, text)`
    /// if one is due (`force`: always).
    fn poll(&self, force: bool, kind: &'static str, position: f64, total: f64, text: impl FnOnce() -> String) {
        if self.cancel.load(Ordering::Relaxed) {
            return;
        }
        Python::attach(|py| {
            let mut result = py.check_signals();
            if result.is_ok() {
                if let Some(cb) = &self.callback {
                    let mut last = self.last.lock().unwrap_or_else(|e| e.into_inner());
                    if force || last.is_none_or(|t| t.elapsed() >= PROGRESS_INTERVAL) {
                        *last = Some(Instant::now());
                        result = cb.call1(py, (kind, position, total, text())).map(|_| ());
                    }
                }
            }
            if let Err(e) = result {
                *self.error.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                self.cancel.store(true, Ordering::Relaxed);
            }
        });
    }

    /// A render's progress: samples per pixel done of a sample budget, else seconds of a time.
    fn frame(&self, p: &pathlab::render::Progress, spp_base: u64, budget: Budget) {
        let spp = p.spp_done - spp_base;
        match budget {
            Budget::Samples(n) => self.poll(false, "samples", spp as f64, n as f64, || format!("{spp} spp")),
            Budget::Time(t) => self.poll(false, "seconds", p.elapsed.as_secs_f64(), t.as_secs_f64(), || format!("{spp} spp")),
        }
    }

    /// The error a signal handler or the callback raised, if any.
    fn take_error(&self) -> Option<PyErr> {
        self.error.lock().unwrap_or_else(|e| e.into_inner()).take()
    }
}

/// A study's or an advice's progress, told to the Python callback as `(kind, position, text)`.
impl Reporter for Watch {
    fn stage(&self, text: &str) {
        self.poll(true, "stage", 0.0, 0.0, || text.to_string());
    }
    fn note(&self, text: &str) {
        self.poll(true, "note", 0.0, 0.0, || text.to_string());
    }
    fn warn(&self, text: &str) {
        self.poll(true, "warn", 0.0, 0.0, || text.to_string());
    }
    fn begin(&self, task: pathlab::progress::Task) {
        let (kind, total) = match task {
            pathlab::progress::Task::Samples(n) => ("begin-samples", n as f64),
            pathlab::progress::Task::Seconds(s) => ("begin-seconds", s),
            pathlab::progress::Task::Runs(n) => ("begin-runs", n as f64),
        };
        self.poll(true, kind, 0.0, total, String::new);
    }
    fn update(&self, position: f64, message: &str) {
        self.poll(false, "update", position, 0.0, || message.to_string());
    }
    fn end(&self) {
        self.poll(true, "end", 0.0, 0.0, String::new);
    }
}

// ---------------------------------------------------------------------------------------------
// Scenes.

/// A validated scene: what `pathlab.load_scene` returns. Immutable; `with_` makes a changed copy.
#[pyclass(frozen, name = "Scene", module = "pathlab")]
struct PyScene {
    scene: Scene,
}

fn scene_error(e: pathlab::scene::SceneError) -> PyErr {
    // The exact text the CLI prints: `file:line:column: error: ...` (one line per finding).
    SceneError::new_err(e.to_string())
}

/// Reads the keyword overrides of `load_scene` and `Scene.with_`; `what` names the call.
fn overrides_of(kwargs: Option<&Bound<'_, PyDict>>, what: &str) -> PyResult<Overrides> {
    let mut o = Overrides::default();
    let Some(kwargs) = kwargs else { return Ok(o) };
    for (key, value) in kwargs.iter() {
        let key: String = key.extract()?;
        let whole = |v: &Bound<'_, PyAny>| -> PyResult<u64> {
            if v.is_instance_of::<pyo3::types::PyBool>() {
                return Err(PyTypeError::new_err(format!("{what}: {key} must be an int, not bool")));
            }
            v.extract::<i64>().map_err(|_| {
                PyTypeError::new_err(format!("{what}: {key} must be an int, not {}", type_name(v)))
            }).and_then(|n| {
                u64::try_from(n).ok().filter(|&n| n >= 1).ok_or_else(|| PyValueError::new_err(format!("{what}: {key} must be at least 1, not {n}")))
            })
        };
        let small = |n: u64| u32::try_from(n).map_err(|_| PyValueError::new_err(format!("{what}: {key} must be below 2^32, not {n}")));
        match key.as_str() {
            "width" => o.width = Some(small(whole(&value)?)?),
            "height" => o.height = Some(small(whole(&value)?)?),
            "max_depth" => o.max_depth = Some(small(whole(&value)?)?),
            "spp" => o.spp = Some(whole(&value)?),
            "rr_depth" => {
                o.rr_depth = Some(if value.is_none() || value.extract::<String>().is_ok_and(|s| s == "off") {
                    None
                } else {
                    Some(small(whole(&value)?)?)
                })
            }
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "{what} got an unexpected keyword argument '{key}' (it takes width, height, max_depth, rr_depth, spp; \
                     a Mitsuba scene's $name values go in defines={{...}})"
                )))
            }
        }
    }
    Ok(o)
}

fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
}

#[pyfunction]
#[pyo3(signature = (path, defines, kwargs=None))]
fn load_scene(py: Python<'_>, path: PathBuf, defines: Vec<(String, String)>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<PyScene> {
    let overrides = overrides_of(kwargs, "load_scene()")?;
    if !defines.is_empty() && !pathlab::scene::is_mitsuba(&path) {
        return Err(PyValueError::new_err(format!("load_scene(): defines are $name values of a Mitsuba XML scene; {} is not one", path.display())));
    }
    let mut scene = py.detach(|| Scene::load_with(&path, &defines)).map_err(scene_error)?;
    overrides.apply(&mut scene).map_err(|e| PyValueError::new_err(format!("load_scene(): {e}")))?;
    Ok(PyScene { scene })
}

fn vec3(v: impl Into<[f64; 3]>) -> (f64, f64, f64) {
    let [x, y, z] = v.into();
    (x, y, z)
}

#[pymethods]
impl PyScene {
    /// The file the scene was read from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.scene.path.clone()
    }
    #[getter]
    fn width(&self) -> u32 {
        self.scene.render.width
    }
    #[getter]
    fn height(&self) -> u32 {
        self.scene.render.height
    }
    /// (width, height) in pixels.
    #[getter]
    fn size(&self) -> (u32, u32) {
        (self.scene.render.width, self.scene.render.height)
    }
    /// Path segments: 1 = emitters seen directly, 2 = direct lighting, ...
    #[getter]
    fn max_depth(&self) -> u32 {
        self.scene.render.max_depth
    }
    /// Russian roulette from this scattering vertex on, or None.
    #[getter]
    fn rr_depth(&self) -> Option<u32> {
        self.scene.render.rr_depth
    }
    /// The scene's default samples per pixel (`render.spp`), or None.
    #[getter]
    fn spp(&self) -> Option<u64> {
        self.scene.render.spp
    }
    /// The canonical content hash (as `pathlab check` and every EXR header give it).
    #[getter]
    fn hash(&self) -> String {
        self.scene.content_hash()
    }
    #[getter]
    fn num_triangles(&self) -> usize {
        self.scene.num_triangles()
    }
    #[getter]
    fn num_materials(&self) -> usize {
        self.scene.materials.len()
    }
    /// Findings that do not stop rendering, as the CLI prints them.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.scene.warnings.iter().map(ToString::to_string).collect()
    }
    /// The display transform of PNGs and display-referred metrics: (transfer, exposure).
    #[getter]
    fn display(&self) -> (String, f32) {
        (self.scene.display.transfer.to_string(), self.scene.display.exposure)
    }
    /// The emitters: one dict per emissive sphere and per emissive mesh, with its radiance and
    /// emitted power (luminance, the weight of power light selection).
    #[getter]
    fn lights<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let s = &self.scene;
        let mut out = Vec::new();
        let mut mesh_power: Vec<(usize, usize, f64)> = Vec::new();
        for light in s.lights() {
            match light {
                Light::Sphere(i) => {
                    let d = PyDict::new(py);
                    let sphere = &s.spheres[i];
                    d.set_item("kind", "sphere")?;
                    d.set_item("index", i)?;
                    d.set_item("center", vec3(sphere.center))?;
                    d.set_item("radius", sphere.radius)?;
                    d.set_item("emission", vec3(s.materials[sphere.material].emission))?;
                    d.set_item("power", s.light_power(light))?;
                    out.push(d);
                }
                Light::Triangle { mesh, .. } => match mesh_power.last_mut() {
                    Some((m, n, p)) if *m == mesh => {
                        *n += 1;
                        *p += s.light_power(light);
                    }
                    _ => mesh_power.push((mesh, 1, s.light_power(light))),
                },
            }
        }
        for (mesh, triangles, power) in mesh_power {
            let d = PyDict::new(py);
            d.set_item("kind", "mesh")?;
            d.set_item("index", mesh)?;
            d.set_item("triangles", triangles)?;
            d.set_item("emission", vec3(s.materials[s.meshes[mesh].material].emission))?;
            d.set_item("two_sided", s.meshes[mesh].two_sided_emission)?;
            d.set_item("power", power)?;
            out.push(d);
        }
        Ok(out)
    }
    /// A copy with render settings replaced: width, height, max_depth, rr_depth (an int, or
    /// None / "off"), spp.
    #[pyo3(signature = (**kwargs))]
    fn with_(&self, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<PyScene> {
        let overrides = overrides_of(kwargs, "Scene.with_()")?;
        let mut scene = self.scene.clone();
        overrides.apply(&mut scene).map_err(|e| PyValueError::new_err(format!("Scene.with_(): {e}")))?;
        Ok(PyScene { scene })
    }
    fn __repr__(&self) -> String {
        let r = &self.scene.render;
        format!(
            "pathlab.Scene('{}', {}x{}, max_depth={}, rr_depth={}, {} lights, {} triangles)",
            self.scene.path.display(),
            r.width,
            r.height,
            r.max_depth,
            r.rr_depth.map_or("None".into(), |k| k.to_string()),
            self.scene.lights().len(),
            self.scene.num_triangles()
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Methods and renders.

fn choice<T: Named>(argument: &'static str, name: &str) -> PyResult<T> {
    pathlab::names::parse_name::<T>(argument, name).map_err(|e| PyValueError::new_err(format!("{argument}: {e}")))
}

fn method_of(method: &str, sampler: Option<&str>, bsdf: Option<&str>, lights: Option<&str>) -> PyResult<Method> {
    let mut m = Method::from_name(method).map_err(|e| PyValueError::new_err(format!("method: {e}")))?;
    if let Some(s) = sampler {
        m.sampler = choice::<Sampler>("sampler", s)?;
    }
    if let Some(b) = bsdf {
        m.bsdf = choice::<BsdfSampling>("bsdf", b)?;
    }
    if let Some(l) = lights {
        m.lights = choice::<LightSampling>("lights", l)?;
    }
    Ok(m)
}

/// (H, W, 3) float32 arrays of a film's mean and variance of the mean.
fn film_arrays<'py>(py: Python<'py>, film: &Film) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let shape = [film.height as usize, film.width as usize, 3];
    let flat = |v: &[[f32; 3]]| PyArray1::from_vec(py, v.iter().flatten().copied().collect()).reshape(shape).map(Bound::into_any);
    Ok((flat(&film.mean)?, flat(&film.variance)?))
}

type RenderTuple<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>, u64, f64, u64, Vec<(String, String)>, bool, Option<String>);

/// What `Render` is made of: image, variance, spp, seconds, rays, metadata, interrupted, and
/// the error estimates of a render to a target (JSON).
fn outcome_tuple<'py>(py: Python<'py>, job: &RenderJob, outcome: &RenderOutcome, adapter: &str) -> PyResult<RenderTuple<'py>> {
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

/// One render of `scene`, as `pathlab render` does it (one `RenderJob`).
#[pyfunction]
#[pyo3(signature = (scene, method, seed, spp, time, target_rel_error, sampler, bsdf, lights, progress))]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
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
        job.error = Some(ErrorPlan { target: Some(Target::RelMse(e)), every: None, display: s.display });
    }
    let device = device(py)?;
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
struct NativeRenderer {
    state: Mutex<RendererState>,
}

struct RendererState {
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
        let job = RenderJob::new(s.clone(), s.path.clone(), method, seed, Budget::Samples(0));
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

    /// Reads the accumulators back: the parts of a `Render`.
    fn film<'py>(&self, py: Python<'py>) -> PyResult<RenderTuple<'py>> {
        let (readback, st_seconds, job, adapter) = py.detach(|| {
            let st = self.state.lock().unwrap_or_else(|e| e.into_inner());
            (st.renderer.readback(), st.seconds, st.job.clone(), st.device.gpu.info.name.clone())
        });
        let readback = readback.map_err(render_error)?;
        let stats = RenderStats { spp: readback.film.spp, seconds: st_seconds, frames: 0, interrupted: false };
        let outcome = RenderOutcome { film: readback.film, rays: readback.rays, stats, error: None };
        outcome_tuple(py, &job, &outcome, &adapter)
    }
}

// ---------------------------------------------------------------------------------------------
// Files.

/// Writes an EXR atomically with the render's header (`variance`: with variance channels).
#[pyfunction]
#[pyo3(signature = (path, image, variance, spp, metadata))]
fn write_exr(
    py: Python<'_>,
    path: PathBuf,
    image: PyReadonlyArray3<'_, f32>,
    variance: Option<PyReadonlyArray3<'_, f32>>,
    spp: u64,
    metadata: Vec<(String, String)>,
) -> PyResult<()> {
    let film = film_of(&image, variance.as_ref(), spp)?;
    let metadata: Vec<(String, String)> = metadata.into_iter().filter(|(k, _)| k != pathlab::output::CHECKSUM_KEY).collect();
    let with_variance = variance.is_some();
    py.detach(|| pathlab::output::write_exr(&path, &film, &metadata, with_variance)).map_err(render_error)
}

/// Reads an EXR: image, variance (or None), spp and its pathlab metadata.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn read_exr<'py>(py: Python<'py>, path: PathBuf) -> PyResult<(Bound<'py, PyAny>, Option<Bound<'py, PyAny>>, u64, Vec<(String, String)>)> {
    let exr = py.detach(|| pathlab::output::read_exr_image(&path)).map_err(|e| match &e {
        pathlab::output::OutputError::Read { message, .. } if message.contains("No such file") => {
            pyo3::exceptions::PyFileNotFoundError::new_err(e.to_string())
        }
        _ => render_error(e),
    })?;
    let (image, variance) = film_arrays(py, &exr.film)?;
    // The checksum of the file's pixels (checked on reading) is the file's, not the render's.
    let metadata = exr.metadata.into_iter().filter(|(k, _)| k != pathlab::output::CHECKSUM_KEY).collect();
    Ok((image, exr.has_variance.then_some(variance), exr.film.spp, metadata))
}

// ---------------------------------------------------------------------------------------------
// Metrics (arrays checked for dtype and shape by `pathlab/metrics.py`).

fn pixels(a: &PyReadonlyArray3<'_, f32>) -> PyResult<(u32, u32, Vec<[f32; 3]>)> {
    let shape = a.shape();
    if shape[2] != 3 {
        return Err(PyValueError::new_err(format!("expected an (H, W, 3) array, got shape {shape:?}")));
    }
    let slice = a.as_slice().map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((shape[1] as u32, shape[0] as u32, slice.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect()))
}

fn film_of(mean: &PyReadonlyArray3<'_, f32>, variance: Option<&PyReadonlyArray3<'_, f32>>, spp: u64) -> PyResult<Film> {
    let (width, height, mean) = pixels(mean)?;
    let variance = match variance {
        Some(v) => {
            let (w, h, v) = pixels(v)?;
            if (w, h) != (width, height) {
                return Err(PyValueError::new_err(format!("variance is {w}x{h}, the image {width}x{height}")));
            }
            v
        }
        None => vec![[0.0; 3]; mean.len()],
    };
    Ok(Film { width, height, spp, mean, variance })
}

fn transform_of(display: Option<&str>, exposure: f32) -> PyResult<Option<DisplayTransform>> {
    display
        .map(|d| {
            let transfer: Transfer = d.parse().map_err(|e: pathlab::display::TransferParseError| PyValueError::new_err(format!("display: {}", e.0)))?;
            Ok(DisplayTransform { transfer, exposure })
        })
        .transpose()
}

/// A display image: the array as given (`display` None: already display-referred, as
/// scikit-image takes it), or the array through the display transform.
fn display_image(a: &PyReadonlyArray3<'_, f32>, transform: Option<&DisplayTransform>) -> PyResult<DisplayImage> {
    let (width, height, pixels) = pixels(a)?;
    Ok(match transform {
        Some(t) => t.film(&Film { width, height, spp: 0, variance: vec![[0.0; 3]; pixels.len()], mean: pixels }),
        None => DisplayImage { width, height, pixels },
    })
}

/// One metric of `test` against `reference`: psnr, ssim, flip (display-referred), mse,
/// rel_mse (linear).
#[pyfunction]
#[pyo3(signature = (name, test, reference, display, exposure))]
fn metric(name: &str, test: PyReadonlyArray3<'_, f32>, reference: PyReadonlyArray3<'_, f32>, display: Option<&str>, exposure: f32) -> PyResult<f64> {
    if test.shape() != reference.shape() {
        return Err(PyValueError::new_err(format!("test is {:?} and reference {:?}: the shapes differ", test.shape(), reference.shape())));
    }
    let transform = transform_of(display, exposure)?;
    match name {
        "mse" | "rel_mse" => {
            let (t, r) = (film_of(&test, None, 0)?, film_of(&reference, None, 0)?);
            Ok(if name == "mse" { pathlab::metrics::mse(&t, &r) } else { pathlab::metrics::rel_mse(&t, &r) })
        }
        _ => {
            let (t, r) = (display_image(&test, transform.as_ref())?, display_image(&reference, transform.as_ref())?);
            let min = pathlab::metrics::ssim::MIN_SIZE;
            match name {
                "psnr" => Ok(pathlab::metrics::psnr(&r, &t)),
                "ssim" | "flip" if t.width < min || t.height < min => {
                    Err(PyValueError::new_err(format!("{name} needs images of at least {min}x{min} pixels, not {}x{}", t.width, t.height)))
                }
                "ssim" => Ok(pathlab::metrics::ssim(&r, &t)),
                "flip" => Ok(pathlab::metrics::flip(&r, &t)),
                _ => Err(PyValueError::new_err(format!("unknown metric {name}"))),
            }
        }
    }
}

/// Every metric of `pathlab compare --json`, as JSON.
#[pyfunction]
#[pyo3(signature = (test, test_variance, test_spp, reference, reference_variance, reference_spp, display, exposure, block))]
#[allow(clippy::too_many_arguments)]
fn compare_json(
    test: PyReadonlyArray3<'_, f32>,
    test_variance: Option<PyReadonlyArray3<'_, f32>>,
    test_spp: u64,
    reference: PyReadonlyArray3<'_, f32>,
    reference_variance: Option<PyReadonlyArray3<'_, f32>>,
    reference_spp: u64,
    display: &str,
    exposure: f32,
    block: u32,
) -> PyResult<String> {
    let with_variance = test_variance.is_some() && reference_variance.is_some();
    let t = film_of(&test, test_variance.as_ref(), test_spp)?;
    let r = film_of(&reference, reference_variance.as_ref(), reference_spp)?;
    let transform = transform_of(Some(display), exposure)?.expect("a display was given");
    let result = pathlab::metrics::compare_blocks(&t, &r, transform, with_variance, block).map_err(|e| PyValueError::new_err(e.to_string()))?;
    serde_json::to_string(&result).map_err(render_error)
}

// ---------------------------------------------------------------------------------------------
// The study and the advice.

fn opt<'py, T: FromPyObjectOwned<'py>>(options: &Bound<'py, PyDict>, key: &str, what: &str) -> PyResult<Option<T>> {
    match options.get_item(key)? {
        None => Ok(None),
        Some(v) if v.is_none() => Ok(None),
        Some(v) => v.extract::<T>().map(Some).map_err(|_| PyTypeError::new_err(format!("{key} must be {what}, not {}", type_name(&v)))),
    }
}

/// Runs `pathlab study` and returns its `results.json`.
#[pyfunction]
#[pyo3(signature = (scene, out, options, progress))]
fn study_json(py: Python<'_>, scene: &PyScene, out: PathBuf, options: &Bound<'_, PyDict>, progress: Option<Py<PyAny>>) -> PyResult<String> {
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
    let rr_depth = match options.get_item("rr_depth")? {
        None => None,
        Some(v) if v.is_none() || v.extract::<String>().is_ok_and(|s| s == "off") => Some(None),
        Some(v) => Some(Some(v.extract::<u32>().map_err(|_| PyTypeError::new_err("rr_depth must be an int >= 1, None or 'off'"))?)),
    };
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
fn advise_json(
    py: Python<'_>,
    scene: &PyScene,
    methods: Vec<String>,
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

/// The names a method, sampler, BSDF strategy or light strategy may take.
#[pyfunction]
fn names() -> Vec<(String, Vec<String>)> {
    let presets: Vec<String> = pathlab::method::Preset::names().iter().map(|s| s.to_string()).chain(pathlab::method::named_variants().iter().map(|(n, _)| n.to_string())).collect();
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
    m.add_class::<PyScene>()?;
    m.add_class::<NativeRenderer>()?;
    m.add_function(wrap_pyfunction!(load_scene, m)?)?;
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(write_exr, m)?)?;
    m.add_function(wrap_pyfunction!(read_exr, m)?)?;
    m.add_function(wrap_pyfunction!(metric, m)?)?;
    m.add_function(wrap_pyfunction!(compare_json, m)?)?;
    m.add_function(wrap_pyfunction!(study_json, m)?)?;
    m.add_function(wrap_pyfunction!(advise_json, m)?)?;
    m.add_function(wrap_pyfunction!(adapters_json, m)?)?;
    m.add_function(wrap_pyfunction!(device_info, m)?)?;
    m.add_function(wrap_pyfunction!(names, m)?)?;
    Ok(())
}
