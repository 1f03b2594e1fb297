//! Mitsuba 3's XML as a tree of plugin objects, before any plugin is interpreted: files and
//! their `<include>`s, `<default>`s with `$name` substitution (and `--define` overrides), named
//! objects and `<ref>`s, typed property values and `<transform>`s. Every object, property and
//! value keeps its offset in the `SourceMap`, so that errors name file, line and column.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{DMat4, DVec3};

use super::super::diagnostic::{Diagnostic, Findings, Severity, SourceMap};
use super::super::spectrum::{Spectrum, CIE_MAX, CIE_MIN};

/// Deepest `<include>` nesting (a cycle would otherwise recurse without end).
const MAX_INCLUDE_DEPTH: usize = 16;

/// A plugin instance: `<bsdf type="diffuse" id="white">` and what it holds.
#[derive(Debug, Clone)]
pub(crate) struct Object {
    /// The element: `bsdf`, `shape`, `emitter`, `sensor`, `film`, `sampler`, `rfilter`, `integrator`, ...
    pub tag: String,
    /// The plugin (`type` attribute).
    pub plugin: String,
    pub id: Option<String>,
    /// Its `name` attribute, as a nested object's (`<texture name="reflectance">`).
    pub name: Option<String>,
    /// Offset of the element's start (global, see `SourceMap`).
    pub at: usize,
    /// The file the object was written in (for relative file names).
    pub dir: PathBuf,
    pub props: Vec<Prop>,
    /// Nested objects (and resolved `<ref>`s), in order.
    pub children: Vec<Object>,
}

/// A named property: `<float name="radius" value="1"/>`.
#[derive(Debug, Clone)]
pub(crate) struct Prop {
    pub name: String,
    pub value: Value,
    /// Offset of the element (global).
    pub at: usize,
    /// Offset of its value attribute, where it has one.
    pub value_at: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Value {
    Float(f64),
    Integer(i64),
    Boolean(bool),
    String(String),
    /// `rgb`.
    Color([f64; 3]),
    /// `spectrum`: one value, wavelength:value pairs, or a blackbody. Its colour depends on
    /// what it is for (`SpectrumRole`), so it is converted where it is read.
    Spectrum(Spectrum),
    Point(DVec3),
    Vector(DVec3),
    Transform(Vec<TransformOp>),
}

impl Value {
    pub fn kind(&self) -> &'static str {
        match self {
            Value::Float(_) => "float",
            Value::Integer(_) => "integer",
            Value::Boolean(_) => "boolean",
            Value::String(_) => "string",
            Value::Color(_) => "rgb",
            Value::Spectrum(_) => "spectrum",
            Value::Point(_) => "point",
            Value::Vector(_) => "vector",
            Value::Transform(_) => "transform",
        }
    }
}

/// One element of a `<transform>`, in the order written; each applies after the previous
/// (Mitsuba composes them as M = op_n ... op_2 op_1).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TransformOp {
    pub kind: OpKind,
    pub at: usize,
}

#[derive(Debug, Clone, PartialEq)]
pub(crate) enum OpKind {
    Translate(DVec3),
    /// Axis and angle in degrees (right-handed).
    Rotate(DVec3, f64),
    Scale(DVec3),
    /// Row-major 4x4.
    Matrix([[f64; 4]; 4]),
    LookAt { origin: DVec3, target: DVec3, up: DVec3 },
}

impl OpKind {
    /// The matrix of one operation, as Mitsuba builds it (`Transform4f.translate`, `.rotate`,
    /// `.scale`, `.look_at`): a look-at maps the camera's +z to the view direction, +y to the
    /// up vector made orthogonal, and +x to left = up x direction.
    pub fn matrix(&self) -> DMat4 {
        match self {
            OpKind::Translate(t) => DMat4::from_translation(*t),
            OpKind::Rotate(axis, angle) => DMat4::from_axis_angle(axis.normalize(), angle.to_radians()),
            OpKind::Scale(s) => DMat4::from_scale(*s),
            OpKind::Matrix(rows) => DMat4::from_cols_array_2d(rows).transpose(),
            OpKind::LookAt { origin, target, up } => {
                let dir = (*target - *origin).normalize();
                let left = up.normalize().cross(dir).normalize();
                let new_up = dir.cross(left);
                DMat4::from_cols(left.extend(0.0), new_up.extend(0.0), dir.extend(0.0), origin.extend(1.0))
            }
        }
    }
}

