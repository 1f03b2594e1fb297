//! `pathlab.Scene`: a validated scene, its properties, and the keyword overrides of
//! `load_scene` and `Scene.with_`.

use std::path::PathBuf;

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use pathlab::scene::{Light, Overrides, Scene};

use crate::SceneError;

/// A validated scene: what `pathlab.load_scene` returns. Immutable; `with_` makes a changed copy.
#[pyclass(frozen, name = "Scene", module = "pathlab")]
pub(crate) struct PyScene {
    pub(crate) scene: Scene,
}

pub(crate) fn scene_error(e: pathlab::scene::SceneError) -> PyErr {
    // The exact text the CLI prints: `file:line:column: error: ...` (one line per finding).
    SceneError::new_err(e.to_string())
}

/// A whole number >= 1 given for `key` (a bool is not one).
fn whole(what: &str, key: &str, v: &Bound<'_, PyAny>) -> PyResult<u64> {
    if v.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyTypeError::new_err(format!("{what}: {key} must be an int, not bool")));
    }
    let n = v.extract::<i64>().map_err(|_| PyTypeError::new_err(format!("{what}: {key} must be an int, not {}", type_name(v))))?;
    u64::try_from(n).ok().filter(|&n| n >= 1).ok_or_else(|| PyValueError::new_err(format!("{what}: {key} must be at least 1, not {n}")))
}

fn small(what: &str, key: &str, n: u64) -> PyResult<u32> {
    u32::try_from(n).map_err(|_| PyValueError::new_err(format!("{what}: {key} must be below 2^32, not {n}")))
}

/// `rr_depth` as Python gives it: a scattering vertex >= 1, or None / "off" (no Russian
/// roulette).
pub(crate) fn rr_depth_of(what: &str, v: &Bound<'_, PyAny>) -> PyResult<Option<u32>> {
    if v.is_none() || v.extract::<String>().is_ok_and(|s| s == "off") {
        return Ok(None);
    }
    Ok(Some(small(what, "rr_depth", whole(what, "rr_depth", v)?)?))
}

