//! Scenes in Mitsuba 3's XML format, translated into the scene model the TOML format feeds
//! (`raw::RawScene`, then the same validation), so that one scene written both ways is one
//! `Scene` with one content hash.
//!
//! `xml` reads the files into plugin objects (includes, defaults and `$name`, `<ref>`, values
//! and transforms); this module interprets the plugins pathlab supports and refuses, with file,
//! line, column, plugin and parameter, everything else. A setting that pathlab handles
//! differently but whose expected image is Mitsuba's (the pixel filter, the sampler type, ...)
//! is accepted with a warning. The subset and the warnings are listed in the README
//! ("Scenes from Mitsuba").

mod emitters;
mod xml;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};
use toml::Spanned;

use super::diagnostic::{Diagnostic, Findings, Severity, SourceMap};
use super::raw::{
    RawCamera, RawColor, RawCurve, RawCylinder, RawSdfGrid, RawColorOrTexture, RawMaterial, RawMesh, RawRender, RawRotation, RawRotations, RawScale, RawScene, RawShape,
    RawSphere, RawTransform,
};
use super::bsdfs::{color_value, PluginProps, DEFAULT_REFLECTANCE};
use super::spectrum::{Spectrum, SpectrumRole};
use super::{validate, BsdfKind, Fov, Scene, SceneError};
use xml::{describe, compose, Object, OpKind, Prop, TransformOp, Value};

/// Mitsuba's defaults where a file says nothing.
const DEFAULT_FILM_SIZE: (i64, i64) = (768, 576);
/// Mitsuba's default far clip distance, which is also a thin lens's default focus distance.
const MITSUBA_FAR_CLIP: f64 = 1e4;
/// Mitsuba's default `near_clip` (where an orthographic sensor's rays begin).
const MITSUBA_NEAR_CLIP: f64 = 1e-2;
const DEFAULT_MAX_DEPTH: i64 = -1;
const DEFAULT_RR_DEPTH: i64 = 5;

const SHAPES: &str = "obj, ply, serialized, rectangle, cube, sphere, disk, cylinder, linearcurve, bsplinecurve, sdfgrid, shapegroup, instance";

/// The shapes read so far, by the raw scene's tables.
#[derive(Default)]
struct Shapes {
    meshes: Vec<Spanned<RawMesh>>,
    rectangles: Vec<Spanned<RawShape>>,
    cubes: Vec<Spanned<RawShape>>,
    spheres: Vec<Spanned<RawSphere>>,
    disks: Vec<Spanned<RawShape>>,
    cylinders: Vec<Spanned<RawCylinder>>,
    linear_curves: Vec<Spanned<RawCurve>>,
    bspline_curves: Vec<Spanned<RawCurve>>,
    sdf_grids: Vec<Spanned<RawSdfGrid>>,
}

impl Shapes {
    /// How many shapes, of every kind.
    fn len(&self) -> usize {
        self.meshes.len() + self.rectangles.len() + self.cubes.len() + self.spheres.len() + self.disks.len() + self.cylinders.len() + self.linear_curves.len() + self.bspline_curves.len() + self.sdf_grids.len()
    }
}

/// Reads and validates a Mitsuba 3 scene; `defines` override its `<default>`s (`--define`).
pub(super) fn load(path: &Path, defines: &[(String, String)]) -> Result<Scene, SceneError> {
    load_with_raw(path, defines).map(|(scene, _)| scene)
}

/// The validated scene and the translation it was made from (translated once).
fn load_with_raw(path: &Path, defines: &[(String, String)]) -> Result<(Scene, RawScene), SceneError> {
    let (raw, sources, diagnostics, translation) = translate(path, defines)?;
    let mut scene = validate::validate(&raw, path, sources.clone(), diagnostics)?;
    scene.translation = translation;
    // pathlab's sphere lights also emit inwards, Mitsuba's only outwards: the same image only
    // where no path vertex can be inside one.
    if scene.light_interiors_reachable() {
        let light = scene.light_spheres().first().map_or(0, |&i| raw.spheres[i].span().start);
        let d = sources.diagnostic(
            Severity::Error,
            light,
            "sphere".into(),
            "the camera or another object reaches inside an emitting sphere: Mitsuba's sphere emitters emit only \
             outwards, pathlab's also inwards, so the image would differ"
                .into(),
        );
        return Err(SceneError::Invalid(vec![d]));
    }
    Ok((scene, raw))
}

/// The TOML text of a Mitsuba scene (`pathlab convert`): the scene model it is translated into,
/// mesh files named relative to `out_dir` where they lie below it. The scene is validated first.
pub fn to_toml(path: &Path, defines: &[(String, String)], out_dir: &Path) -> Result<(String, Vec<Diagnostic>), SceneError> {
    let (scene, mut raw) = load_with_raw(path, defines)?;
    for f in raw.shape_files_mut() {
        let file = path.parent().unwrap_or(Path::new("")).join(f.get_ref());
        let relative = relative_to(&file, out_dir);
        *f = Spanned::new(f.span(), relative.display().to_string());
    }
    let body = toml::to_string(&raw).map_err(|e| {
        SceneError::Invalid(vec![Diagnostic {
            severity: Severity::Error,
            file: path.to_path_buf(),
            line: 0,
            column: 0,
            field: String::new(),
            message: format!("cannot write the translation as TOML: {e}"),
        }])
    })?;
    let text = format!(
        "# Translated from {} by pathlab {} (`pathlab convert`).\n# Same scene, same content hash: {}\n\n{body}",
        path.display(),
        crate::VERSION,
        scene.content_hash()
    );
    Ok((text, scene.warnings))
}

/// What Mitsuba 3.9.1 refuses in a shape group (`src/render/shapegroup.cpp`: no emitters, groups
/// or instances inside), and, where it stands at the top level (`top`), a group without an id,
/// which no instance could place: (position, field, message) each.
fn shapegroup_problems(o: &Object, top: bool) -> Vec<(usize, String, String)> {
    let mut problems = Vec::new();
    if top && o.id.is_none() {
        problems.push((o.at, "id".into(), "a <shape type=\"shapegroup\"> needs an id, for the <shape type=\"instance\"> that place it".to_string()));
    }
    if let Some(p) = o.props.first() {
        problems.push((p.at, p.name.clone(), format!("`{}` of <shape type=\"shapegroup\"> is not supported (a group places its shapes where its instances' to_world put them)", p.name)));
    }
    for c in &o.children {
        match (c.tag.as_str(), c.plugin.as_str()) {
            ("shape", "shapegroup") => problems.push((c.at, "type".into(), "a shape group inside a shape group is not permitted (as in Mitsuba)".to_string())),
            ("shape", "instance") => problems.push((c.at, "type".into(), "an instance inside a shape group is not permitted (as in Mitsuba)".to_string())),
            ("shape", _) => {
                if let Some(e) = c.children.iter().find(|e| e.tag == "emitter") {
                    problems.push((e.at, "type".into(), "an emitter inside a shape group is not supported (Mitsuba does not instance emitters)".to_string()));
                }
            }
            (tag, plugin) => problems.push((c.at, String::new(), format!("{} inside a shape group is not supported (a group holds shapes)", describe(tag, plugin)))),
        }
    }
    problems
}

/// `file` relative to `dir` when it lies below it (both made absolute first), else as it is.
fn relative_to(file: &Path, dir: &Path) -> PathBuf {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let (file_abs, dir_abs) = (abs(file), abs(dir));
    file_abs.strip_prefix(&dir_abs).map(Path::to_path_buf).unwrap_or(file_abs)
}

fn translate(path: &Path, defines: &[(String, String)]) -> Result<(RawScene, SourceMap, Vec<Diagnostic>, crate::scene::Translation), SceneError> {
    let mut loaded = xml::load(path, defines).map_err(|cause| SceneError::Io { path: path.to_path_buf(), cause })?;
    let diagnostics = std::mem::take(&mut loaded.diagnostics);
    let mut t = Translator {
        sources: &loaded.sources,
        diagnostics,
        materials: BTreeMap::new(),
        material_keys: Vec::new(),
        bsdfs: BTreeMap::new(),
        shape_count: 0,
        instanced: Vec::new(),
        sensor_correction: None,
        media: Vec::new(),
        volumetric: volumetric_integrator(&loaded.objects),
        medium_defs: BTreeMap::new(),
        camera_medium: None,
        loaded: &loaded,
    };
    let mut raw = t.scene(path, &loaded.objects);
    let translation = crate::scene::Translation {
        instancing: (!t.instanced.is_empty()).then(|| crate::scene::Instancing {
            instances: t.instanced.len(),
            groups: t.instanced.iter().map(|(g, _)| g).collect::<std::collections::BTreeSet<_>>().len(),
            shapes: t.instanced.iter().map(|(_, n)| n).sum(),
        }),
        sensor_correction: t.sensor_correction,
    };
    // Mesh, curve and grid files as the scene model names them: relative to the main file's
    // folder (where the validation looks), each found beside the XML file that names it.
    let main_dir = path.parent().unwrap_or(Path::new(""));
    for f in raw.iter_mut().flat_map(RawScene::shape_files_mut) {
        *f = Spanned::new(f.span(), relative_to(Path::new(f.get_ref()), main_dir).display().to_string());
    }
    let mut diagnostics = t.diagnostics;
    if let Some(v) = loaded.version.as_deref().filter(|v| !v.starts_with("3.")) {
        diagnostics.push(Diagnostic {
            severity: Severity::Warning,
            file: path.to_path_buf(),
            line: 0,
            column: 0,
            field: "version".into(),
            message: format!("the file is for Mitsuba {v}: pathlab reads Mitsuba 3's format (parameter names differ between versions)"),
        });
    }
    match raw {
        Some(raw) if !diagnostics.iter().any(|d| d.severity == Severity::Error) => Ok((raw, loaded.sources, diagnostics, translation)),
        _ => {
            diagnostics.sort_by_key(|d| (d.severity != Severity::Error, d.file.clone(), d.line, d.column));
            Err(SceneError::Invalid(diagnostics))
        }
    }
}

/// A BSDF as the TOML material writes it: a kind of the registry (`scene::bsdfs`) with its
/// fields, one- or two-sided.
#[derive(Debug, Clone, PartialEq)]
struct Bsdf {
    kind: BsdfKind,
    fields: Vec<(&'static str, toml::Value)>,
    two_sided: bool,
    /// Its name for the material table: the id, or made up from the shape.
    name: Option<String>,
    /// A `mask`'s opacity as the TOML field's value (`scene::Opacity`): a number, or a texture
    /// table.
    opacity: Option<toml::Value>,
    /// A `normalmap`'s texture as the TOML field's value (`scene::NormalMap`).
    normal_map: Option<toml::Value>,
    /// A `bumpmap`'s texture and scale as the TOML field's value (`scene::BumpMap`).
    bump_map: Option<toml::Value>,
    /// A `twosided`'s second BSDF, which scatters on the back (`Material::back`).
    back: Option<Box<Bsdf>>,
    /// A `blendbsdf`'s second BSDF and its weight as the TOML field's value (`Material::blend`:
    /// a number, or a texture table); this BSDF is its first.
    blend: Option<(Box<Bsdf>, toml::Value)>,
}

impl Bsdf {
    /// Mitsuba's BSDF of a shape without one (`Shape::Shape` in its shape.cpp): `diffuse` with
    /// its default reflectance, or black where the shape emits (an area light reflects nothing
    /// unless given a BSDF).
    fn default_diffuse(emits: bool) -> Bsdf {
        let (reflectance, name) = if emits { (0.0, "default-emitter") } else { (DEFAULT_REFLECTANCE, "default-diffuse") };
        Bsdf { kind: BsdfKind::Phong, fields: vec![("diffuse", color_value([reflectance; 3]))], two_sided: false, name: Some(name.into()), opacity: None, normal_map: None, bump_map: None, back: None, blend: None }
    }
}

/// One plugin object's properties, read by a BSDF kind's `from_mitsuba` through the
/// translator's getters.
/// A medium's coefficient as the file gives it: a value (with a constvolume's to_world), or a
/// grid's TOML texture table.
enum MediumField {
    Value([f64; 3], Option<DMat4>),
    Grid(toml::Table),
}

struct PluginReader<'t, 'a, 'o> {
    t: &'t mut Translator<'a>,
    p: Option<Props>,
    o: &'o Object,
    /// The nested textures taken (`color_or_texture`), by position.
    taken: Vec<usize>,
}

impl PluginReader<'_, '_, '_> {
    fn props(&mut self) -> &mut Props {
        self.p.as_mut().expect("props before finish")
    }
}