/// The composed matrix of a transform's operations.
pub(crate) fn compose(ops: &[TransformOp]) -> DMat4 {
    ops.iter().fold(DMat4::IDENTITY, |m, op| op.kind.matrix() * m)
}

/// The top-level objects of a scene file, with its includes resolved, and where each file is.
pub(crate) struct Loaded {
    pub objects: Vec<Object>,
    pub sources: SourceMap,
    pub diagnostics: Vec<Diagnostic>,
    /// `<scene version>` of the main file.
    pub version: Option<String>,
    /// Where relative file names (meshes) are looked for, in order: Mitsuba's file resolver
    /// after the whole file is read, each `<path>` folder in front of the ones before it, then
    /// the main file's folder.
    pub search: Vec<PathBuf>,
}

impl Loaded {
    /// `name` as Mitsuba's file resolver finds it: absolute as it is, else in the first folder of
    /// `search` that has it, then beside `dir` (the XML file that names it, pathlab's rule
    /// before `<path>`). `Err`: every folder searched, for the message.
    pub fn resolve(&self, name: &str, dir: &Path) -> Result<PathBuf, String> {
        resolve(&self.search, name, dir)
    }
}

/// `name` found in the first of `search`'s folders that has it, then beside `dir`
/// (`Loaded::resolve`; also used while reading, with the `<path>` folders read so far).
fn resolve(search: &[PathBuf], name: &str, dir: &Path) -> Result<PathBuf, String> {
    let file = Path::new(name);
    if file.is_absolute() {
        return Ok(file.to_path_buf());
    }
    let mut folders: Vec<&Path> = search.iter().map(PathBuf::as_path).collect();
    if !folders.contains(&dir) {
        folders.push(dir);
    }
    if let Some(found) = folders.iter().map(|f| f.join(file)).find(|c| c.exists()) {
        return Ok(found);
    }
    let shown: Vec<String> = folders.iter().map(|f| if f.as_os_str().is_empty() { "./".to_string() } else { format!("{}/", f.display()) }).collect();
    Err(format!("\"{name}\" not found (searched {})", shown.join(", ")))
}

struct Loader<'a> {
    sources: SourceMap,
    diagnostics: Vec<Diagnostic>,
    /// `$name` values: `--define`s first (they win), then `<default>`s as they come.
    params: BTreeMap<String, String>,
    defined: &'a [(String, String)],
    /// Named objects so far, for `<ref>`.
    named: BTreeMap<String, Object>,
    /// Names that a `<default>` declared or a `$name` used (so a `--define` of another name
    /// is reported as having no effect).
    used: std::collections::BTreeSet<String>,
    version: Option<String>,
    /// The `<path>` folders so far, the latest first.
    paths: Vec<PathBuf>,
    /// The main file's folder (the resolver's last).
    main_dir: PathBuf,
}

impl Loader<'_> {
    /// The folders of Mitsuba's file resolver while reading: the `<path>` folders so far (the
    /// latest first), then the main file's.
    fn resolver(&self) -> impl Iterator<Item = &PathBuf> {
        self.paths.iter().chain(std::iter::once(&self.main_dir))
    }
}