/// Reads the keyword overrides of `load_scene` and `Scene.with_`; `what` names the call.
pub(crate) fn overrides_of(kwargs: Option<&Bound<'_, PyDict>>, what: &str) -> PyResult<Overrides> {
    let mut o = Overrides::default();
    let Some(kwargs) = kwargs else { return Ok(o) };
    for (key, value) in kwargs.iter() {
        let key: String = key.extract()?;
        let dimension = |v: &Bound<'_, PyAny>| small(what, &key, whole(what, &key, v)?);
        match key.as_str() {
            "width" => o.width = Some(dimension(&value)?),
            "height" => o.height = Some(dimension(&value)?),
            "max_depth" => o.max_depth = Some(dimension(&value)?),
            "spp" => o.spp = Some(whole(what, &key, &value)?),
            "rr_depth" => o.rr_depth = Some(rr_depth_of(what, &value)?),
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

pub(crate) fn type_name(v: &Bound<'_, PyAny>) -> String {
    v.get_type().name().map_or_else(|_| "?".into(), |n| n.to_string())
}

#[pyfunction]
#[pyo3(signature = (path, defines, kwargs=None))]
pub(crate) fn load_scene(py: Python<'_>, path: PathBuf, defines: Vec<(String, String)>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<PyScene> {
    let overrides = overrides_of(kwargs, "load_scene()")?;
    if !defines.is_empty() && !pathlab::scene::is_mitsuba(&path) {
        return Err(PyValueError::new_err(format!("load_scene(): defines are $name values of a Mitsuba XML scene; {} is not one", path.display())));
    }
    let mut scene = py.detach(|| Scene::load_with(&path, &defines)).map_err(scene_error)?;
    let reframing = overrides.apply(&mut scene).map_err(|e| PyValueError::new_err(format!("load_scene(): {e}")))?;
    warn_reframing(py, reframing)?;
    Ok(PyScene { scene })
}

/// Tells, as a `UserWarning` at the caller's line, how a new size changes the framing.
fn warn_reframing(py: Python<'_>, reframing: Option<pathlab::scene::Reframing>) -> PyResult<()> {
    let Some(r) = reframing else { return Ok(()) };
    let message = std::ffi::CString::new(r.to_string()).unwrap_or_default();
    PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyUserWarning>(), &message, 1)
}

pub(crate) fn vec3(v: impl Into<[f64; 3]>) -> (f64, f64, f64) {
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
    /// The participating media: one dict per medium (name, type: homogeneous or heterogeneous,
    /// sigma_t: a constant's value times scale or a grid's file, scale, albedo: a value or a
    /// grid's file, phase, g, bounded_by: the materials whose surfaces bound it, camera: whether
    /// the camera is in it).
    #[getter]
    fn media<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
        let s = &self.scene;
        let mut out = Vec::new();
        for (i, m) in s.media.iter().enumerate() {
            let d = PyDict::new(py);
            d.set_item("name", &m.name)?;
            // A constant coefficient as its value (σ_t times scale), a grid as its file.
            let field = |f: &pathlab::scene::media::Field, scale: f64| -> PyResult<Py<PyAny>> {
                Ok(match f {
                    pathlab::scene::media::Field::Constant(c) => vec3(*c * scale).into_pyobject(py)?.into_any().unbind(),
                    pathlab::scene::media::Field::Grid(g) => g.file.display().to_string().into_pyobject(py)?.into_any().unbind(),
                })
            };
            d.set_item("type", if m.is_heterogeneous() { "heterogeneous" } else { "homogeneous" })?;
            d.set_item("sigma_t", field(&m.sigma_t, if m.sigma_t.constant().is_some() { m.scale } else { 1.0 })?)?;
            d.set_item("scale", m.scale)?;
            d.set_item("albedo", field(&m.albedo, 1.0)?)?;
            let phase = match m.phase {
                pathlab::scene::media::Phase::Isotropic => "isotropic",
                pathlab::scene::media::Phase::HenyeyGreenstein { .. } => "hg",
            };
            d.set_item("phase", phase)?;
            d.set_item("g", m.phase.g())?;
            let bounded: Vec<&str> = s.materials.iter().filter(|t| t.interior == Some(i) || t.exterior == Some(i)).map(|t| t.name.as_str()).collect();
            d.set_item("bounded_by", bounded)?;
            d.set_item("camera", s.camera_medium == Some(i))?;
            out.push(d);
        }
        Ok(out)
    }
    /// The display transform of PNGs and display-referred metrics: (transfer, exposure).
    #[getter]
    fn display(&self) -> (String, f32) {
        (self.scene.display.transfer.to_string(), self.scene.display.exposure)
    }
    /// The emitters: one dict per emissive sphere, per emissive disk or cylinder, per emissive mesh and per point, spot,
    /// directional or projector light, with its radiance (intensity, irradiance) and emitted power
    /// (luminance, the weight of power light selection).
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
                Light::Disk(i) | Light::Cylinder(i) => {
                    let d = PyDict::new(py);
                    let q = &s.quadrics[i];
                    d.set_item("kind", q.kind.name())?;
                    d.set_item("index", i)?;
                    // A disk's centre and normal; a cylinder's p0 and axis.
                    d.set_item("center", vec3(q.to_world.translation))?;
                    if let Light::Disk(_) = light {
                        d.set_item("normal", vec3(q.normal(q.to_world.translation)))?;
                    } else {
                        d.set_item("axis", vec3(q.to_world.matrix3.z_axis))?;
                    }
                    d.set_item("area", q.area())?;
                    d.set_item("emission", vec3(s.materials[q.material].emission))?;
                    d.set_item("two_sided", q.two_sided_emission)?;
                    d.set_item("power", s.light_power(light))?;
                    out.push(d);
                }
                Light::Point(i) => {
                    let d = PyDict::new(py);
                    let l = &s.point_lights[i];
                    d.set_item("kind", "point")?;
                    d.set_item("index", i)?;
                    d.set_item("position", vec3(l.position))?;
                    d.set_item("intensity", vec3(l.intensity))?;
                    d.set_item("power", s.light_power(light))?;
                    out.push(d);
                }
                Light::Spot(i) => {
                    let d = PyDict::new(py);
                    let l = &s.spot_lights[i];
                    d.set_item("kind", "spot")?;
                    d.set_item("index", i)?;
                    d.set_item("position", vec3(l.position))?;
                    d.set_item("direction", vec3(l.direction))?;
                    d.set_item("intensity", vec3(l.intensity))?;
                    d.set_item("cutoff_angle", l.cutoff_angle)?;
                    d.set_item("beam_width", l.beam_width)?;
                    d.set_item("textured", l.texture.is_some())?;
                    d.set_item("power", s.light_power(light))?;
                    out.push(d);
                }
                Light::Directional(i) => {
                    let d = PyDict::new(py);
                    let l = &s.directional_lights[i];
                    d.set_item("kind", "directional")?;
                    d.set_item("index", i)?;
                    d.set_item("direction", vec3(l.direction))?;
                    d.set_item("irradiance", vec3(l.irradiance))?;
                    d.set_item("power", s.light_power(light))?;
                    out.push(d);
                }
                Light::Projector(i) => {
                    let d = PyDict::new(py);
                    let l = &s.projector_lights[i];
                    d.set_item("kind", "projector")?;
                    d.set_item("index", i)?;
                    d.set_item("position", vec3(l.position))?;
                    d.set_item("direction", vec3(l.direction))?;
                    d.set_item("up", vec3(l.up))?;
                    let (w, h) = l.resolution();
                    let (fx, fy) = l.fov.angles(w, h);
                    d.set_item("fov", (fx, fy))?;
                    d.set_item("scale", l.scale)?;
                    d.set_item("power", s.light_power(light))?;
                    out.push(d);
                }
                // `lights()` lists every light but the environment, which is the scene's
                // `environment`.
                Light::Environment => {}
            }
        }
        for (mesh, triangles, power) in mesh_power {
            let d = PyDict::new(py);
            d.set_item("kind", "mesh")?;
            d.set_item("index", mesh)?;
            d.set_item("triangles", triangles)?;
            // The emission's mean where it is a texture (`textured`).
            d.set_item("emission", vec3(s.materials[s.meshes[mesh].material].emission))?;
            d.set_item("textured", s.materials[s.meshes[mesh].material].emission_texture.is_some())?;
            d.set_item("two_sided", s.meshes[mesh].two_sided_emission)?;
            d.set_item("power", power)?;
            out.push(d);
        }
        Ok(out)
    }
    /// A copy with a researcher's technique loaded (`kind`: "bsdf" or "light"; the WGSL file
    /// at `path`), validated by naga; methods use it as `+KIND=NAME`, NAME the file's stem.
    /// `allow_unproven`: used even where it fails its check, its results marked unproven.
    #[pyo3(signature = (kind, path, allow_unproven=false))]
    fn with_technique(&self, kind: &str, path: PathBuf, allow_unproven: bool) -> PyResult<PyScene> {
        let spec = format!("{kind}:{}", path.display());
        let mut t = pathlab::scene::Technique::from_spec(&spec).map_err(|e| PyValueError::new_err(e.to_string()))?;
        t.allow_unproven = allow_unproven;
        pathlab::shaders::validate_technique(&t).map_err(|e| PyValueError::new_err(e.to_string()))?;
        let mut scene = self.scene.clone();
        scene.techniques.retain(|o| o.name != t.name);
        scene.techniques.push(t);
        Ok(PyScene { scene })
    }
    /// The techniques loaded: (kind, name, path, sha256) each.
    #[getter]
    fn techniques(&self) -> Vec<(String, String, String, String)> {
        self.scene.techniques.iter().map(|t| (t.kind.name().to_string(), t.name.to_string(), t.path.display().to_string(), t.sha256.clone())).collect()
    }
    /// A copy with render settings replaced: width, height, max_depth, rr_depth (an int, or
    /// None / "off"), spp.
    #[pyo3(signature = (**kwargs))]
    fn with_(&self, py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<PyScene> {
        let overrides = overrides_of(kwargs, "Scene.with_()")?;
        let mut scene = self.scene.clone();
        let reframing = overrides.apply(&mut scene).map_err(|e| PyValueError::new_err(format!("Scene.with_(): {e}")))?;
        warn_reframing(py, reframing)?;
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
            self.scene.num_lights(),
            self.scene.num_triangles()
        )
    }
}