impl PluginReader<'_, '_, '_> {
    /// A nested `<texture type="rawconstant">` (Mitsuba's src/spectra/rawconstant.cpp) as its
    /// TOML inline table: `value`, a `<float>` or a `<vector>`, finite, taken as given.
    fn raw_constant(&mut self, t: &Object) -> Option<toml::Value> {
        let mut p = Props::of(t);
        let value = self.t.get::<RawValue>(&mut p, "value");
        self.t.finish(p, "value");
        let Some((RawValue(v), prop)) = value else {
            if !t.props.iter().any(|p| p.name == "value") {
                self.t.error(t.at, "value", "<texture type=\"rawconstant\"> needs its `value` (a <float> or a <vector>)");
            }
            return None;
        };
        if !v.is_finite() {
            self.t.error(prop.value_at, "value", format!("`value` of <texture type=\"rawconstant\"> must be finite (got {v})"));
            return None;
        }
        let mut table = toml::Table::new();
        table.insert("texture".into(), toml::Value::String("rawconstant".into()));
        table.insert("value".into(), toml::Value::Array(v.to_array().iter().map(|x| toml::Value::Float(*x)).collect()));
        Some(toml::Value::Table(table))
    }

    /// A nested `<texture type="mesh_attribute">` (Mitsuba's src/textures/mesh_attribute.cpp) as
    /// its TOML inline table: `name` (starting with `vertex_` or `face_`) and `scale`.
    fn mesh_attribute(&mut self, t: &Object) -> Option<toml::Value> {
        let mut p = Props::of(t);
        let name = self.t.string(&mut p, "name");
        let scale = self.t.get::<f64>(&mut p, "scale");
        self.t.finish(p, "name, scale");
        let Some((name, at)) = name else {
            self.t.error(t.at, "name", "<texture type=\"mesh_attribute\"> needs the attribute's `name` (e.g. \"vertex_color\")");
            return None;
        };
        if !(name.starts_with("vertex_") || name.starts_with("face_")) {
            self.t.error(at, "name", format!("`name` of <texture type=\"mesh_attribute\"> must start with \"vertex_\" or \"face_\" (got \"{name}\"), as Mitsuba requires"));
            return None;
        }
        let mut table = toml::Table::new();
        table.insert("texture".into(), toml::Value::String("mesh_attribute".into()));
        table.insert("name".into(), toml::Value::String(name));
        if let Some((scale, prop)) = scale {
            if !scale.is_finite() {
                self.t.error(prop.value_at, "scale", format!("`scale` of <texture type=\"mesh_attribute\"> must be finite (got {scale})"));
                return None;
            }
            table.insert("scale".into(), toml::Value::Float(scale));
        }
        for c in &t.children {
            self.t.error(c.at, "", format!("{} inside a <texture type=\"mesh_attribute\"> is not supported", describe(&c.tag, &c.plugin)));
        }
        Some(toml::Value::Table(table))
    }

    /// A nested `<texture type="bitmap">` as its TOML inline table, the file found by
    /// Mitsuba's resolver (an error names every folder searched).
    fn bitmap(&mut self, t: &Object) -> Option<toml::Value> {
        let mut p = Props::of(t);
        let mut table = toml::Table::new();
        table.insert("texture".into(), toml::Value::String("bitmap".into()));
        let file = self.t.string(&mut p, "filename");
        self.filter_wrap_flags(&mut p, "bitmap", &["bilinear", "nearest"], &["raw"], &mut table);
        // `to_uv`: Mitsuba 3.9.1 keeps the 2D affine part of the 4x4 transform: rows and
        // columns x, y and the translation (measured: <matrix value="1 2 5 7 3 4 6 8 9 9 9 9 0 0
        // 0 1"/> gives [[1, 2, 7], [3, 4, 8]], and <scale value="2"/><translate value="-.5,
        // -.5, 0"/> gives [[2, 0, -0.5], [0, 2, -0.5]]). Until 2026-12-05 pathlab took the
        // upper-left 3x3, which drops a translation.
        if let Some((ops, _)) = self.t.transform(&mut p, "to_uv") {
            let m = compose(&ops).transpose().to_cols_array_2d();
            let row = |r: usize| toml::Value::Array([0, 1, 3].iter().map(|&c| toml::Value::Float(m[r][c])).collect());
            table.insert("to_uv".into(), toml::Value::Array(vec![row(0), row(1)]));
        }
        // Storage choices without effect on the values: `accel` (CUDA's hardware textures),
        // `format` (Mitsuba's storage precision; pathlab keeps 8-bit images as bytes, others as
        // 32-bit floats).
        let accel = self.t.get::<bool>(&mut p, "accel").is_some();
        let format = self.t.string(&mut p, "format").is_some();
        for (key, given) in [("accel", accel), ("format", format)] {
            if given {
                self.t.warn(t.at, key, format!("`{key}` of a bitmap is a storage choice: pathlab keeps 8-bit images as bytes and others as 32-bit floats"));
            }
        }
        self.t.finish(p, "filename, filter_type, wrap_mode, raw, to_uv, accel, format");
        for c in &t.children {
            self.t.error(c.at, "", format!("{} inside a bitmap <texture> is not supported", describe(&c.tag, &c.plugin)));
        }
        self.with_file(t, file, "<texture type=\"bitmap\">", "image file", table)
    }

    /// A file-backed texture's `filter_type` (one of `filters`), `wrap_mode` (repeat, mirror,
    /// clamp) and boolean `flags` into `table`, a wrong choice refused naming the `plugin`.
    fn filter_wrap_flags(&mut self, p: &mut Props, plugin: &str, filters: &[&str], flags: &[&str], table: &mut toml::Table) {
        for (key, names) in [("filter_type", filters), ("wrap_mode", &["repeat", "mirror", "clamp"][..])] {
            if let Some((v, at)) = self.t.string(p, key) {
                if names.contains(&v.as_str()) {
                    table.insert(key.into(), toml::Value::String(v));
                } else {
                    self.t.error(at, key, format!("`{key}` of a {plugin} must be one of {} (got \"{v}\")", names.join(", ")));
                }
            }
        }
        for &key in flags {
            if let Some((v, _)) = self.t.get::<bool>(p, key) {
                table.insert(key.into(), toml::Value::Boolean(v));
            }
        }
    }

    /// `table` with the `filename` of `o` (an element such as `<texture type="bitmap">`) found by
    /// Mitsuba's resolver (an error names every folder searched), made absolute: the material's
    /// fields resolve a relative name against the main file's folder.
    fn with_file(&mut self, o: &Object, file: Option<(String, usize)>, element: &str, what: &str, mut table: toml::Table) -> Option<toml::Value> {
        let Some((name, _)) = file else {
            self.t.error(o.at, "filename", format!("{element} needs <string name=\"filename\">"));
            return None;
        };
        match self.t.loaded.resolve(&name, &o.dir) {
            Ok(path) => {
                let path = std::path::absolute(&path).unwrap_or(path);
                table.insert("filename".into(), toml::Value::String(path.display().to_string()));
                Some(toml::Value::Table(table))
            }
            Err(message) => {
                self.t.error(o.at, "filename", format!("{what} {message}"));
                None
            }
        }
    }
}

impl PluginReader<'_, '_, '_> {
    /// A nested `<texture type="volume">` around a `<volume type="gridvolume">` as its TOML
    /// inline table, the `.vol` file found by Mitsuba's resolver.
    fn volume(&mut self, t: &Object) -> Option<toml::Value> {
        let mut p = Props::of(t);
        if let Some(prop) = p.take("volume") {
            self.t.error(prop.at, "volume", "a constant volume (a value named `volume`) is not supported: give the value itself instead of a volume texture".to_string());
            return None;
        }
        self.t.finish(p, "a <volume type=\"gridvolume\" name=\"volume\">");
        let is_grid = |c: &Object| c.tag == "volume" && c.name.as_deref().is_none_or(|n| n == "volume");
        let grids: Vec<&Object> = t.children.iter().filter(|c| is_grid(c)).collect();
        for c in t.children.iter().filter(|c| !is_grid(c)) {
            self.t.error(c.at, c.name.as_deref().unwrap_or(""), format!("{} inside a volume <texture> is not supported", describe(&c.tag, &c.plugin)));
        }
        let [g] = grids[..] else {
            self.t.error(t.at, "volume", "<texture type=\"volume\"> needs one <volume type=\"gridvolume\" name=\"volume\">".to_string());
            return None;
        };
        if g.plugin != "gridvolume" && g.plugin != "grid" {
            self.t.error(g.at, "type", format!("<volume type=\"{}\"> is not supported (pathlab has gridvolume)", g.plugin));
            return None;
        }
        self.grid_volume(g)
    }

    /// A `<volume type="gridvolume">` as its TOML inline table (`texture = "volume"`), the
    /// `.vol` file found by Mitsuba's resolver.
    fn grid_volume(&mut self, g: &Object) -> Option<toml::Value> {
        let mut p = Props::of(g);
        let mut table = toml::Table::new();
        table.insert("texture".into(), toml::Value::String("volume".into()));
        let file = self.t.string(&mut p, "filename");
        self.filter_wrap_flags(&mut p, "gridvolume", &["trilinear", "nearest"], &["raw", "use_grid_bbox"], &mut table);
        if let Some((ops, _)) = self.t.transform(&mut p, "to_world") {
            let m = compose(&ops).transpose().to_cols_array_2d();
            let row = |r: usize| toml::Value::Array((0..4).map(|c| toml::Value::Float(m[r][c])).collect());
            table.insert("to_world".into(), toml::Value::Array(vec![row(0), row(1), row(2)]));
        }
        // `accel`: CUDA's hardware interpolation, a storage choice (pathlab interpolates in f32).
        if self.t.get::<bool>(&mut p, "accel").is_some() {
            self.t.warn(g.at, "accel", "`accel` of a gridvolume is a storage choice: pathlab interpolates in 32-bit floats".to_string());
        }
        self.t.finish(p, "filename, filter_type, wrap_mode, raw, use_grid_bbox, to_world, accel");
        for c in &g.children {
            self.t.error(c.at, "", format!("{} inside a gridvolume is not supported", describe(&c.tag, &c.plugin)));
        }
        self.with_file(g, file, "<volume type=\"gridvolume\">", "volume file", table)
    }
}

impl PluginProps for PluginReader<'_, '_, '_> {
    fn plugin(&self) -> &str {
        &self.o.plugin
    }
    fn at(&self) -> usize {
        self.o.at
    }
    fn texture(&self) -> Option<usize> {
        self.o.children.iter().enumerate().find(|(i, c)| c.tag == "texture" && !self.taken.contains(i)).map(|(_, t)| t.at)
    }
    fn has_texture(&self, name: &str) -> bool {
        self.o.children.iter().any(|c| c.tag == "texture" && c.name.as_deref() == Some(name))
    }
    fn has(&self, name: &str) -> bool {
        self.has_texture(name) || self.p.as_ref().is_some_and(|p| p.props.iter().any(|prop| prop.name == name))
    }
    fn color_or_texture(&mut self, name: &str) -> Option<toml::Value> {
        let nested = self.o.children.iter().position(|c| c.tag == "texture" && c.name.as_deref() == Some(name));
        let Some(i) = nested else { return self.color(name).map(color_value) };
        self.taken.push(i);
        let t = &self.o.children[i];
        if t.plugin == "bitmap" {
            return self.bitmap(t);
        }
        if t.plugin == "volume" {
            return self.volume(t);
        }
        if t.plugin == "rawconstant" {
            return self.raw_constant(t);
        }
        if t.plugin == "mesh_attribute" {
            return self.mesh_attribute(t);
        }
        if t.plugin != "checkerboard" {
            self.t.error(t.at, "type", format!("<texture type=\"{}\"> is not supported (pathlab has checkerboard, bitmap, volume, rawconstant, mesh_attribute)", t.plugin));
            return None;
        }
        let mut p = Props::of(t);
        let mut table = toml::Table::new();
        table.insert("texture".into(), toml::Value::String("checkerboard".into()));
        for key in ["color0", "color1"] {
            if let Some(c) = self.t.color(&mut p, key, SpectrumRole::Reflectance) {
                table.insert(key.into(), color_value(c.0));
            }
        }
        // `to_uv`: the 2D affine part of the 4x4 transform, as for a bitmap (Mitsuba 3.9.1's
        // checkerboard.cpp: `to_uv` extracted to a 3x3, applied by transform_affine): rows and
        // columns x, y and the translation. Until 2026-12-05 pathlab read scales alone.
        if let Some((ops, _)) = self.t.transform(&mut p, "to_uv") {
            let m = compose(&ops).transpose().to_cols_array_2d();
            let row = |r: usize| toml::Value::Array([0, 1, 3].iter().map(|&c| toml::Value::Float(m[r][c])).collect());
            table.insert("to_uv".into(), toml::Value::Array(vec![row(0), row(1)]));
        }
        self.t.finish(p, "color0, color1, to_uv");
        for c in &t.children {
            self.t.error(c.at, "", format!("{} inside a <texture> is not supported (give <rgb> colours)", describe(&c.tag, &c.plugin)));
        }
        Some(toml::Value::Table(table))
    }
    fn color(&mut self, name: &str) -> Option<[f64; 3]> {
        let mut p = self.p.take().expect("props before finish");
        let c = self.t.color(&mut p, name, SpectrumRole::Reflectance).map(|c| c.0);
        self.p = Some(p);
        c
    }
    fn unbounded_color(&mut self, name: &str) -> Option<[f64; 3]> {
        let mut p = self.p.take().expect("props before finish");
        let c = self.t.color(&mut p, name, SpectrumRole::Unbounded).map(|c| c.0);
        self.p = Some(p);
        c
    }
    fn float(&mut self, name: &str) -> Option<(f64, usize)> {
        let mut p = self.p.take().expect("props before finish");
        let v = self.t.get::<f64>(&mut p, name).map(|(v, prop)| (v, prop.value_at));
        self.p = Some(p);
        v
    }
    fn string(&mut self, name: &str) -> Option<(String, usize)> {
        let mut p = self.p.take().expect("props before finish");
        let v = self.t.string(&mut p, name);
        self.p = Some(p);
        v
    }
    fn boolean(&mut self, name: &str) -> Option<(bool, usize)> {
        let mut p = self.p.take().expect("props before finish");
        let v = self.t.get::<bool>(&mut p, name).map(|(v, prop)| (v, prop.value_at));
        self.p = Some(p);
        v
    }
    fn float_or_string(&mut self, name: &str) -> Option<(Result<f64, String>, usize)> {
        let mut p = self.p.take().expect("props before finish");
        let v = self.t.get::<FloatOrString>(&mut p, name).map(|(v, prop)| (v.0, prop.value_at));
        self.p = Some(p);
        v
    }
    fn take(&mut self, name: &str) -> Option<usize> {
        self.props().take(name).map(|prop| prop.at)
    }
    fn error(&mut self, at: usize, name: &str, message: String) {
        self.t.error(at, name, message);
    }
    fn warn(&mut self, at: usize, name: &str, message: String) {
        self.t.warn(at, name, message);
    }
    fn finish(&mut self, reads: &str) {
        if let Some(p) = self.p.take() {
            self.t.finish(p, reads);
        }
    }
}