/// Reads `path` and everything it includes. Errors are collected in `diagnostics` (reading
/// goes on past them where it can); the objects are what could be read.
pub(crate) fn load(path: &Path, defines: &[(String, String)]) -> Result<Loaded, std::io::Error> {
    let mut loader = Loader {
        sources: SourceMap::default(),
        diagnostics: Vec::new(),
        params: defines.iter().cloned().collect(),
        defined: defines,
        named: BTreeMap::new(),
        used: Default::default(),
        version: None,
        paths: Vec::new(),
        main_dir: path.parent().map(Path::to_path_buf).unwrap_or_default(),
    };
    let text = std::fs::read_to_string(path)?;
    let mut objects = Vec::new();
    loader.file(path, &text, 0, &mut objects);
    for (name, _) in defines {
        if !loader.used_define(name) {
            loader.diagnostics.push(Diagnostic {
                severity: Severity::Warning,
                file: path.to_path_buf(),
                line: 0,
                column: 0,
                field: format!("--define {name}"),
                message: format!("the scene has no <default name=\"{name}\"> and no `${name}`: the definition has no effect"),
            });
        }
    }
    for o in &mut objects {
        loader.resolve_forward_refs(o, 0);
    }
    objects.retain(|o| o.tag != "ref");
    let mut search = loader.paths;
    search.push(path.parent().map(Path::to_path_buf).unwrap_or_default());
    Ok(Loaded { objects, sources: loader.sources, diagnostics: loader.diagnostics, version: loader.version, search })
}

/// The element's name for messages: `<bsdf type="diffuse">`.
pub(crate) fn describe(tag: &str, plugin: &str) -> String {
    if plugin.is_empty() { format!("<{tag}>") } else { format!("<{tag} type=\"{plugin}\">") }
}

impl Findings for Loader<'_> {
    fn sources(&self) -> &SourceMap {
        &self.sources
    }
    fn findings(&mut self) -> &mut Vec<Diagnostic> {
        &mut self.diagnostics
    }
}