struct Translator<'a> {
    sources: &'a SourceMap,
    diagnostics: Vec<Diagnostic>,
    materials: BTreeMap<String, Spanned<RawMaterial>>,
    /// (BSDF, emission, media) of each material made, for sharing identical ones.
    material_keys: Vec<(String, Bsdf, Option<RawColorOrTexture>, (Option<String>, Option<String>))>,
    /// Named BSDFs already interpreted (a `<ref>` is a copy: interpreted once, reported once).
    bsdfs: BTreeMap<String, Option<Bsdf>>,
    shape_count: usize,
    /// Per instance flattened: its shape group's id and how many shapes it placed.
    instanced: Vec<(String, usize)>,
    /// The sensor matrix's orthonormalisation (`Translation::sensor_correction`).
    sensor_correction: Option<f64>,
    /// Where the file puts `<medium>`s (in shapes, in the sensor, or named at the top level).
    media: Vec<usize>,
    /// A volumetric integrator (`volpath`, `volpathmis`), with where it is: with it media matter.
    volumetric: Option<(String, usize)>,
    /// Media translated (under a volumetric integrator), by name: a top-level medium's id, or
    /// `<shape>-interior` for one nested in a shape.
    medium_defs: BTreeMap<String, Spanned<super::raw::RawMedium>>,
    /// The sensor's medium, by that name.
    camera_medium: Option<Spanned<String>>,
    /// The loaded files, for resolving relative file names (`xml::Loaded::resolve`).
    loaded: &'a xml::Loaded,
}

/// The volumetric integrator (`volpath`, `volpathmis`) among the scene's integrators, nested
/// ones (in `moment`, `aov`) included, with where it is: under it media are rendered.
fn volumetric_integrator(objects: &[Object]) -> Option<(String, usize)> {
    objects.iter().filter(|o| o.tag == "integrator").find_map(|o| {
        if o.plugin == "volpath" || o.plugin == "volpathmis" {
            return Some((o.plugin.clone(), o.at));
        }
        volumetric_integrator(&o.children)
    })
}

fn span(at: usize) -> std::ops::Range<usize> {
    at..at + 1
}

fn spanned<T>(at: usize, v: T) -> Spanned<T> {
    Spanned::new(span(at), v)
}

/// The properties of one object, taken as they are read; what is left at the end is refused.
struct Props {
    tag: String,
    plugin: String,
    props: Vec<Prop>,
}

impl Props {
    fn of(o: &Object) -> Props {
        Props { tag: o.tag.clone(), plugin: o.plugin.clone(), props: o.props.clone() }
    }

    fn what(&self) -> String {
        describe(&self.tag, &self.plugin)
    }

    fn take(&mut self, name: &str) -> Option<Prop> {
        let i = self.props.iter().position(|p| p.name == name)?;
        Some(self.props.remove(i))
    }
}

/// A Rust type a property can be read as (`Translator::get`): the element kinds it accepts,
/// and what the error names otherwise.
trait PropKind: Sized {
    const EXPECTED: &'static str;
    /// The value as `Self`, or the value back where it is another kind.
    fn read(value: Value) -> Result<Self, Value>;
}

/// A colour property before its role is known: an `<rgb>`, a `<float>` for all three channels,
/// or a `<spectrum>` (converted by role, `Translator::color`).
enum ColorValue {
    Rgb([f64; 3]),
    Spectrum(Spectrum),
}

/// A property that is a number or a name (an index of refraction: `<float>` or `<string>`).
struct FloatOrString(Result<f64, String>);

/// A `rawconstant`'s `value`: one number (for all three channels) or a `<vector>`.
struct RawValue(DVec3);

/// `PropKind` for `$t`: the element kinds (patterns of `Value`) it accepts, and the value each
/// gives.
macro_rules! prop_kind {
    ($t:ty, $expected:literal, $($pattern:pat => $value:expr),+ $(,)?) => {
        impl PropKind for $t {
            const EXPECTED: &'static str = $expected;
            fn read(value: Value) -> Result<$t, Value> {
                match value {
                    $($pattern => Ok($value),)+
                    other => Err(other),
                }
            }
        }
    };
}

prop_kind!(f64, "a <float>", Value::Float(v) => v, Value::Integer(v) => v as f64);
prop_kind!(i64, "an <integer>", Value::Integer(v) => v);
prop_kind!(bool, "a <boolean>", Value::Boolean(v) => v);
prop_kind!(String, "a <string>", Value::String(v) => v);
prop_kind!(FloatOrString, "a <float> or a <string>", Value::Float(v) => FloatOrString(Ok(v)), Value::Integer(v) => FloatOrString(Ok(v as f64)), Value::String(v) => FloatOrString(Err(v)));
prop_kind!(ColorValue, "an <rgb>, a <spectrum> or a <float>", Value::Color(c) => ColorValue::Rgb(c), Value::Float(v) => ColorValue::Rgb([v; 3]), Value::Spectrum(s) => ColorValue::Spectrum(s));
prop_kind!(DVec3, "a <point>", Value::Point(v) | Value::Vector(v) => v);
prop_kind!(RawValue, "a <float> or a <vector>", Value::Float(v) => RawValue(DVec3::splat(v)), Value::Integer(v) => RawValue(DVec3::splat(v as f64)), Value::Point(v) | Value::Vector(v) => RawValue(v));
prop_kind!(Vec<TransformOp>, "a <transform>", Value::Transform(ops) => ops);

impl Findings for Translator<'_> {
    fn sources(&self) -> &SourceMap {
        self.sources
    }
    fn findings(&mut self) -> &mut Vec<Diagnostic> {
        &mut self.diagnostics
    }
}