impl Loader<'_> {
    fn used_define(&self, name: &str) -> bool {
        self.used.contains(name)
    }

    /// Replaces the `<ref>`s left in `o` and below it (references to objects defined after
    /// them) by copies of the objects now named, or reports them.
    fn resolve_forward_refs(&mut self, o: &mut Object, depth: usize) {
        if o.tag == "ref" {
            let id = o.id.clone().unwrap_or_default();
            match self.named.get(&id) {
                Some(named) if depth < MAX_INCLUDE_DEPTH => *o = Object { name: o.name.clone().or_else(|| named.name.clone()), ..named.clone() },
                Some(_) => {
                    self.error(o.at, "id", format!("<ref id=\"{id}\"> refers to itself through its own references"));
                    return;
                }
                None => {
                    let known: Vec<&str> = self.named.keys().map(String::as_str).collect();
                    let known = if known.is_empty() { "none".to_string() } else { known.join(", ") };
                    self.error(o.at, "id", format!("<ref id=\"{id}\"> names no object of the scene (defined: {known})"));
                    return;
                }
            }
        }
        for child in &mut o.children {
            self.resolve_forward_refs(child, depth + 1);
        }
        o.children.retain(|c| c.tag != "ref");
    }

    /// Parses one file and appends its top-level objects.
    fn file(&mut self, path: &Path, text: &str, depth: usize, out: &mut Vec<Object>) {
        let base = self.sources.add(path, text);
        let doc = match roxmltree::Document::parse(text) {
            Ok(doc) => doc,
            Err(e) => {
                let pos = e.pos();
                self.diagnostics.push(Diagnostic {
                    severity: Severity::Error,
                    file: path.to_path_buf(),
                    line: pos.row as usize,
                    column: pos.col as usize,
                    field: String::new(),
                    message: format!("malformed XML: {e}"),
                });
                return;
            }
        };
        let root = doc.root_element();
        let at = |n: roxmltree::Node| base + n.range().start;
        if root.tag_name().name() != "scene" {
            self.error(at(root), "", format!("the root element is <{}>, not <scene>", root.tag_name().name()));
            return;
        }
        if depth == 0 {
            match root.attribute("version") {
                Some(v) => self.version = Some(v.to_string()),
                None => self.warn(at(root), "version", "<scene> has no version attribute (Mitsuba 3 files say version=\"3.0.0\")"),
            }
        }
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        for node in root.children().filter(|n| n.is_element()) {
            match node.tag_name().name() {
                "default" => self.default(node, base),
                // Mitsuba's `<path value>`: a folder put in front of the file resolver's
                // (relative: to this file's folder, else where the resolver finds it: Mitsuba
                // 3.9.1's parser.cpp, so that an included file's `<path>` may name a folder of
                // the main file's).
                "path" => {
                    let Some(value) = self.attr(node, "value", base) else { continue };
                    let folder = dir.join(&value);
                    let found = if folder.is_dir() { Some(folder.clone()) } else { self.resolver().map(|f| f.join(&value)).find(|c| c.is_dir()) };
                    match found {
                        Some(f) => self.paths.insert(0, f),
                        None => {
                            let searched: Vec<String> = std::iter::once(folder).chain(self.resolver().map(|f| f.join(&value))).map(|f| f.display().to_string()).collect();
                            self.error(at(node), "value", format!("<path>: folder \"{value}\" not found (searched {})", searched.join(", ")));
                        }
                    }
                }
                "include" => {
                    let Some(name) = self.attr(node, "filename", base) else { continue };
                    // Beside the including file, else where Mitsuba's resolver finds it (the
                    // `<path>` folders, then the main file's: an included file's include may
                    // name a file beside the main one, as Mitsuba 3.9.1's parser.cpp allows).
                    let mut file = dir.join(&name);
                    if !file.exists() {
                        if let Some(found) = self.resolver().map(|f| f.join(&name)).find(|c| c.exists()) {
                            file = found;
                        }
                    }
                    if depth + 1 > MAX_INCLUDE_DEPTH {
                        self.error(at(node), "filename", format!("includes nest deeper than {MAX_INCLUDE_DEPTH} (a file that includes itself?)"));
                        continue;
                    }
                    match std::fs::read_to_string(&file) {
                        Ok(t) => self.file(&file, &t, depth + 1, out),
                        Err(e) => self.error(at(node), "filename", format!("cannot read included file {}: {e}", file.display())),
                    }
                }
                _ => {
                    if let Some(o) = self.object_or_ref(node, base, &dir) {
                        out.push(o);
                    }
                }
            }
        }
    }

    /// `<default name value>`: a `--define` of the same name wins, and so does a value the
    /// scene already has, as Mitsuba's parser shares one table of parameters between a file
    /// and the files it includes (src/core/parser.cpp, TagType::Default: added only where not
    /// found): a main file's `<default name="integrator" value="volpath"/>` before its
    /// `<include>` holds against the included file's `path`.
    fn default(&mut self, node: roxmltree::Node, base: usize) {
        let (Some(name), Some(value)) = (node.attribute("name"), node.attribute("value")) else {
            self.error(base + node.range().start, "", "<default> needs both name and value");
            return;
        };
        self.used.insert(name.to_string());
        if !self.defined.iter().any(|(n, _)| n == name) && !self.params.contains_key(name) {
            self.params.insert(name.to_string(), value.to_string());
        }
    }

    /// An attribute's value with `$name` substituted; `None` (with an error) when missing or
    /// when a name has no value.
    fn attr(&mut self, node: roxmltree::Node, name: &str, base: usize) -> Option<String> {
        let Some(a) = node.attributes().find(|a| a.name() == name) else {
            self.error(base + node.range().start, name, format!("<{}> needs a `{name}` attribute", node.tag_name().name()));
            return None;
        };
        self.substitute(a.value(), base + a.range_value().start, name)
    }

    fn opt_attr(&mut self, node: roxmltree::Node, name: &str, base: usize) -> Option<Option<String>> {
        match node.attributes().find(|a| a.name() == name) {
            None => Some(None),
            Some(a) => self.substitute(a.value(), base + a.range_value().start, name).map(Some),
        }
    }

    /// Replaces every `$name` (letters, digits, `_`) by its value.
    fn substitute(&mut self, text: &str, at: usize, field: &str) -> Option<String> {
        if !text.contains('$') {
            return Some(text.to_string());
        }
        let mut out = String::new();
        let mut rest = text;
        let mut ok = true;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let len = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
            let name = &after[..len];
            if name.is_empty() {
                out.push('$');
            } else if let Some(v) = self.params.get(name) {
                self.used.insert(name.to_string());
                out.push_str(&v.clone());
            } else {
                let offset = at + (text.len() - rest.len()) + i;
                self.error(offset, field, format!("`${name}` has no value: add <default name=\"{name}\" value=\"...\"/> or pass --define {name}=..."));
                ok = false;
            }
            rest = &after[len..];
        }
        out.push_str(rest);
        ok.then_some(out)
    }

    /// A plugin element, or a `<ref id>` resolved to a copy of the named object.
    fn object_or_ref(&mut self, node: roxmltree::Node, base: usize, dir: &Path) -> Option<Object> {
        let at = base + node.range().start;
        let tag = node.tag_name().name().to_string();
        if tag == "ref" {
            let id = self.attr(node, "id", base)?;
            // `<ref name="reflectance" id="wood"/>`: the named object in that parameter's place.
            let name = self.opt_attr(node, "name", base)?;
            return match self.named.get(&id) {
                Some(o) => Some(Object { name: name.or_else(|| o.name.clone()), ..o.clone() }),
                // A forward reference (Mitsuba resolves references after reading every file):
                // kept as a `<ref>`, resolved by `resolve_forward_refs`.
                None => Some(Object { tag, plugin: String::new(), id: Some(id), name, at, dir: dir.to_path_buf(), props: Vec::new(), children: Vec::new() }),
            };
        }
        if !PLUGIN_TAGS.contains(&tag.as_str()) {
            let what = if VALUE_TAGS.contains(&tag.as_str()) { "a property outside any object" } else { "not a Mitsuba 3 element pathlab knows" };
            self.error(at, "", format!("<{tag}> is {what} (objects: {})", PLUGIN_TAGS.join(", ")));
            return None;
        }
        let plugin = self.opt_attr(node, "type", base)?.unwrap_or_default();
        let id = self.opt_attr(node, "id", base)?;
        let name = self.opt_attr(node, "name", base)?;
        let mut object = Object { tag, plugin, id: id.clone(), name, at, dir: dir.to_path_buf(), props: Vec::new(), children: Vec::new() };
        for child in node.children().filter(|n| n.is_element()) {
            let child_tag = child.tag_name().name();
            if VALUE_TAGS.contains(&child_tag) || child_tag == "transform" {
                if let Some(p) = self.property(child, base, dir) {
                    if object.props.iter().any(|q| q.name == p.name) {
                        self.error(p.at, &p.name, format!("`{}` is given twice in {}", p.name, describe(&object.tag, &object.plugin)));
                    } else {
                        object.props.push(p);
                    }
                }
            } else if child_tag == "default" || child_tag == "include" {
                self.error(base + child.range().start, "", format!("<{child_tag}> must be a direct child of <scene>"));
            } else if let Some(o) = self.object_or_ref(child, base, dir) {
                object.children.push(o);
            }
        }
        if let Some(id) = id {
            if self.named.contains_key(&id) {
                self.error(at, "id", format!("id \"{id}\" is used twice"));
            }
            self.named.insert(id, object.clone());
        }
        Some(object)
    }

    /// A typed property: `<float name value>`, `<rgb>`, `<point>`, `<transform>`, ...
    fn property(&mut self, node: roxmltree::Node, base: usize, dir: &Path) -> Option<Prop> {
        let tag = node.tag_name().name();
        let at = base + node.range().start;
        let name = self.attr(node, "name", base)?;
        if tag == "spectrum" {
            if let Some(kind) = self.opt_attr(node, "type", base)? {
                return self.spectrum_plugin(node, &kind, name, at, base);
            }
            if let Some(file) = self.opt_attr(node, "filename", base)? {
                return self.spectrum_file(&file, name, at, dir);
            }
        }
        let value_attr = node.attributes().find(|a| a.name() == "value");
        let value_at = value_attr.map_or(at, |a| base + a.range_value().start);
        let numbers = |s: &str| -> Result<Vec<f64>, String> {
            s.split(|c: char| c == ',' || c.is_whitespace())
                .filter(|t| !t.is_empty())
                .map(|t| t.parse::<f64>().map_err(|_| format!("`{t}` is not a number")))
                .collect()
        };
        let value = match tag {
            "transform" => Value::Transform(self.transform(node, base)?),
            "point" | "vector" => {
                let v = match self.opt_attr(node, "value", base)? {
                    Some(text) => match numbers(&text) {
                        Ok(n) if n.len() == 3 => DVec3::new(n[0], n[1], n[2]),
                        Ok(n) if n.len() == 1 => DVec3::splat(n[0]),
                        Ok(n) => return self.bad(value_at, &name, format!("<{tag}> needs 3 numbers, got {}", n.len())),
                        Err(e) => return self.bad(value_at, &name, e),
                    },
                    None => {
                        let mut v = [0.0; 3];
                        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                            if let Some(text) = self.opt_attr(node, axis, base)? {
                                match text.trim().parse::<f64>() {
                                    Ok(x) => v[k] = x,
                                    Err(_) => return self.bad(at, &name, format!("{axis}=\"{text}\" is not a number")),
                                }
                            }
                        }
                        DVec3::from_array(v)
                    }
                };
                if tag == "point" { Value::Point(v) } else { Value::Vector(v) }
            }
            _ => {
                let text = self.attr(node, "value", base)?;
                match tag {
                    "float" => match text.trim().parse::<f64>() {
                        Ok(v) => Value::Float(v),
                        Err(_) => return self.bad(value_at, &name, format!("`{text}` is not a number")),
                    },
                    "integer" => match text.trim().parse::<i64>() {
                        Ok(v) => Value::Integer(v),
                        Err(_) => return self.bad(value_at, &name, format!("`{text}` is not an integer")),
                    },
                    "boolean" => match text.trim().to_ascii_lowercase().as_str() {
                        "true" => Value::Boolean(true),
                        "false" => Value::Boolean(false),
                        _ => return self.bad(value_at, &name, format!("`{text}` is not true or false")),
                    },
                    "string" => Value::String(text),
                    "spectrum" => match Spectrum::parse(&text) {
                        Ok(s) => Value::Spectrum(s),
                        Err(e) => return self.bad(value_at, &name, format!("<spectrum>: {e}")),
                    },
                    "rgb" => match numbers(&text) {
                        Ok(n) if n.len() == 3 => Value::Color([n[0], n[1], n[2]]),
                        Ok(n) if n.len() == 1 => Value::Color([n[0]; 3]),
                        Ok(n) => return self.bad(value_at, &name, format!("<rgb> needs 3 (or 1) numbers, got {}", n.len())),
                        Err(e) => return self.bad(value_at, &name, e),
                    },
                    _ => unreachable!("VALUE_TAGS"),
                }
            }
        };
        Some(Prop { name, value, at, value_at })
    }

    /// `<spectrum name filename="…"/>`: Mitsuba's spectral data file (`spectrum_from_file`,
    /// `.spd` only): per line a wavelength in nm and a value, separated by white space, `#`
    /// starting a comment; then the same checks as wavelength:value pairs. The file is found as
    /// Mitsuba's resolver finds it (the `<path>` folders so far, the main file's folder), else
    /// beside the XML file; a missing one names every folder searched, a bad line its line.
    fn spectrum_file(&mut self, file: &str, name: String, at: usize, dir: &Path) -> Option<Prop> {
        let mut folders = self.paths.clone();
        folders.push(self.main_dir.clone());
        let path = match resolve(&folders, file, dir) {
            Ok(path) => path,
            Err(message) => return self.bad(at, "filename", format!("spectral data file {message}")),
        };
        if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case("spd")) {
            return self.bad(at, "filename", format!("{}: Mitsuba reads spectral data files ending in .spd only", path.display()));
        }
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) => return self.bad(at, "filename", format!("cannot read spectral data file {}: {e}", path.display())),
        };
        let (mut wavelengths, mut values) = (Vec::new(), Vec::new());
        for (k, line) in text.lines().enumerate() {
            let data = line.split('#').next().unwrap_or("");
            let tokens: Vec<&str> = data.split_whitespace().collect();
            if tokens.is_empty() {
                continue;
            }
            let numbers: Result<Vec<f64>, _> = tokens.iter().map(|t| t.parse::<f64>()).collect();
            match numbers {
                Ok(n) if n.len() == 2 && n.iter().all(|x| x.is_finite()) => {
                    wavelengths.push(n[0]);
                    values.push(n[1]);
                }
                _ => return self.bad(at, "filename", format!("{}:{}: expected a wavelength and a value, got `{}`", path.display(), k + 1, line.trim())),
            }
        }
        match Spectrum::sampled(wavelengths, values) {
            Ok(spectrum) => Some(Prop { name, value: Value::Spectrum(spectrum), at, value_at: at }),
            Err(e) => self.bad(at, "filename", format!("{}: {e}", path.display())),
        }
    }

    /// `<spectrum type="blackbody" name="radiance">` with its `<float>`s `temperature`,
    /// `wavelength_min` and `wavelength_max` (default Mitsuba's CIE range); other spectrum
    /// plugins are refused.
    fn spectrum_plugin(&mut self, node: roxmltree::Node, kind: &str, name: String, at: usize, base: usize) -> Option<Prop> {
        if kind != "blackbody" {
            return self.bad(at, "type", format!("<spectrum type=\"{kind}\"> is not supported (pathlab reads <spectrum value=\"…\"/> and <spectrum type=\"blackbody\">)"));
        }
        let (mut temperature, mut min, mut max) = (None, CIE_MIN, CIE_MAX);
        let mut ok = true;
        for child in node.children().filter(|n| n.is_element()) {
            let child_at = base + child.range().start;
            let Some(p) = self.property(child, base, Path::new("")) else {
                ok = false;
                continue;
            };
            let value = match p.value {
                Value::Float(v) => v,
                Value::Integer(v) => v as f64,
                other => {
                    ok = false;
                    self.error(child_at, &p.name, format!("`{}` of a blackbody must be a <float>, not <{}>", p.name, other.kind()));
                    continue;
                }
            };
            match p.name.as_str() {
                "temperature" if value.is_finite() && value > 0.0 => temperature = Some(value),
                "temperature" => {
                    ok = false;
                    self.error(p.value_at, "temperature", format!("a blackbody's `temperature` must be a finite number of kelvin > 0 (got {value})"));
                }
                "wavelength_min" => min = value,
                "wavelength_max" => max = value,
                other => {
                    ok = false;
                    self.error(child_at, other, format!("`{other}` of a blackbody is not supported (pathlab reads: temperature, wavelength_min, wavelength_max)"));
                }
            }
        }
        if !(min.is_finite() && max.is_finite() && min < max) {
            return self.bad(at, &name, format!("a blackbody's wavelength range must be increasing (got {min} to {max} nm)"));
        }
        let Some(temperature) = temperature else {
            if ok {
                self.error(at, "temperature", "<spectrum type=\"blackbody\"> needs <float name=\"temperature\">".to_string());
            }
            return None;
        };
        ok.then(|| Prop { name, value: Value::Spectrum(Spectrum::Blackbody { temperature, min, max }), at, value_at: at })
    }

    fn bad<T>(&mut self, at: usize, field: &str, message: impl Into<String>) -> Option<T> {
        self.error(at, field, message);
        None
    }

    /// The operations of a `<transform>`.
    fn transform(&mut self, node: roxmltree::Node, base: usize) -> Option<Vec<TransformOp>> {
        let mut ops = Vec::new();
        let mut ok = true;
        for child in node.children().filter(|n| n.is_element()) {
            let at = base + child.range().start;
            let tag = child.tag_name().name();
            match self.op(child, tag, base) {
                Some(Some(kind)) => ops.push(TransformOp { kind, at }),
                Some(None) => {
                    self.error(at, tag, format!("<{tag}> is not a transform operation (translate, rotate, scale, matrix, lookat)"));
                    ok = false;
                }
                None => ok = false,
            }
        }
        ok.then_some(ops)
    }

    fn op(&mut self, node: roxmltree::Node, tag: &str, base: usize) -> Option<Option<OpKind>> {
        let at = base + node.range().start;
        let numbers = |this: &mut Self, text: &str, at: usize, field: &str| -> Option<Vec<f64>> {
            let parsed: Result<Vec<f64>, _> = text.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty()).map(str::parse::<f64>).collect();
            match parsed {
                Ok(v) => Some(v),
                Err(_) => this.bad(at, field, format!("`{text}` is not a list of numbers")),
            }
        };
        // x, y, z attributes (each defaulting to `fill`) or `value` (one number or three).
        let vec3 = |this: &mut Self, fill: f64, allow_one: bool| -> Option<DVec3> {
            if let Some(a) = node.attributes().find(|a| a.name() == "value") {
                let vat = base + a.range_value().start;
                let text = this.substitute(a.value(), vat, "value")?;
                let n = numbers(this, &text, vat, "value")?;
                return match n.len() {
                    3 => Some(DVec3::new(n[0], n[1], n[2])),
                    1 if allow_one => Some(DVec3::splat(n[0])),
                    k => this.bad(vat, "value", format!("<{tag}> needs 3 numbers, got {k}")),
                };
            }
            let mut v = [fill; 3];
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                if let Some(text) = this.opt_attr(node, axis, base)? {
                    match text.trim().parse::<f64>() {
                        Ok(x) => v[k] = x,
                        Err(_) => return this.bad(at, axis, format!("{axis}=\"{text}\" is not a number")),
                    }
                }
            }
            Some(DVec3::from_array(v))
        };
        let point = |this: &mut Self, name: &str| -> Option<DVec3> {
            let a = node.attributes().find(|a| a.name() == name);
            let Some(a) = a else { return this.bad(at, name, format!("<lookat> needs `{name}`")) };
            let vat = base + a.range_value().start;
            let text = this.substitute(a.value(), vat, name)?;
            let n = numbers(this, &text, vat, name)?;
            if n.len() != 3 {
                return this.bad(vat, name, format!("`{name}` needs 3 numbers, got {}", n.len()));
            }
            Some(DVec3::new(n[0], n[1], n[2]))
        };
        Some(Some(match tag {
            "translate" => OpKind::Translate(vec3(self, 0.0, false)?),
            "scale" => OpKind::Scale(vec3(self, 1.0, true)?),
            "rotate" => {
                let axis = vec3(self, 0.0, false)?;
                if axis == DVec3::ZERO {
                    return self.bad(at, "axis", "<rotate> has a zero axis: give x, y, z (or `value`) with a component other than 0");
                }
                let Some(angle) = self.opt_attr(node, "angle", base)? else { return self.bad(at, "angle", "<rotate> needs an angle (degrees)") };
                let Ok(angle) = angle.trim().parse::<f64>() else { return self.bad(at, "angle", format!("`{angle}` is not a number")) };
                OpKind::Rotate(axis, angle)
            }
            "matrix" => {
                let text = self.attr(node, "value", base)?;
                let vat = node.attributes().find(|a| a.name() == "value").map_or(at, |a| base + a.range_value().start);
                let n = numbers(self, &text, vat, "value")?;
                match n.len() {
                    16 => OpKind::Matrix([[n[0], n[1], n[2], n[3]], [n[4], n[5], n[6], n[7]], [n[8], n[9], n[10], n[11]], [n[12], n[13], n[14], n[15]]]),
                    9 => OpKind::Matrix([[n[0], n[1], n[2], 0.0], [n[3], n[4], n[5], 0.0], [n[6], n[7], n[8], 0.0], [0.0, 0.0, 0.0, 1.0]]),
                    k => return self.bad(vat, "value", format!("<matrix> needs 16 numbers (or 9), got {k}")),
                }
            }
            "lookat" => {
                let origin = point(self, "origin")?;
                let target = point(self, "target")?;
                let up = if node.has_attribute("up") { point(self, "up")? } else { DVec3::Y };
                OpKind::LookAt { origin, target, up }
            }
            _ => return Some(None),
        }))
    }
}

/// Elements that are plugin objects.
const PLUGIN_TAGS: [&str; 12] = ["bsdf", "shape", "emitter", "sensor", "film", "sampler", "rfilter", "integrator", "texture", "volume", "medium", "phase"];
/// Elements that are property values.
const VALUE_TAGS: [&str; 8] = ["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector"];