impl Translator<'_> {
    /// Refuses every property not read, naming what pathlab reads instead.
    fn finish(&mut self, p: Props, reads: &str) {
        for prop in p.props {
            self.error(
                prop.at,
                &prop.name,
                format!("`{}` of {} is not supported (pathlab reads: {reads})", prop.name, describe(&p.tag, &p.plugin)),
            );
        }
    }

    fn wrong_kind(&mut self, prop: &Prop, what: &str, expected: &str) {
        self.error(prop.at, &prop.name, format!("`{}` of {what} must be {expected}, not <{}>", prop.name, prop.value.kind()));
    }

    /// The one typed getter: takes property `name` of `p` and reads it as a `T`, refusing
    /// another kind of element with what was expected. Returns the value and the property.
    fn get<T: PropKind>(&mut self, p: &mut Props, name: &str) -> Option<(T, Prop)> {
        let mut prop = p.take(name)?;
        let value = std::mem::replace(&mut prop.value, Value::Boolean(false));
        match T::read(value) {
            Ok(v) => Some((v, prop)),
            Err(value) => {
                prop.value = value;
                let what = p.what();
                self.wrong_kind(&prop, &what, T::EXPECTED);
                None
            }
        }
    }

    fn float(&mut self, p: &mut Props, name: &str) -> Option<f64> {
        self.get::<f64>(p, name).map(|(v, _)| v)
    }

    /// A finite float > 0.
    fn positive(&mut self, p: &mut Props, name: &str) -> Option<(f64, usize)> {
        let (v, prop) = self.get::<f64>(p, name)?;
        if !(v.is_finite() && v > 0.0) {
            let what = p.what();
            self.error(prop.value_at, name, format!("`{name}` of {what} must be a finite number > 0 (got {v})"));
            return None;
        }
        Some((v, prop.value_at))
    }

    fn integer(&mut self, p: &mut Props, name: &str) -> Option<(i64, usize)> {
        self.get::<i64>(p, name).map(|(v, prop)| (v, prop.value_at))
    }

    fn boolean(&mut self, p: &mut Props, name: &str) -> Option<bool> {
        self.get::<bool>(p, name).map(|(v, _)| v)
    }

    fn string(&mut self, p: &mut Props, name: &str) -> Option<(String, usize)> {
        self.get::<String>(p, name).map(|(v, prop)| (v, prop.value_at))
    }

    /// A colour for `role`: finite, non-negative channels. A `<spectrum>` becomes the colour
    /// Mitsuba's RGB variants give it in that role (`scene::spectrum`), with Mitsuba's warning
    /// where it is clamped into the role's gamut.
    fn color(&mut self, p: &mut Props, name: &str, role: SpectrumRole) -> Option<([f64; 3], usize)> {
        let (c, prop) = self.get::<ColorValue>(p, name)?;
        let rgb = match c {
            ColorValue::Rgb(rgb) => rgb,
            ColorValue::Spectrum(Spectrum::Blackbody { .. }) if role != SpectrumRole::Emission => {
                let what = p.what();
                self.error(prop.at, name, format!("`{name}` of {what} cannot be a blackbody: a blackbody is an emission spectrum"));
                return None;
            }
            ColorValue::Spectrum(s) => {
                let converted = s.to_srgb(role);
                if let Some(from) = converted.clamped_from {
                    let range = if role == SpectrumRole::Reflectance { "[0, 1]" } else { ">= 0" };
                    self.warn(prop.value_at, name, format!("the spectrum's colour {from:.4?} lies outside {range}: clamped to {:.4?}, as Mitsuba clamps it", converted.rgb));
                }
                converted.rgb
            }
        };
        if role == SpectrumRole::Unbounded && rgb.iter().all(|v| v.is_finite()) && rgb.iter().any(|v| *v < 0.0) {
            // A conductor's eta or k below 0 (Bitterli's RGB fits have some): Mitsuba accepts
            // them, and its Fresnel term (as pathlab's, fresnel.wgsl) reads eta and k only
            // squared, so their magnitudes give the same term.
            let what = p.what();
            let magnitude = rgb.map(f64::abs);
            self.warn(prop.value_at, name, format!("`{name}` of {what} has channels below 0 ({rgb:?}): the conductor's Fresnel term depends on eta and k squared only, so it is read as {magnitude:?}, the same term Mitsuba computes"));
            return Some((magnitude, prop.value_at));
        }
        if !rgb.iter().all(|v| v.is_finite() && *v >= 0.0) {
            let what = p.what();
            self.error(prop.value_at, name, format!("`{name}` of {what} must be finite and >= 0 in every channel (got {rgb:?})"));
            return None;
        }
        Some((rgb, prop.value_at))
    }

    fn point(&mut self, p: &mut Props, name: &str) -> Option<DVec3> {
        let (v, prop) = self.get::<DVec3>(p, name)?;
        if !v.is_finite() {
            self.error(prop.value_at, name, format!("`{name}` must be finite"));
            return None;
        }
        Some(v)
    }

    fn transform(&mut self, p: &mut Props, name: &str) -> Option<(Vec<TransformOp>, usize)> {
        self.get::<Vec<TransformOp>>(p, name).map(|(ops, prop)| (ops, prop.at))
    }

    /// `<emitter type="envmap">`: `filename` (found by Mitsuba's resolver), `scale`, `to_world`.
    fn envmap(&mut self, o: &Object) -> Option<Spanned<super::raw::RawEnvironmentMap>> {
        let mut p = Props::of(o);
        let file = self.string(&mut p, "filename");
        let scale = self.get::<f64>(&mut p, "scale").map(|(v, prop)| spanned(prop.value_at, v));
        let to_world = self.transform(&mut p, "to_world");
        self.finish(p, "filename, scale, to_world");
        let transform = match &to_world {
            Some((ops, at)) => self.raw_transform(ops, *at),
            None => None,
        };
        let Some((name, at)) = file else {
            self.error(o.at, "filename", "<emitter type=\"envmap\"> needs <string name=\"filename\">".to_string());
            return None;
        };
        match self.loaded.resolve(&name, &o.dir) {
            Ok(path) => {
                let path = std::path::absolute(&path).unwrap_or(path);
                Some(spanned(o.at, super::raw::RawEnvironmentMap { filename: spanned(at, path.display().to_string()), scale, transform }))
            }
            Err(message) => {
                self.error(at, "filename", format!("image file {message}"));
                None
            }
        }
    }

    fn scene(&mut self, path: &Path, objects: &[Object]) -> Option<RawScene> {
        let mut camera = None;
        let mut film = (DEFAULT_FILM_SIZE.0, DEFAULT_FILM_SIZE.1, 0usize);
        let mut spp = None;
        let mut depth = (DEFAULT_MAX_DEPTH, DEFAULT_RR_DEPTH, 0usize, None);
        let mut environment: Option<([f64; 3], usize)> = None;
        let mut environment_map = None;
        let mut shapes = Shapes::default();
        let (mut point_lights, mut spot_lights, mut directional_lights, mut projector_lights) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut sensors = 0;
        let mut integrators = 0;
        for o in objects {
            match o.tag.as_str() {
                "sensor" => {
                    sensors += 1;
                    if sensors > 1 {
                        self.error(o.at, "", "a second <sensor>: pathlab renders one camera");
                        continue;
                    }
                    let (c, f, s) = self.sensor(o);
                    camera = c;
                    film = f;
                    spp = s;
                }
                "integrator" => {
                    integrators += 1;
                    if integrators > 1 {
                        self.error(o.at, "", "a second <integrator>");
                        continue;
                    }
                    depth = self.integrator(o);
                }
                "bsdf" => {
                    self.bsdf(o);
                }
                "shape" => self.shape(o, &mut shapes),
                "emitter" => match o.plugin.as_str() {
                    "constant" => {
                        let mut p = Props::of(o);
                        let radiance = self.color(&mut p, "radiance", SpectrumRole::Emission);
                        self.finish(p, "radiance");
                        if environment.is_some() || environment_map.is_some() {
                            self.error(o.at, "", "a second infinite emitter (pathlab has one environment: constant or envmap)");
                        }
                        // Mitsuba's default radiance is 1.
                        environment = Some(radiance.unwrap_or(([1.0; 3], o.at)));
                    }
                    "envmap" => {
                        if environment.is_some() || environment_map.is_some() {
                            self.error(o.at, "", "a second infinite emitter (pathlab has one environment: constant or envmap)".to_string());
                        }
                        environment_map = self.envmap(o);
                    }
                    // A named one is a definition that shapes take by <ref> (Mitsuba's cbox-rgb).
                    "area" if o.id.is_some() => {}
                    "area" => self.error(o.at, "", "<emitter type=\"area\"> belongs inside the <shape> that emits (or, with an id, is taken by a <ref> in one)"),
                    "point" => point_lights.extend(self.point_emitter(o)),
                    "spot" => spot_lights.extend(self.spot_emitter(o)),
                    "directional" => directional_lights.extend(self.directional_emitter(o)),
                    "projector" => projector_lights.extend(self.projector_emitter(o)),
                    other => self.error(o.at, "type", format!("<emitter type=\"{other}\"> is not supported (pathlab has area, constant, envmap, point, spot, directional, projector)")),
                },
                // A named texture is a definition that BSDFs take by <ref name="…" id="…"/>.
                "texture" if o.id.is_some() => {}
                "texture" => self.error(o.at, "", "a <texture> outside a <bsdf> needs an id, for a <ref name=\"…\" id=\"…\"/> in one".to_string()),
                // A named one is a definition that a sensor (or film) takes by <ref id="…"/>
                // (mitsuba-data's sampler documentation scenes).
                "film" | "sampler" | "rfilter" if o.id.is_some() => {}
                "film" | "sampler" | "rfilter" => self.error(o.at, "", format!("<{}> belongs inside the <sensor> (or, with an id, is taken by a <ref> in it)", o.tag)),
                // A named medium is a definition that shapes take by <ref name="interior" …/>.
                "medium" if self.volumetric.is_some() && o.id.is_some() => {}
                "medium" if self.volumetric.is_some() => self.error(o.at, "", "a <medium> outside a <shape> or <sensor> needs an id, for a <ref name=\"interior\" id=\"…\"/> in one"),
                "medium" => self.media.push(o.at),
                other => self.error(o.at, "", format!("{} is not supported at the top level of a scene", describe(other, &o.plugin))),
            }
        }
        self.check_media();
        let Some((camera, _)) = camera else {
            if sensors == 0 && !self.has_errors() {
                let at = objects.first().map_or(0, |o| o.at);
                self.error(at, "sensor", format!("{} has no <sensor type=\"perspective\">", path.display()));
            }
            return None;
        };
        let (max_depth, rr, depth_at, hide_emitters) = depth;
        // Roulette that never acts (from a vertex at or beyond the last) is none.
        let rr_depth = (max_depth == -1 || rr < max_depth).then_some(rr);
        Some(RawScene {
            techniques: None,
            camera: spanned(0, camera),
            render: spanned(
                depth_at,
                RawRender {
                    width: spanned(film.2, film.0),
                    height: spanned(film.2, film.1),
                    max_depth: spanned(depth_at, max_depth),
                    rr_depth: rr_depth.map(|r| spanned(depth_at, r)),
                    environment: environment.map(|(c, at)| spanned(at, RawColor(c))),
                    spp: spp.map(|(s, at)| spanned(at, s)),
                    hide_emitters: hide_emitters.filter(|(hide, _)| *hide).map(|(hide, at)| spanned(at, hide)),
                },
            ),
            materials: std::mem::take(&mut self.materials),
            environment_map,
            spheres: shapes.spheres,
            planes: Vec::new(),
            display: None,
            meshes: shapes.meshes,
            rectangles: shapes.rectangles,
            cubes: shapes.cubes,
            disks: shapes.disks,
            cylinders: shapes.cylinders,
            linear_curves: shapes.linear_curves,
            bspline_curves: shapes.bspline_curves,
            sdf_grids: shapes.sdf_grids,
            point_lights,
            spot_lights,
            directional_lights,
            projector_lights,
            media: std::mem::take(&mut self.medium_defs),
        })
    }

    /// Participating media under `path`: Mitsuba's `path` integrator ignores them (its image is
    /// the same without them; checked with Mitsuba 3.9.1), so pathlab does too and says so.
    /// Under `volpath` they are read where shapes and the sensor take them (`medium`).
    fn check_media(&mut self) {
        let mut media = std::mem::take(&mut self.media);
        // A medium taken by several <ref>s is reported once, where it is defined. Under a
        // volumetric integrator media are translated where they are taken (`medium`), and
        // none is listed here.
        media.sort_unstable();
        media.dedup();
        for at in media {
            self.warn(at, "", "<medium> is ignored, as Mitsuba's `path` integrator ignores participating media (the image is the same)");
        }
    }

    /// A `<medium>` (nested, or a top-level definition copied by a `<ref>`) under a volumetric
    /// integrator: Mitsuba's `homogeneous` or `heterogeneous` with its `sigma_t` (times
    /// `scale`), `albedo` (values, or `<volume>`s: `constvolume`, `gridvolume`) and phase
    /// function (`isotropic`, `hg`), translated once per id; its name, or `None` where it is
    /// refused. `fallback` names a nested one.
    fn medium(&mut self, o: &Object, fallback: &str) -> Option<String> {
        let name = o.id.clone().unwrap_or_else(|| fallback.to_string());
        if self.medium_defs.contains_key(&name) {
            return Some(name);
        }
        let heterogeneous = match o.plugin.as_str() {
            "homogeneous" => false,
            "heterogeneous" => true,
            _ => {
                self.error(o.at, "type", format!("{} is not supported (pathlab has homogeneous and heterogeneous media)", describe(&o.tag, &o.plugin)));
                return None;
            }
        };
        let mut p = Props::of(o);
        // Mitsuba's defaults (homogeneous.cpp, heterogeneous.cpp): sigma_t 1, albedo 0.75,
        // scale 1; a value given as a property is a constvolume of identity to_world.
        let sigma_t = self.color(&mut p, "sigma_t", SpectrumRole::Unbounded).map(|(c, _)| MediumField::Value(c, None));
        let albedo = self.color(&mut p, "albedo", SpectrumRole::Reflectance).map(|(c, _)| MediumField::Value(c, None));
        let scale = match self.get::<f64>(&mut p, "scale") {
            Some((v, _)) if v.is_finite() && v >= 0.0 => v,
            Some((v, prop)) => {
                self.error(prop.value_at, "scale", format!("`scale` of a medium must be a finite number >= 0 (got {v})"));
                1.0
            }
            None => 1.0,
        };
        if let Some((false, prop)) = self.get::<bool>(&mut p, "sample_emitters") {
            self.warn(prop.value_at, "sample_emitters", "`sample_emitters` = false is ignored: pathlab samples the lights from every vertex in a medium where the method samples lights (the image's expectation is the same; only its noise differs)");
        }
        let spectral_extinction = self.get::<bool>(&mut p, "has_spectral_extinction");
        self.finish(p, "sigma_t, albedo, scale, sample_emitters, has_spectral_extinction");
        let (mut sigma_t, mut albedo) = (sigma_t, albedo);
        let mut phase = None;
        let mut g = None;
        for c in &o.children {
            match (c.tag.as_str(), c.plugin.as_str()) {
                ("phase", "isotropic") => {
                    phase = Some("isotropic");
                    self.finish(Props::of(c), "no parameters");
                }
                ("phase", "hg") => {
                    let mut pp = Props::of(c);
                    // Mitsuba's default g (hg.cpp): 0.8.
                    g = Some(self.get::<f64>(&mut pp, "g").map_or((0.8, c.at), |(v, prop)| (v, prop.value_at)));
                    phase = Some("hg");
                    self.finish(pp, "g");
                }
                ("phase", other) => self.error(c.at, "type", format!("<phase type=\"{other}\"> is not supported (pathlab has isotropic, hg)")),
                ("volume", _) if matches!(c.name.as_deref(), Some("sigma_t" | "albedo")) => {
                    let role = if c.name.as_deref() == Some("albedo") { SpectrumRole::Reflectance } else { SpectrumRole::Unbounded };
                    let field = self.medium_volume(c, role);
                    if c.name.as_deref() == Some("albedo") {
                        albedo = field;
                    } else {
                        sigma_t = field;
                    }
                }
                ("volume", _) => self.error(c.at, "name", format!("a <volume> in a <medium> is its `sigma_t` or `albedo` (got name {:?})", c.name)),
                (other, plugin) => self.error(c.at, "", format!("{} inside a <medium> is not supported", describe(other, plugin))),
            }
        }
        let sigma_t = sigma_t.unwrap_or(MediumField::Value([1.0; 3], None));
        let coloured = match &sigma_t {
            MediumField::Value(c, _) => c[0] != c[1] || c[1] != c[2],
            MediumField::Grid(_) => true,
        };
        if let Some((false, prop)) = spectral_extinction.filter(|_| coloured) {
            self.warn(prop.value_at, "has_spectral_extinction", "`has_spectral_extinction` = false with a coloured `sigma_t`: Mitsuba then weighs scattering by the albedo alone, which is biased; pathlab renders the medium as given");
        }
        let (sigma_t, scale, bounds) = match (heterogeneous, sigma_t) {
            // A homogeneous medium's sigma_t is one value (homogeneous.cpp evaluates it at no
            // particular point), its scale folded in; a constvolume's box does not matter.
            (false, MediumField::Value(c, _)) => (RawColorOrTexture::Color(RawColor(c.map(|v| v * scale))), None, None),
            (false, MediumField::Grid(_)) => {
                self.error(o.at, "sigma_t", "a homogeneous medium's sigma_t is one value everywhere: a <volume type=\"gridvolume\"> needs <medium type=\"heterogeneous\">");
                return None;
            }
            // A heterogeneous medium fills its sigma_t volume's box: a constvolume's is its
            // to_world's unit cube (volume.h, update_bbox).
            (true, MediumField::Value(c, to_world)) => {
                let [lo, hi] = crate::scene::media::unit_cube_bounds(to_world.unwrap_or(DMat4::IDENTITY));
                (RawColorOrTexture::Color(RawColor(c)), Some(scale), Some(spanned(o.at, [lo.to_array(), hi.to_array()])))
            }
            (true, MediumField::Grid(table)) => (RawColorOrTexture::Texture(table), Some(scale), None),
        };
        let albedo = albedo.map(|a| match a {
            MediumField::Value(c, _) => spanned(o.at, RawColorOrTexture::Color(RawColor(c))),
            MediumField::Grid(table) => spanned(o.at, RawColorOrTexture::Texture(table)),
        });
        let raw = super::raw::RawMedium {
            kind: heterogeneous.then(|| spanned(o.at, "heterogeneous".to_string())),
            sigma_t: spanned(o.at, sigma_t),
            scale: scale.map(|s| spanned(o.at, s)),
            albedo,
            bounds,
            phase: phase.map(|ph| spanned(o.at, ph.to_string())),
            g: g.map(|(v, at)| spanned(at, v)),
        };
        self.medium_defs.insert(name.clone(), spanned(o.at, raw));
        Some(name)
    }

    /// A medium's `<volume name="sigma_t">` or `<volume name="albedo">`: a `constvolume`'s value
    /// (and its to_world, which bounds a heterogeneous medium), or a `gridvolume` as its TOML
    /// texture table; `None` where refused.
    fn medium_volume(&mut self, v: &Object, role: SpectrumRole) -> Option<MediumField> {
        match v.plugin.as_str() {
            "constvolume" | "const" => {
                let mut p = Props::of(v);
                // constvolume.cpp: value default 1.
                let value = self.color(&mut p, "value", role).map_or([1.0; 3], |(c, _)| c);
                let to_world = self.transform(&mut p, "to_world").map(|(ops, _)| compose(&ops));
                self.finish(p, "value, to_world");
                for c in &v.children {
                    self.error(c.at, "", format!("{} inside a constvolume is not supported (give `value` as an <rgb> or <float>)", describe(&c.tag, &c.plugin)));
                }
                Some(MediumField::Value(value, to_world))
            }
            "gridvolume" | "grid" => {
                let mut reader = PluginReader { t: self, p: None, o: v, taken: Vec::new() };
                match reader.grid_volume(v)? {
                    toml::Value::Table(t) => Some(MediumField::Grid(t)),
                    _ => None,
                }
            }
            other => {
                self.error(v.at, "type", format!("<volume type=\"{other}\"> is not supported (pathlab has constvolume, gridvolume)"));
                None
            }
        }
    }

    fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(|d| d.severity == Severity::Error)
    }

    /// `<sensor type="perspective">` (or `thinlens`, `orthographic`): the camera, the film size
    /// and the sample count.
    fn sensor(&mut self, o: &Object) -> (Option<(RawCamera, usize)>, (i64, i64, usize), Option<(i64, usize)>) {
        let mut film = (DEFAULT_FILM_SIZE.0, DEFAULT_FILM_SIZE.1, o.at);
        let mut spp = None;
        if !["perspective", "thinlens", "orthographic"].contains(&o.plugin.as_str()) {
            self.error(o.at, "type", format!("{} is not supported (pathlab has perspective, thinlens, orthographic)", describe(&o.tag, &o.plugin)));
            return (None, film, spp);
        }
        let thin_lens = o.plugin == "thinlens";
        for child in &o.children {
            match child.tag.as_str() {
                "film" => film = self.film(child),
                "sampler" => spp = self.sampler(child),
                "medium" if self.volumetric.is_some() => self.camera_medium = self.medium(child, "sensor-medium").map(|n| spanned(child.at, n)),
                "medium" => self.media.push(child.at),
                other => self.error(child.at, "", format!("{} inside a <sensor> is not supported", describe(other, &child.plugin))),
            }
        }
        let mut p = Props::of(o);
        if o.plugin == "orthographic" {
            return (self.orthographic(o, p), film, spp);
        }
        let fov = self.field_of_view(o, &mut p);
        // A thin lens: `aperture_radius` (required, as Mitsuba) and `focus_distance` (Mitsuba's
        // default: far_clip, 1e4 unless given).
        let mut lens = (None, None);
        if thin_lens {
            lens.0 = match self.get::<f64>(&mut p, "aperture_radius") {
                Some((v, prop)) if v.is_finite() && v >= 0.0 => Some(spanned(prop.value_at, v)),
                Some((v, prop)) => {
                    self.error(prop.value_at, "aperture_radius", format!("`aperture_radius` must be a finite number >= 0 (got {v})"));
                    None
                }
                None => {
                    self.error(o.at, "aperture_radius", "<sensor type=\"thinlens\"> needs <float name=\"aperture_radius\">".to_string());
                    None
                }
            };
            lens.1 = self.get::<f64>(&mut p, "focus_distance").map(|(v, prop)| spanned(prop.value_at, v));
        } else if let Some(prop) = p.take("focus_distance") {
            self.warn(prop.at, "focus_distance", "`focus_distance` is ignored: a perspective camera is a pinhole, in focus everywhere (the image is the same)".to_string());
        }
        for clip in ["near_clip", "far_clip"] {
            let value = p.props.iter().find(|q| q.name == clip).and_then(|q| match q.value {
                Value::Float(v) => Some(v),
                Value::Integer(v) => Some(v as f64),
                _ => None,
            });
            if let Some(prop) = p.take(clip) {
                if clip == "far_clip" && thin_lens && lens.1.is_none() {
                    // Mitsuba's focus distance defaults to the far clip distance.
                    lens.1 = value.map(|v| spanned(prop.value_at, v));
                }
                self.warn(prop.at, clip, format!("`{clip}` is ignored: pathlab does not clip (the image differs only where geometry lies outside the clip range)"));
            }
        }
        if thin_lens && lens.1.is_none() {
            lens.1 = Some(spanned(o.at, MITSUBA_FAR_CLIP));
        }
        for offset in ["principal_point_offset_x", "principal_point_offset_y"] {
            if let Some(prop) = p.take(offset) {
                if prop.value != Value::Float(0.0) {
                    self.error(prop.at, offset, format!("`{offset}` is not supported (pathlab's principal point is the image centre)"));
                }
            }
        }
        let to_world = self.transform(&mut p, "to_world");
        self.finish(
            p,
            if thin_lens { "fov, fov_axis, focal_length, to_world, aperture_radius, focus_distance, near_clip, far_clip" } else { "fov, fov_axis, focal_length, to_world, near_clip, far_clip (and, with a warning, focus_distance)" },
        );
        let Some((fov, fov_at)) = fov else { return (None, film, spp) };
        let given = |f: Fov, key: &str| (f.key() == key).then(|| spanned(fov_at, f.degrees()));
        let (position, look_at, up) = match to_world {
            None => (DVec3::ZERO, DVec3::Z, DVec3::Y),
            // A look-at alone is kept as written.
            Some((ops, _)) if matches!(ops.as_slice(), [TransformOp { kind: OpKind::LookAt { .. }, .. }]) => {
                let OpKind::LookAt { origin, target, up } = ops[0].kind else { unreachable!() };
                (origin, target, up)
            }
            Some((ops, at)) => {
                let m = compose(&ops);
                let position = m.w_axis.truncate();
                let (left, up, dir) = (m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate());
                // Orthogonal to 1e-4 (Bitterli's scenes write rotations to 6 digits, whose axes'
                // products reach 2e-5; the camera built from position, direction and up then
                // differs from Mitsuba's by less than 1e-4 rad).
                let orthogonal = [left.dot(up), up.dot(dir), dir.dot(left)].iter().all(|d| d.abs() <= 1e-4 * left.length() * dir.length().max(up.length()));
                if !m.is_finite() || dir.length() == 0.0 || up.length() == 0.0 || !orthogonal {
                    self.error(at, "to_world", "the sensor's to_world must be a rotation and translation (with at most a uniform scale)");
                } else if left.dot(up.cross(dir)) <= 0.0 {
                    self.error(at, "to_world", "the sensor's to_world mirrors the image, which pathlab's camera cannot");
                } else if (left.length() - dir.length()).abs() > 1e-4 * dir.length() || (up.length() - dir.length()).abs() > 1e-4 * dir.length() {
                    // Mitsuba normalises to_world times the image plane's point: scaling the
                    // axes unequally changes the field of view, which pathlab would not see.
                    self.error(at, "to_world", format!("the sensor's to_world scales its axes unequally ({}, {}, {}), which changes the field of view; give a rotation and translation (with at most a uniform scale)", left.length(), up.length(), dir.length()));
                } else {
                    self.note_sensor_correction(up, left, dir);
                }
                (position, position + dir.normalize(), up.normalize())
            }
        };
        let camera = RawCamera {
            position: spanned(o.at, position.to_array()),
            look_at: spanned(o.at, look_at.to_array()),
            up: spanned(o.at, up.to_array()),
            fov_x: given(fov, "fov_x"),
            fov_y: given(fov, "fov_y"),
            fov_smaller: given(fov, "fov_smaller"),
            fov_larger: given(fov, "fov_larger"),
            fov_diagonal: given(fov, "fov_diagonal"),
            orthographic_width: None,
            aperture_radius: lens.0,
            focus_distance: lens.1,
            medium: self.camera_medium.clone(),
        };
        (Some((camera, fov_at)), film, spp)
    }

    /// Mitsuba's field of view of a perspective sensor or a projector (`parse_fov` in
    /// src/render/sensor.cpp): `fov` with `fov_axis`, or `focal_length` ("<x>mm" on a 36 x 24
    /// mm film, 50mm where neither is given: the diagonal field of view). The rule is kept, to
    /// be resolved at the size that renders (or, for a projector, its texture's); with where
    /// its value is written.
    fn field_of_view(&mut self, o: &Object, p: &mut Props) -> Option<(Fov, usize)> {
        // The field of view, an angle in (0, 180) degrees; `written`: where its value is, if any.
        let written = p.props.iter().find(|q| q.name == "fov").map(|q| q.value_at);
        let fov = match (self.float(p, "fov"), written) {
            (Some(v), Some(at)) if v.is_finite() && v > 0.0 && v < 180.0 => Some((v, at)),
            (Some(v), Some(at)) => {
                self.error(at, "fov", format!("`fov` must be a finite angle in (0, 180) degrees (got {v})"));
                None
            }
            _ => None,
        };
        let axis = self.string(p, "fov_axis");
        // Mitsuba's `focal_length` ("<x>mm" on a 36 x 24 mm film, 50mm by default): the
        // diagonal field of view 2 atan(sqrt(36^2 + 24^2) / (2 x)).
        let focal = match p.take("focal_length") {
            Some(prop) if written.is_some() => {
                self.error(prop.at, "focal_length", "give either `fov` or `focal_length`, not both (as Mitsuba requires)");
                None
            }
            Some(prop) => {
                let text = match &prop.value {
                    Value::String(t) => Some(t.clone()),
                    Value::Float(v) => Some(v.to_string()),
                    _ => None,
                };
                match text.as_deref().map(|t| t.trim().trim_end_matches("mm").trim().parse::<f64>()) {
                    Some(Ok(mm)) if mm.is_finite() && mm > 0.0 => Some((mm, prop.value_at)),
                    _ => {
                        self.error(prop.value_at, "focal_length", "`focal_length` must be of the form <x>mm with x > 0 (Mitsuba's)".to_string());
                        None
                    }
                }
            }
            None if written.is_none() => Some((50.0, o.at)),
            None => None,
        };
        let (fov, fov_at, axis_name) = match (fov, focal) {
            (Some((fov, at)), _) => (fov, at, axis.as_ref().map_or("x", |(a, _)| a.as_str()).to_string()),
            (None, Some((mm, at))) => {
                if let Some((_, axis_at)) = &axis {
                    self.warn(*axis_at, "fov_axis", "`fov_axis` is ignored with a focal length: Mitsuba's is then the diagonal".to_string());
                }
                (2.0 * (36.0f64.hypot(24.0) / (2.0 * mm)).atan().to_degrees(), at, "diagonal".to_string())
            }
            (None, None) => return None,
        };
        // The field of view by its rule, kept as Mitsuba's: resolved at whatever size renders.
        let fov = match axis_name.as_str() {
            "x" => Fov::X(fov),
            "y" => Fov::Y(fov),
            "smaller" => Fov::Smaller(fov),
            "larger" => Fov::Larger(fov),
            "diagonal" => Fov::Diagonal(fov),
            other => {
                let at = axis.as_ref().map_or(o.at, |(_, at)| *at);
                self.error(at, "fov_axis", format!("unknown fov_axis \"{other}\" (x, y, smaller, larger, diagonal)"));
                Fov::X(fov)
            }
        };
        Some((fov, fov_at))
    }

    /// Mitsuba 3.9.1's `orthographic` sensor (`src/sensors/orthographic.cpp`): its sample-to-camera
    /// map sends the film to camera x in [-1, 1] (x to the left) and y in [-1/aspect, 1/aspect]
    /// at depth `near_clip`, and rays leave there along +z, all through `to_world`. So the view is
    /// twice to_world's x scale across, and its rectangle's centre is to_world's origin moved by
    /// `near_clip` along its z axis.
    fn orthographic(&mut self, o: &Object, mut p: Props) -> Option<(RawCamera, usize)> {
        let near = match self.get::<f64>(&mut p, "near_clip") {
            Some((v, _)) if v.is_finite() && v >= 0.0 => v,
            Some((v, prop)) => {
                self.error(prop.value_at, "near_clip", format!("`near_clip` must be a finite number >= 0 (got {v})"));
                0.0
            }
            None => MITSUBA_NEAR_CLIP,
        };
        if let Some(prop) = p.take("far_clip") {
            self.warn(prop.at, "far_clip", "`far_clip` is ignored: pathlab does not clip (the image differs only where geometry lies beyond it)".to_string());
        }
        let to_world = self.transform(&mut p, "to_world");
        self.finish(p, "to_world, near_clip (and, with a warning, far_clip)");
        let m = match &to_world {
            None => glam::DMat4::IDENTITY,
            Some((ops, _)) => compose(ops),
        };
        let at = to_world.as_ref().map_or(o.at, |(_, at)| *at);
        let (left, up, dir) = (m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate());
        let scale = left.length().max(up.length()).max(dir.length());
        let orthogonal = [left.dot(up), up.dot(dir), dir.dot(left)].iter().all(|d| d.abs() <= 1e-4 * scale * scale);
        if !m.is_finite() || left.length() == 0.0 || dir.length() == 0.0 || up.length() == 0.0 || !orthogonal {
            self.error(at, "to_world", "an orthographic sensor's to_world must be a rotation, a scale and a translation");
            return None;
        }
        if (left.length() - up.length()).abs() > 1e-4 * scale {
            self.error(at, "to_world", format!("an orthographic sensor's to_world scales x and y unequally ({} and {}), which stretches the image; pathlab's view keeps the pixels square", left.length(), up.length()));
            return None;
        }
        if left.dot(up.cross(dir)) <= 0.0 {
            self.error(at, "to_world", "the sensor's to_world mirrors the image, which pathlab's camera cannot");
            return None;
        }
        self.note_sensor_correction(up, left, dir);
        let position = m.w_axis.truncate() + near * dir;
        let width = 2.0 * left.length();
        let camera = RawCamera {
            position: spanned(o.at, position.to_array()),
            look_at: spanned(o.at, (position + dir.normalize()).to_array()),
            up: spanned(o.at, up.normalize().to_array()),
            fov_x: None,
            fov_y: None,
            fov_smaller: None,
            fov_larger: None,
            fov_diagonal: None,
            orthographic_width: Some(spanned(at, width)),
            aperture_radius: None,
            focus_distance: None,
            medium: self.camera_medium.clone(),
        };
        Some((camera, at))
    }

    /// Records how far the camera frame built from a sensor matrix's axes (the view direction
    /// kept, up made perpendicular to it, left their cross product) moved each axis: the angle
    /// between unit vectors, by atan2 for accuracy near zero (`Translation::sensor_correction`).
    fn note_sensor_correction(&mut self, up: DVec3, left: DVec3, dir: DVec3) {
        let d = dir.normalize();
        let u = (up - d * d.dot(up)).normalize();
        let l = u.cross(d);
        let angle = |a: DVec3, b: DVec3| {
            let a = a.normalize();
            a.cross(b).length().atan2(a.dot(b))
        };
        let moved = angle(up, u).max(angle(left, l));
        if moved > 0.0 {
            self.sensor_correction = Some(moved);
        }
    }

    fn film(&mut self, o: &Object) -> (i64, i64, usize) {
        if o.plugin != "hdrfilm" {
            self.error(o.at, "type", format!("{} is not supported (pathlab has hdrfilm)", describe(&o.tag, &o.plugin)));
        }
        let mut p = Props::of(o);
        let width = self.integer(&mut p, "width").map_or(DEFAULT_FILM_SIZE.0, |(v, _)| v);
        let height = self.integer(&mut p, "height").map_or(DEFAULT_FILM_SIZE.1, |(v, _)| v);
        for name in ["pixel_format", "component_format", "file_format"] {
            if let Some(prop) = p.take(name) {
                self.warn(prop.at, name, format!("`{name}` is ignored: pathlab writes RGB float32 EXR (the image is the same)"));
            }
        }
        for name in ["crop_offset_x", "crop_offset_y", "crop_width", "crop_height"] {
            if let Some(prop) = p.take(name) {
                self.error(prop.at, name, format!("`{name}` is not supported (pathlab renders the whole film)"));
            }
        }
        // Mitsuba 3's hdrfilm marks `banner` as read and ignores it ("no banner in Mitsuba 3").
        if let Some(prop) = p.take("banner") {
            self.warn(prop.at, "banner", "`banner` is ignored, as Mitsuba 3 ignores it (the image is the same)");
        }
        if let Some(prop) = p.take("sample_border") {
            if prop.value == Value::Boolean(true) {
                self.warn(prop.at, "sample_border", "`sample_border` is ignored: with pathlab's box filter no sample crosses a pixel border");
            }
        }
        self.finish(p, "width, height (and, with a warning, pixel_format, component_format, file_format, sample_border, banner)");
        let mut filter = None;
        for child in &o.children {
            match child.tag.as_str() {
                "rfilter" => filter = Some(child),
                other => self.error(child.at, "", format!("{} inside a <film> is not supported", describe(other, &child.plugin))),
            }
        }
        match filter {
            Some(f) if f.plugin == "box" => self.finish(Props::of(f), "nothing"),
            Some(f) => self.warn(
                f.at,
                "rfilter",
                format!(
                    "<rfilter type=\"{}\">: pathlab's pixel filter is a box (each sample counts in its own pixel only), so its image is \
                     slightly sharper than Mitsuba's with this filter; use <rfilter type=\"box\"/> to compare pixel for pixel",
                    f.plugin
                ),
            ),
            None => self.warn(
                o.at,
                "rfilter",
                "no <rfilter>: Mitsuba's default is gaussian, pathlab's pixel filter is a box, so its image is slightly sharper; \
                 add <rfilter type=\"box\"/> to compare pixel for pixel",
            ),
        }
        (width, height, o.at)
    }

    fn sampler(&mut self, o: &Object) -> Option<(i64, usize)> {
        if o.plugin != "independent" {
            self.warn(
                o.at,
                "type",
                format!("<sampler type=\"{}\">: pathlab's sampler is chosen with --method (or --sampler); the expected image is the same", o.plugin),
            );
        }
        let mut p = Props::of(o);
        let spp = self.integer(&mut p, "sample_count");
        if let Some(prop) = p.take("seed") {
            self.warn(prop.at, "seed", "the sampler's `seed` is ignored: pathlab's seed is --seed");
        }
        // Parameters of other sampler types change only the noise.
        for name in ["jitter", "scramble_seed", "dimension", "strata"] {
            if let Some(prop) = p.take(name) {
                self.warn(prop.at, name, format!("`{name}` is ignored: it changes the noise, not the expected image"));
            }
        }
        self.finish(p, "sample_count (and, with a warning, seed)");
        spp
    }

    /// `<integrator type="path">`: (max_depth, rr_depth, offset).
    fn integrator(&mut self, o: &Object) -> (i64, i64, usize, Option<(bool, usize)>) {
        match o.plugin.as_str() {
            // Mitsuba's `moment` renders the integrator it wraps, with its moments as extra
            // channels: the image is that integrator's.
            "moment" => {
                let nested: Vec<&Object> = o.children.iter().filter(|c| c.tag == "integrator").collect();
                if let [inner] = nested.as_slice() {
                    self.warn(
                        o.at,
                        "type",
                        "<integrator type=\"moment\"> is read as the integrator it wraps (the image is the same; pathlab writes variance channels, not Mitsuba's moment channels)".to_string(),
                    );
                    self.finish(Props::of(o), "nothing");
                    return self.integrator(inner);
                }
                self.error(o.at, "type", format!("<integrator type=\"moment\"> must wrap exactly one <integrator> (it wraps {})", nested.len()));
            }
            // Mitsuba's `aov` renders its first nested integrator's image and writes the AOVs
            // it names as extra channels (src/integrators/aov.cpp: `result` is inner integrator
            // 0's): the image is that integrator's.
            "aov" => {
                let nested: Vec<&Object> = o.children.iter().filter(|c| c.tag == "integrator").collect();
                if let Some(first) = nested.first() {
                    self.warn(
                        o.at,
                        "type",
                        "<integrator type=\"aov\"> is read as its first nested integrator (the image is the same; pathlab writes no AOV channels)".to_string(),
                    );
                    let mut p = Props::of(o);
                    let _ = self.string(&mut p, "aovs");
                    self.finish(p, "aovs");
                    for extra in &nested[1..] {
                        self.warn(extra.at, "", "a second integrator inside <integrator type=\"aov\"> is ignored: its image goes to AOV channels, which pathlab does not write".to_string());
                    }
                    return self.integrator(first);
                }
                self.error(o.at, "type", "<integrator type=\"aov\"> without a nested integrator renders AOVs only, which pathlab does not write".to_string());
            }
            // Mitsuba's `ptracer` (src/integrators/ptracer.cpp) traces light from the emitters
            // to the sensor: the same expected image as `path` at the same depth, except light
            // that reaches the sensor through a specular (delta) surface, which a particle
            // tracer cannot connect and `path` renders. `samples_per_pass` changes nothing.
            "ptracer" => {
                self.warn(
                    o.at,
                    "type",
                    "<integrator type=\"ptracer\"> is read as path with its max_depth, rr_depth and hide_emitters: the same expected image, except light reaching the camera through a specular surface, which Mitsuba's particle tracer cannot render and path does".to_string(),
                );
                let mut p = Props::of(o);
                let _ = self.integer(&mut p, "samples_per_pass");
                let max_depth = self.integer(&mut p, "max_depth");
                let rr_depth = self.integer(&mut p, "rr_depth");
                let hide_emitters = self.get::<bool>(&mut p, "hide_emitters").map(|(v, prop)| (v, prop.value_at));
                self.finish(p, "max_depth, rr_depth, hide_emitters, samples_per_pass");
                return self.depths(o, max_depth, rr_depth, hide_emitters);
            }
            "path" => {}
            // Mitsuba's `direct` (src/integrators/direct.cpp): what the camera sees emitted,
            // plus one bounce of direct light from light and BSDF sampling weighed by the power
            // heuristic: the same expectation as `path` with max_depth 2 (its first vertex's
            // next event estimation and BSDF sample, the hit's emission). Its sample counts
            // change only the noise.
            "direct" => {
                self.warn(
                    o.at,
                    "type",
                    "<integrator type=\"direct\"> is read as path with max_depth 2: the same expected image (emitted light and one bounce of direct light); emitter_samples, bsdf_samples and shading_samples change only the noise and are not used".to_string(),
                );
                let mut p = Props::of(o);
                for name in ["emitter_samples", "bsdf_samples", "shading_samples"] {
                    if let Some((n, at)) = self.integer(&mut p, name) {
                        if n < 0 {
                            self.error(at, name, format!("{name} must be at least 0 (got {n})"));
                        }
                    }
                }
                let hide_emitters = self.get::<bool>(&mut p, "hide_emitters").map(|(v, prop)| (v, prop.value_at));
                self.finish(p, "emitter_samples, bsdf_samples, shading_samples, hide_emitters");
                // hide_emitters: Mitsuba's direct skips every area emitter the camera ray meets
                // (skip_area_emitters), as pathlab's path does (render.hide_emitters).
                return (2, DEFAULT_RR_DEPTH, o.at, hide_emitters);
            }
            // Rendered by the volumetric path tracer where the scene has media (volpath.wgsl),
            // by the path tracer otherwise (volpath without media is one). volpathmis differs
            // from volpath in variance only.
            "volpath" | "volpathmis" => {}
            other => self.error(
                o.at,
                "type",
                format!("<integrator type=\"{other}\"> is not supported (pathlab is a unidirectional path tracer: path, volpath and volpathmis, direct (path with max_depth 2), ptracer and aov (read as path and their nested integrator))"),
            ),
        }
        let mut p = Props::of(o);
        let max_depth = self.integer(&mut p, "max_depth");
        let rr_depth = self.integer(&mut p, "rr_depth");
        let hide_emitters = self.get::<bool>(&mut p, "hide_emitters").map(|(v, prop)| (v, prop.value_at));
        self.finish(p, "max_depth, rr_depth, hide_emitters");
        self.depths(o, max_depth, rr_depth, hide_emitters)
    }

    /// A path tracer's depths as read (`max_depth`, `rr_depth`, Mitsuba's defaults where not
    /// given), checked.
    fn depths(&mut self, o: &Object, max_depth: Option<(i64, usize)>, rr_depth: Option<(i64, usize)>, hide_emitters: Option<(bool, usize)>) -> (i64, i64, usize, Option<(bool, usize)>) {
        if let Some((d, at)) = max_depth {
            if d == 0 || d < -1 {
                self.error(at, "max_depth", format!("max_depth must be -1 (unbounded) or at least 1 (got {d})"));
            }
        }
        if let Some((r, at)) = rr_depth {
            if r < 1 {
                self.error(at, "rr_depth", format!("rr_depth must be at least 1 (got {r})"));
            }
        }
        (max_depth.map_or(DEFAULT_MAX_DEPTH, |d| d.0), rr_depth.map_or(DEFAULT_RR_DEPTH, |d| d.0), o.at, hide_emitters)
    }

    /// A BSDF object, interpreted once per id.
    fn bsdf(&mut self, o: &Object) -> Option<Bsdf> {
        if let Some(id) = &o.id {
            if let Some(done) = self.bsdfs.get(id) {
                return done.clone();
            }
        }
        let b = self.bsdf_uncached(o);
        if let Some(id) = &o.id {
            self.bsdfs.insert(id.clone(), b.clone());
        }
        b
    }

    fn bsdf_uncached(&mut self, o: &Object) -> Option<Bsdf> {
        let name = o.id.clone();
        let b = match o.plugin.as_str() {
            "twosided" => {
                self.finish(Props::of(o), "one nested <bsdf>");
                let inner: Vec<&Object> = o.children.iter().filter(|c| c.tag == "bsdf").collect();
                match inner.as_slice() {
                    [one] => match self.bsdf(one) {
                        // Mitsuba: "Only materials without a transmission component can be
                        // nested!": a mask's null lobe counts as one.
                        Some(b) if b.opacity.is_some() => {
                            self.error(one.at, "type", "a mask inside a <bsdf type=\"twosided\"> (Mitsuba refuses it: only materials without a transmission component can be nested; wrap the twosided in the mask)");
                            None
                        }
                        // Around a blend, both of its BSDFs are two-sided.
                        b => b.map(|b| {
                            let blend = b.blend.clone().map(|(other, w)| (Box::new(Bsdf { two_sided: true, ..*other }), w));
                            Bsdf { two_sided: true, name: name.or(b.name.clone()), blend, ..b }
                        }),
                    },
                    [] => {
                        self.error(o.at, "", "<bsdf type=\"twosided\"> needs the <bsdf> it makes two-sided");
                        None
                    }
                    [front, back] => {
                        let (f, b) = (self.bsdf(front), self.bsdf(back));
                        let (f, b) = (f?, b?);
                        // Mitsuba: "Only materials without a transmission component can be
                        // nested!"; a mask or a twosided inside one side pathlab does not model.
                        for (side, o, bsdf) in [("front", front, &f), ("back", back, &b)] {
                            if bsdf.kind.fields_transmit_or_both_sides(&bsdf.fields) {
                                self.error(o.at, "type", format!("the {side} of a <bsdf type=\"twosided\"> with two BSDFs is a {}, which transmits: only BSDFs that reflect can be nested (Mitsuba refuses it too)", o.plugin));
                                return None;
                            }
                            if bsdf.opacity.is_some() || bsdf.two_sided || bsdf.normal_map.is_some() || bsdf.bump_map.is_some() || bsdf.blend.is_some() {
                                self.error(o.at, "type", format!("the {side} of a <bsdf type=\"twosided\"> with two BSDFs must be one plain BSDF (a mask, normal map, bump map or twosided inside one side is not supported; a mask may wrap the twosided)"));
                                return None;
                            }
                        }
                        Some(Bsdf { two_sided: true, name: name.or(f.name.clone()), back: Some(Box::new(b)), ..f })
                    }
                    [_, _, third, ..] => {
                        self.error(third.at, "", "<bsdf type=\"twosided\"> takes at most two nested BSDFs (Mitsuba: \"At most two nested BSDFs can be specified!\")");
                        None
                    }
                }
            }
            "mask" => self.mask(o),
            "blendbsdf" => self.blend(o),
            "normalmap" => self.normal_map(o),
            "bumpmap" => self.bump_map(o),
            plugin => match BsdfKind::from_mitsuba_plugin(plugin) {
                Some(kind) => {
                    let mut reader = PluginReader { t: self, p: Some(Props::of(o)), o, taken: Vec::new() };
                    let fields = kind.read_mitsuba(&mut reader);
                    reader.finish("");
                    fields.map(|fields| Bsdf { kind, fields, two_sided: false, name, opacity: None, normal_map: None, bump_map: None, back: None, blend: None })
                }
                None => {
                    let known = BsdfKind::all_mitsuba_plugins().join(", ");
                    self.error(o.at, "type", format!("<bsdf type=\"{plugin}\"> is not supported (pathlab has {known}, twosided, mask, blendbsdf, normalmap, bumpmap)"));
                    None
                }
            },
        };
        for c in o.children.iter().filter(|c| c.tag != "bsdf" && c.tag != "texture") {
            self.error(c.at, "", format!("{} inside a <bsdf> is not supported", describe(&c.tag, &c.plugin)));
        }
        b
    }

    /// A BSDF wrapper's one scalar property `name` (a mask's `opacity`, a blend's `weight`) as its
    /// TOML value: a float, a colour as its channels' mean (Mitsuba's `eval_1` of a constant), or
    /// a texture's table; any other nested texture refused. `reads` lists what the plugin reads.
    fn scalar_or_texture(&mut self, o: &Object, name: &str, reads: &str) -> Option<toml::Value> {
        let mut reader = PluginReader { t: self, p: Some(Props::of(o)), o, taken: Vec::new() };
        let value = reader.color_or_texture(name);
        let stray = reader.texture();
        reader.finish(reads);
        if let Some(at) = stray {
            self.error(at, "", format!("a <texture> inside a <bsdf type=\"{}\"> other than its `{name}` is not supported", o.plugin));
        }
        value.map(|v| match v {
            toml::Value::Table(t) => toml::Value::Table(t),
            c => {
                let c = <crate::scene::raw::RawColor as serde::Deserialize>::deserialize(c).map(|c| c.0).unwrap_or([0.0; 3]);
                toml::Value::Float(c.iter().sum::<f64>() / 3.0)
            }
        })
    }

    /// `<bsdf type="mask">` (Mitsuba's mask.cpp): its one nested BSDF with the opacity, a float,
    /// a colour (its channels' mean: Mitsuba's `eval_1` of a constant) or a texture; 0.5 when not
    /// given, as Mitsuba's.
    fn mask(&mut self, o: &Object) -> Option<Bsdf> {
        let opacity = self
            .scalar_or_texture(o, "opacity", "opacity, one nested <bsdf>")
            .unwrap_or(toml::Value::Float(crate::scene::bsdfs::DEFAULT_MITSUBA_OPACITY));
        let inner: Vec<&Object> = o.children.iter().filter(|c| c.tag == "bsdf").collect();
        match inner.as_slice() {
            [one] => match self.bsdf(one) {
                Some(b) if b.opacity.is_some() => {
                    self.error(one.at, "", "a mask inside a <bsdf type=\"mask\"> is not supported (give one mask, the opacities' product)");
                    None
                }
                b => b.map(|b| Bsdf { opacity: Some(opacity), name: o.id.clone().or(b.name.clone()), ..b }),
            },
            [] => {
                self.error(o.at, "", "<bsdf type=\"mask\"> needs the <bsdf> it masks");
                None
            }
            [_, second, ..] => {
                self.error(second.at, "", "<bsdf type=\"mask\"> takes one nested <bsdf> (Mitsuba: \"Cannot specify more than one child BSDF\")");
                None
            }
        }
    }

    /// `<bsdf type="blendbsdf">` (Mitsuba's blendbsdf.cpp, `bsdfs::Blend`): its two nested BSDFs,
    /// plain (each may be `twosided`; a mask or twosided may wrap the blend), and its `weight`
    /// (required, as Mitsuba's): a float, a colour (its channels' mean, Mitsuba's `eval_1` of a
    /// constant) or a texture.
    fn blend(&mut self, o: &Object) -> Option<Bsdf> {
        let weight = self.scalar_or_texture(o, "weight", "weight, two nested <bsdf>");
        if weight.is_none() {
            self.error(o.at, "weight", "<bsdf type=\"blendbsdf\"> needs its `weight` (Mitsuba requires it)");
        }
        let inner: Vec<&Object> = o.children.iter().filter(|c| c.tag == "bsdf").collect();
        let [first, second] = inner.as_slice() else {
            let at = inner.get(2).map_or(o.at, |c| c.at);
            self.error(at, "", "<bsdf type=\"blendbsdf\"> takes two nested BSDFs (Mitsuba: \"BlendBSDF: Two child BSDFs must be specified!\")");
            return None;
        };
        let (f, s) = (self.bsdf(first), self.bsdf(second));
        let (f, s) = (f?, s?);
        for (o, b) in [(first, &f), (second, &s)] {
            if b.opacity.is_some() || b.back.is_some() || b.normal_map.is_some() || b.bump_map.is_some() || b.blend.is_some() {
                self.error(o.at, "type", "each BSDF inside a <bsdf type=\"blendbsdf\"> must be one plain BSDF, or a twosided one (a mask or twosided may wrap the blend)");
                return None;
            }
        }
        Some(Bsdf { name: o.id.clone().or(f.name.clone()), blend: Some((Box::new(s), weight?)), ..f })
    }

    /// `<bsdf type="normalmap">` (Mitsuba's normalmap.cpp): its one nested BSDF, plain and
    /// reflecting (a mask or twosided may wrap the normal map, not the other way round), with
    /// the `normalmap` texture; `flip_invalid_normals` and `use_shadowing_function` true, as
    /// Mitsuba's defaults (false is refused).
    fn normal_map(&mut self, o: &Object) -> Option<Bsdf> {
        // Mitsuba's normalmap reads eval_3, which only its bitmap and rawconstant have (its
        // checkerboard fails at render time: "Texture::eval_3(): not implemented!").
        let other = o.children.iter().find(|c| c.tag == "texture" && c.name.as_deref() == Some("normalmap") && c.plugin != "bitmap" && c.plugin != "rawconstant");
        if let Some(t) = other {
            let why = if t.plugin == "checkerboard" { "Mitsuba's checkerboard has no eval_3, which its normalmap reads".to_string() } else { format!("<texture type=\"{}\"> is not supported as one", t.plugin) };
            self.error(t.at, "normalmap", format!("a normal map must be a bitmap or a rawconstant ({why})"));
            return None;
        }
        let mut reader = PluginReader { t: self, p: Some(Props::of(o)), o, taken: Vec::new() };
        let has_map = reader.has_texture("normalmap");
        let map = if has_map { reader.color_or_texture("normalmap") } else { None };
        let flags = ["flip_invalid_normals", "use_shadowing_function"].map(|name| (name, reader.boolean(name)));
        let stray = reader.texture();
        reader.finish("normalmap (a <texture>), flip_invalid_normals, use_shadowing_function, one nested <bsdf>");
        if let Some(at) = stray {
            self.error(at, "", "a <texture> inside a <bsdf type=\"normalmap\"> other than its `normalmap` is not supported");
        }
        for (name, value) in flags {
            if let Some((false, at)) = value {
                self.error(at, name, format!("`{name}` = false is not supported (pathlab follows Mitsuba's default, true)"));
            }
        }
        if !has_map {
            self.error(o.at, "normalmap", "<bsdf type=\"normalmap\"> needs its normals as a <texture name=\"normalmap\">");
        }
        let b = self.perturbed_bsdf(o, "normal map", "normal-map")?;
        Some(Bsdf { normal_map: Some(map?), name: o.id.clone().or(b.name.clone()), ..b })
    }

    /// The one nested BSDF of a `normalmap` or `bumpmap` `o` (its `noun` and `verb` for the
    /// messages): plain and reflecting (a mask or twosided may wrap the map, not the other way
    /// round), as Mitsuba's "Only a single BSDF child object can be specified."
    fn perturbed_bsdf(&mut self, o: &Object, noun: &str, verb: &str) -> Option<Bsdf> {
        let kind = &o.plugin;
        let inner: Vec<&Object> = o.children.iter().filter(|c| c.tag == "bsdf").collect();
        match inner.as_slice() {
            [one] => {
                let b = self.bsdf(one)?;
                if b.opacity.is_some() || b.two_sided || b.back.is_some() || b.normal_map.is_some() || b.bump_map.is_some() || b.blend.is_some() {
                    self.error(one.at, "type", format!("the BSDF inside a <bsdf type=\"{kind}\"> must be one plain BSDF (a mask or twosided may wrap the {noun} instead)"));
                    return None;
                }
                if b.kind.fields_transmit_or_both_sides(&b.fields) {
                    self.error(one.at, "type", format!("a {noun} around a <bsdf type=\"{}\">, which transmits, is not supported ({verb} a BSDF that reflects)", one.plugin));
                    return None;
                }
                Some(b)
            }
            [] => {
                self.error(o.at, "", format!("<bsdf type=\"{kind}\"> needs the <bsdf> it perturbs"));
                None
            }
            [_, second, ..] => {
                self.error(second.at, "", format!("<bsdf type=\"{kind}\"> takes one nested <bsdf> (Mitsuba: \"Only a single BSDF child object can be specified.\")"));
                None
            }
        }
    }

    /// `<bsdf type="bumpmap">` (Mitsuba's bumpmap.cpp): its one nested BSDF, plain and
    /// reflecting (a mask or twosided may wrap the bump map, not the other way round), with one
    /// `<texture>` of any name, a bitmap (Mitsuba's only texture with a gradient, `eval_1_grad`),
    /// and `scale` (default 1); `flip_invalid_normals` and `use_shadowing_function` true, as
    /// Mitsuba's defaults (false is refused).
    fn bump_map(&mut self, o: &Object) -> Option<Bsdf> {
        let textures: Vec<(usize, &Object)> = o.children.iter().enumerate().filter(|(_, c)| c.tag == "texture").collect();
        let (index, texture) = match textures.as_slice() {
            [one] => *one,
            [] => {
                self.error(o.at, "", "<bsdf type=\"bumpmap\"> needs its heights as one <texture> (a bitmap)");
                return None;
            }
            [_, second, ..] => {
                self.error(second.1.at, "", "<bsdf type=\"bumpmap\"> takes one <texture> (Mitsuba: \"Only a single Texture child object can be specified.\")");
                return None;
            }
        };
        if texture.plugin != "bitmap" {
            let why = if texture.plugin == "checkerboard" { "Mitsuba's checkerboard has no gradient, eval_1_grad, which its bumpmap reads".to_string() } else { format!("<texture type=\"{}\"> is not supported as one", texture.plugin) };
            self.error(texture.at, "type", format!("a bump map must be a bitmap ({why})"));
            return None;
        }
        let mut reader = PluginReader { t: self, p: Some(Props::of(o)), o, taken: vec![index] };
        let heights = reader.bitmap(texture);
        let scale = reader.float("scale");
        let flags = ["flip_invalid_normals", "use_shadowing_function"].map(|name| (name, reader.boolean(name)));
        reader.finish("scale, flip_invalid_normals, use_shadowing_function, one <texture>, one nested <bsdf>");
        for (name, value) in flags {
            if let Some((false, at)) = value {
                self.error(at, name, format!("`{name}` = false is not supported (pathlab follows Mitsuba's default, true)"));
            }
        }
        let b = self.perturbed_bsdf(o, "bump map", "bump-map")?;
        let mut map = heights?;
        if let (toml::Value::Table(t), Some((s, _))) = (&mut map, scale) {
            t.insert("scale".into(), toml::Value::Float(s));
        }
        Some(Bsdf { bump_map: Some(map), name: o.id.clone().or(b.name.clone()), ..b })
    }

    /// The material of a BSDF with an emission: shared by every shape with the same pair.
    fn material(&mut self, bsdf: &Bsdf, emission: Option<RawColorOrTexture>, shape_name: &str, at: usize) -> Spanned<String> {
        self.material_bounding(bsdf, emission, shape_name, at, (None, None))
    }

    /// A material whose surface bounds the media named (interior, exterior): one per distinct
    /// BSDF, emission and media (pathlab's media are the material's, Mitsuba's the shape's).
    fn material_bounding(&mut self, bsdf: &Bsdf, emission: Option<RawColorOrTexture>, shape_name: &str, at: usize, media: (Option<String>, Option<String>)) -> Spanned<String> {
        if let Some((name, ..)) = self.material_keys.iter().find(|(_, b, e, m)| b == bsdf && *e == emission && *m == media) {
            return spanned(at, name.clone());
        }
        let base = match (&emission, &bsdf.name) {
            (None, Some(n)) => n.clone(),
            (None, None) | (Some(_), _) => shape_name.to_string(),
        };
        let mut name = base.clone();
        let mut k = 2;
        while self.materials.contains_key(&name) {
            name = format!("{base}-{k}");
            k += 1;
        }
        // A second BSDF on the back: a material of its own, which this one names.
        let back = bsdf.back.as_ref().map(|b| {
            let back_name = format!("{}-back", bsdf.name.clone().unwrap_or_else(|| shape_name.to_string()));
            let back = Bsdf { name: Some(back_name), ..(**b).clone() };
            self.material(&back, None, shape_name, at)
        });
        // A blend's second BSDF: a material of its own, which this one names with the weight.
        let blend = bsdf.blend.as_ref().map(|(b, weight)| {
            let blend_name = format!("{}-blend", bsdf.name.clone().unwrap_or_else(|| shape_name.to_string()));
            let other = Bsdf { name: Some(blend_name), ..(**b).clone() };
            (self.material(&other, None, shape_name, at), spanned(at, weight.clone()))
        });
        let (blend, blend_weight) = match blend {
            Some((b, w)) => (Some(b), Some(w)),
            None => (None, None),
        };
        let m = RawMaterial {
            blend,
            blend_weight,
            back,
            emission: emission.clone().map(|e| spanned(at, e)),
            // A kind that scatters on both sides by its nature is two-sided unwrapped.
            two_sided: if bsdf.two_sided || bsdf.kind.fields_transmit_or_both_sides(&bsdf.fields) { None } else { Some(spanned(at, false)) },
            bsdf: (bsdf.kind != BsdfKind::ALL[0]).then(|| spanned(at, bsdf.kind.toml_name().to_string())),
            params: bsdf.fields.iter().map(|(k, v)| (k.to_string(), spanned(at, v.clone()))).collect(),
            opacity: bsdf.opacity.clone().map(|o| spanned(at, o)),
            normal_map: bsdf.normal_map.clone().map(|n| spanned(at, n)),
            bump_map: bsdf.bump_map.clone().map(|b| spanned(at, b)),
            interior: media.0.clone().map(|m| spanned(at, m)),
            exterior: media.1.clone().map(|m| spanned(at, m)),
        };
        self.materials.insert(name.clone(), spanned(at, m));
        self.material_keys.push((name.clone(), bsdf.clone(), emission, media));
        spanned(at, name)
    }

    fn shape(&mut self, o: &Object, shapes: &mut Shapes) {
        match o.plugin.as_str() {
            "shapegroup" => self.shapegroup(o),
            "instance" => self.instance(o, shapes),
            _ => self.placed_shape(o, None, shapes),
        }
    }

    /// `<shape type="shapegroup" id>`: shapes placed only by the `instance`s that `<ref>` it.
    /// Its problems are reported here, once, where it is defined.
    fn shapegroup(&mut self, o: &Object) {
        for (at, field, message) in shapegroup_problems(o, true) {
            self.error(at, &field, message);
        }
    }

    /// The file a curve or grid shape reads (its `filename`, found as Mitsuba finds it), with
    /// `flip_normals` refused (`why_no_flip` says why) and a missing `filename` (`needs` adds
    /// what it is) or file (`what` names it) reported at the shape; None after an error.
    fn shape_file(&mut self, o: &Object, file: Option<(String, usize)>, flip: bool, why_no_flip: &str, needs: &str, what: &str) -> Option<Spanned<String>> {
        if flip {
            self.error(o.at, "flip_normals", format!("flip_normals of a <shape type=\"{}\"> is not supported ({why_no_flip})", o.plugin));
            return None;
        }
        let Some((file, _)) = file else {
            self.error(o.at, "filename", format!("<shape type=\"{}\"> needs <string name=\"filename\">{needs}", o.plugin));
            return None;
        };
        match self.loaded.resolve(&file, &o.dir) {
            Ok(path) => Some(spanned(o.at, path.display().to_string())),
            Err(message) => {
                self.error(o.at, "filename", format!("{what} {message}"));
                None
            }
        }
    }

    /// `<shape type="instance">` with a `<ref>` to one shape group and a `to_world`: the group's
    /// shapes flattened into the scene, each with the instance's transform after its own
    /// (Mitsuba's instance to_world times the shape's), as world-space shapes.
    fn instance(&mut self, o: &Object, shapes: &mut Shapes) {
        let mut p = Props::of(o);
        let to_world = self.transform(&mut p, "to_world");
        self.finish(p, "to_world");
        let groups: Vec<&Object> = o.children.iter().filter(|c| c.tag == "shape" && c.plugin == "shapegroup").collect();
        for c in o.children.iter().filter(|c| !(c.tag == "shape" && c.plugin == "shapegroup")) {
            self.error(c.at, "", format!("{} inside an instance is not supported (only a <ref> to a shape group)", describe(&c.tag, &c.plugin)));
        }
        let group = match groups.as_slice() {
            [group] => *group,
            [] => {
                self.error(o.at, "", "an instance needs a <ref id=\"…\"/> to a <shape type=\"shapegroup\">");
                return;
            }
            [_, second, ..] => {
                self.error(second.at, "", "an instance places one shape group (as in Mitsuba)");
                return;
            }
        };
        // A group with problems (reported where it is defined) places nothing.
        if !shapegroup_problems(group, false).is_empty() {
            return;
        }
        let before = shapes.len();
        for shape in group.children.iter().filter(|c| c.tag == "shape") {
            self.placed_shape(shape, to_world.as_ref(), shapes);
        }
        let placed = shapes.len() - before;
        self.instanced.push((group.id.clone().unwrap_or_default(), placed));
    }

    /// A shape, placed by its own `to_world` and then, inside an instance, by the instance's.
    fn placed_shape(
        &mut self,
        o: &Object,
        instance: Option<&(Vec<TransformOp>, usize)>,
        shapes: &mut Shapes,
    ) {
        self.shape_count += 1;
        let shape_name = o.id.clone().unwrap_or_else(|| format!("shape{}", self.shape_count));
        let mut p = Props::of(o);
        // The BSDF (Mitsuba's default: diffuse 0.5, one-sided) and the area emitter.
        let mut bsdf = None;
        let mut emission = None;
        let (mut interior, mut exterior) = (None, None);
        for c in &o.children {
            match (c.tag.as_str(), c.plugin.as_str()) {
                ("medium", _) if self.volumetric.is_some() => match c.name.as_deref() {
                    Some("interior") => interior = self.medium(c, &format!("{shape_name}-interior")),
                    Some("exterior") => exterior = self.medium(c, &format!("{shape_name}-exterior")),
                    other => self.error(c.at, "name", format!("a <medium> in a <shape> is its `interior` or `exterior` (got name {other:?})")),
                },
                ("bsdf", _) if bsdf.is_some() => self.error(c.at, "", "a second <bsdf> in one <shape>"),
                ("bsdf", _) => bsdf = Some(self.bsdf(c)),
                ("emitter", "area") => {
                    let mut ep = Props::of(c);
                    if c.children.iter().any(|t| t.tag == "texture" && t.name.as_deref() == Some("radiance")) {
                        // A textured radiance (Mitsuba's area emitter evaluates it at the
                        // surface point's uv); triangle meshes alone take it (validation
                        // refuses it on spheres and quadrics).
                        emission = match self.emitter_texture(c, ep, "radiance", "radiance").map(Spanned::into_inner) {
                            Some(toml::Value::Table(table)) => Some(RawColorOrTexture::Texture(table)),
                            _ => None,
                        };
                        continue;
                    }
                    if let Some(t) = c.children.iter().find(|t| t.tag == "texture") {
                        let name = t.name.as_deref().unwrap_or("");
                        self.error(t.at, name, format!("a <texture type=\"{}\" name=\"{name}\"> of an area emitter is not supported (its textured property is `radiance`)", t.plugin));
                    } else {
                        match self.color(&mut ep, "radiance", SpectrumRole::Emission) {
                            Some((r, _)) => emission = Some(RawColorOrTexture::Color(RawColor(r))),
                            None if ep.props.iter().any(|q| q.name == "radiance") || self.has_errors() => {}
                            // Mitsuba 3.9.1's default radiance (area.cpp: get_emissive_texture("radiance", 1.f)).
                            None => emission = Some(RawColorOrTexture::Color(RawColor([1.0; 3]))),
                        }
                    }
                    self.finish(ep, "radiance");
                }
                ("medium", _) => self.media.push(c.at),
                ("emitter", other) => self.error(c.at, "type", format!("<emitter type=\"{other}\"> inside a <shape> is not supported (pathlab has area; a {other} emitter stands alone in the <scene>)")),
                (other, plugin) => self.error(c.at, "", format!("{} inside a <shape> is not supported", describe(other, plugin))),
            }
        }
        let bsdf = match bsdf {
            None => Bsdf::default_diffuse(emission.is_some()),
            Some(Some(b)) => b,
            Some(None) => return,
        };
        let bsdf = Bsdf { name: bsdf.name.clone().or_else(|| Some(shape_name.clone())), ..bsdf };
        let material = self.material_bounding(&bsdf, emission, &shape_name, o.at, (interior, exterior));
        let to_world = match (self.transform(&mut p, "to_world"), instance) {
            (own, None) => own,
            (None, Some(outer)) => Some(outer.clone()),
            // The instance's operations after the shape's own (each after the previous).
            (Some((ops, at)), Some((outer, _))) => Some((ops.into_iter().chain(outer.iter().cloned()).collect(), at)),
        };
        let flip = self.boolean(&mut p, "flip_normals");
        let transform = match &to_world {
            Some((ops, at)) => self.raw_transform(ops, *at),
            None => None,
        };
        let flip_normals = flip.map(|f| spanned(o.at, f));
        match o.plugin.as_str() {
            "obj" | "ply" | "serialized" => {
                let file = self.string(&mut p, "filename");
                let face_normals = self.boolean(&mut p, "face_normals");
                let (flip_tex_coords, shape_index) = if o.plugin == "serialized" {
                    (None, self.get::<i64>(&mut p, "shape_index").map(|(v, prop)| spanned(prop.value_at, v)))
                } else {
                    (self.boolean(&mut p, "flip_tex_coords"), None)
                };
                self.finish(p, if o.plugin == "serialized" { "filename, shape_index, face_normals, flip_normals, to_world" } else { "filename, face_normals, flip_normals, flip_tex_coords, to_world" });
                let Some((file, _)) = file else {
                    self.error(o.at, "filename", format!("<shape type=\"{}\"> needs <string name=\"filename\">", o.plugin));
                    return;
                };
                let ext = Path::new(&file).extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
                if ext != o.plugin {
                    self.warn(o.at, "filename", format!("<shape type=\"{}\"> names a .{ext} file: pathlab reads it by its extension", o.plugin));
                }
                let path = match self.loaded.resolve(&file, &o.dir) {
                    Ok(path) => path,
                    Err(message) => {
                        self.error(o.at, "filename", format!("mesh file {message}"));
                        return;
                    }
                };
                shapes.meshes.push(spanned(
                    o.at,
                    RawMesh {
                        file: spanned(o.at, path.display().to_string()),
                        material,
                        transform,
                        face_normals: face_normals.map(|f| spanned(o.at, f)),
                        flip_normals,
                        two_sided_emission: None,
                        flip_tex_coords: flip_tex_coords.map(|f| spanned(o.at, f)),
                        shape_index,
                    },
                ));
            }
            "rectangle" | "cube" => {
                self.finish(p, "flip_normals, to_world");
                let shape = RawShape { material, transform, flip_normals, two_sided_emission: None };
                if o.plugin == "rectangle" { shapes.rectangles.push(spanned(o.at, shape)) } else { shapes.cubes.push(spanned(o.at, shape)) }
            }
            "disk" => {
                self.finish(p, "flip_normals, to_world");
                shapes.disks.push(spanned(o.at, RawShape { material, transform, flip_normals, two_sided_emission: None }));
            }
            "linearcurve" | "bsplinecurve" => {
                let file = self.string(&mut p, "filename");
                self.finish(p, "filename, to_world");
                let Some(file) = self.shape_file(o, file, flip.is_some(), "Mitsuba culls its back faces", "", "curve file") else { return };
                let curve = spanned(o.at, RawCurve { file, material, transform });
                if o.plugin == "linearcurve" { shapes.linear_curves.push(curve) } else { shapes.bspline_curves.push(curve) }
            }
            "sdfgrid" => {
                let file = self.string(&mut p, "filename");
                let normals = self.string(&mut p, "normals").map(|(n, at)| spanned(at, n));
                self.finish(p, "filename, normals, to_world");
                let needs = " (a .vol grid; a `grid` tensor can be given from Python alone)";
                let Some(file) = self.shape_file(o, file, flip.is_some(), "Mitsuba's sdfgrid does not read it", needs, "signed distance grid") else { return };
                shapes.sdf_grids.push(spanned(o.at, RawSdfGrid { file, material, transform, normals }));
            }
            "cylinder" => {
                let p0 = self.point(&mut p, "p0").map(|v| spanned(o.at, v.to_array()));
                let p1 = self.point(&mut p, "p1").map(|v| spanned(o.at, v.to_array()));
                let radius = match p.props.iter().any(|q| q.name == "radius") {
                    true => match self.positive(&mut p, "radius") {
                        Some((r, _)) => Some(spanned(o.at, r)),
                        None => return,
                    },
                    false => None,
                };
                self.finish(p, "p0, p1, radius, flip_normals, to_world");
                shapes.cylinders.push(spanned(o.at, RawCylinder { material, p0, p1, radius, transform, flip_normals, two_sided_emission: None }));
            }
            "sphere" => {
                let center = self.point(&mut p, "center").unwrap_or(DVec3::ZERO);
                let radius = match p.props.iter().any(|q| q.name == "radius") {
                    true => self.positive(&mut p, "radius").map(|r| r.0),
                    false => Some(1.0),
                };
                self.finish(p, "center, radius, to_world");
                if flip == Some(true) {
                    self.error(o.at, "flip_normals", "flip_normals on a sphere is not supported (pathlab's spheres face outwards)");
                }
                let Some(radius) = radius else { return };
                // A similarity (rotation, uniform scale, translation) moves and scales the sphere.
                let (center, radius, axes) = match &to_world {
                    None => (center, radius, None),
                    Some((ops, at)) => {
                        let m = compose(ops);
                        let cols = [m.x_axis.truncate(), m.y_axis.truncate(), m.z_axis.truncate()];
                        let s = cols[0].length();
                        let similar = s > 0.0
                            && cols.iter().all(|c| (c.length() - s).abs() <= 1e-9 * s)
                            && cols[0].dot(cols[1]).abs() <= 1e-9 * s * s
                            && cols[1].dot(cols[2]).abs() <= 1e-9 * s * s
                            && cols[0].dot(cols[2]).abs() <= 1e-9 * s * s;
                        if !similar || !m.is_finite() {
                            self.error(*at, "to_world", "a sphere's to_world must be a rotation, uniform scale and translation");
                            return;
                        }
                        // The object axes (Mitsuba's to_object maps a point to the frame of
                        // its uv parametrisation): the columns without the scale.
                        let axes = cols.map(|c| (c / s).to_array());
                        let rotated = axes != [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
                        (m.transform_point3(center), radius * s, rotated.then(|| spanned(*at, axes)))
                    }
                };
                shapes.spheres.push(spanned(
                    o.at,
                    RawSphere { center: spanned(o.at, center.to_array()), radius: spanned(o.at, radius), material, axes },
                ));
            }
            other => self.error(o.at, "type", format!("<shape type=\"{other}\"> is not supported (pathlab has {SHAPES})")),
        }
    }

    /// A `<transform>` in the scene model: scale, rotations and translation in that order are
    /// kept as such (as a TOML transform writes them, so both files give the same matrix to the
    /// last bit); anything else becomes its matrix. Singular transforms are refused here.
    fn raw_transform(&mut self, ops: &[TransformOp], at: usize) -> Option<Spanned<RawTransform>> {
        let m = compose(ops);
        let rows = m.transpose().to_cols_array_2d();
        if let Err(e) = super::transform::Transform::from_rows(rows) {
            let at = ops.last().map_or(at, |o| o.at);
            self.error(at, "to_world", format!("transform {e}"));
            return None;
        }
        let mut rest = ops;
        let mut scale = None;
        let mut rotations = Vec::new();
        let mut translate = None;
        if let [TransformOp { kind: OpKind::Scale(s), .. }, tail @ ..] = rest {
            scale = Some(*s);
            rest = tail;
        }
        while let [TransformOp { kind: OpKind::Rotate(axis, angle), .. }, tail @ ..] = rest {
            rotations.push(RawRotation { axis: axis.to_array(), angle: *angle });
            rest = tail;
        }
        if let [TransformOp { kind: OpKind::Translate(t), .. }, tail @ ..] = rest {
            translate = Some(*t);
            rest = tail;
        }
        let raw = if rest.is_empty() {
            RawTransform {
                translate: translate.map(|t| spanned(at, t.to_array())),
                rotate: match rotations.len() {
                    0 => None,
                    1 => Some(spanned(at, RawRotations::One(rotations.remove(0)))),
                    _ => Some(spanned(at, RawRotations::Many(rotations))),
                },
                scale: scale.map(|s| spanned(at, if s.x == s.y && s.y == s.z { RawScale::Uniform(s.x) } else { RawScale::PerAxis(s.to_array()) })),
                matrix: None,
            }
        } else {
            RawTransform { translate: None, rotate: None, scale: None, matrix: Some(spanned(at, rows)) }
        };
        Some(spanned(at, raw))
    }
}
