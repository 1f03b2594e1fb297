//! A researcher's own sampling technique: one WGSL file (`--technique KIND:FILE.wgsl`) that
//! implements the contract of `shaders/technique.wgsl` for its kind, read and made safe to run
//! here; `shaders::technique_check_source` validates it with naga (errors at the file's own line
//! and column) and `technique` proves it with the chi-square harness before it renders.
//!
//! Made safe to run: WGSL has no recursion, so a technique can only run forever in a loop. The
//! host writes a guard at the top of every loop body (`loop`, `while`, `for`), on the same line
//! so that line numbers stay the file's: past `TECHNIQUE_MAX_ITERATIONS` iterations in one call
//! every loop of the call breaks, and the kernel counts the sample as a fault (it contributes 0,
//! and is reported), instead of hanging a GPU or being cut silently by llvmpipe's loop limit.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::method::{BadTechniqueName, TechniqueKind, TechniqueName};
use crate::names::UnknownName;

/// Loop iterations one call of a technique's function may run, over all its loops, before the
/// guard breaks them (generated into the WGSL as `TECHNIQUE_MAX_ITERATIONS`).
pub const TECHNIQUE_MAX_ITERATIONS: u32 = 256;

/// The statement the guard writes at the top of every loop body of a technique file.
pub const LOOP_GUARD: &str = "if (technique_loop_guard()) { break; } ";

/// A technique file, read and guarded.
#[derive(Debug, Clone, PartialEq)]
pub struct Technique {
    pub kind: TechniqueKind,
    /// The file's stem: the name methods use (`mis+light=NAME`).
    pub name: TechniqueName,
    pub path: PathBuf,
    /// The file as written.
    pub source: String,
    /// `source` with the loop guard at the top of every loop body (same lines).
    pub guarded: String,
    /// Loops in the file (each guarded).
    pub loops: usize,
    /// SHA-256 of the file's bytes, in hex: recorded with every result that uses it.
    pub sha256: String,
    /// Used even where it fails its check, every result that uses it marked unproven
    /// (`--allow-unproven`).
    pub allow_unproven: bool,
}

/// Why a technique cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum TechniqueError {
    #[error("--technique `{0}`: expected KIND:FILE.wgsl, KIND one of bsdf, light, env (e.g. bsdf:my_lobe.wgsl)")]
    Spec(String),
    #[error("--technique `{spec}`: {cause}")]
    Kind { spec: String, cause: UnknownName },
    #[error("{}: {cause}", path.display())]
    Name { path: PathBuf, cause: BadTechniqueName },
    #[error("cannot read technique {}: {cause}", path.display())]
    Io { path: PathBuf, cause: std::io::Error },
    #[error("{}: not UTF-8 text (a WGSL file is)", path.display())]
    NotText { path: PathBuf },
    #[error("two techniques are named `{name}` ({} and {}): a method names a technique by its file's stem", first.display(), second.display())]
    Duplicate { name: String, first: PathBuf, second: PathBuf },
    /// naga rejects the file: `message` starts with FILE:LINE:COLUMN.
    #[error("{message}")]
    Invalid { message: String },
    #[error("the method uses the {kind} technique `{name}`, which no --technique (or the scene's [techniques]) loads")]
    NotLoaded { kind: TechniqueKind, name: String },
    /// A microfacet technique of one alpha (the contract's first microfacet pair) for a scene with
    /// anisotropic roughness.
    #[error("technique {label} samples microfacet normals of one alpha (sample_microfacet_technique), and material `{material}` has anisotropic roughness: define sample_microfacet_uv_technique and pdf_microfacet_uv_technique instead, of (alpha_u, alpha_v) (shaders/technique.wgsl), render it without the technique, or make the material isotropic")]
    Anisotropic { label: String, material: String },
    /// Its check failed and it is not allowed unproven: the check's report.
    #[error("technique {label} is refused:\n{report}(allow it unproven to render with it anyway: --allow-unproven, or allow_unproven=True in Python)")]
    Refused { label: String, report: String },
}

impl Technique {
    /// Reads `KIND:FILE.wgsl`.
    pub fn from_spec(spec: &str) -> Result<Technique, TechniqueError> {
        let (kind, file) = spec.split_once(':').ok_or_else(|| TechniqueError::Spec(spec.to_string()))?;
        if file.is_empty() {
            return Err(TechniqueError::Spec(spec.to_string()));
        }
        let kind = crate::names::parse_name::<TechniqueKind>("technique kind", kind).map_err(|cause| TechniqueError::Kind { spec: spec.to_string(), cause })?;
        Technique::load(kind, file)
    }

    /// Reads a technique of `kind` from `path`; its name is the file's stem.
    pub fn load(kind: TechniqueKind, path: impl AsRef<Path>) -> Result<Technique, TechniqueError> {
        let path = path.as_ref();
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        let name = TechniqueName::new(&stem).map_err(|cause| TechniqueError::Name { path: path.to_path_buf(), cause })?;
        let bytes = std::fs::read(path).map_err(|cause| TechniqueError::Io { path: path.to_path_buf(), cause })?;
        let sha256 = Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect();
        let source = String::from_utf8(bytes).map_err(|_| TechniqueError::NotText { path: path.to_path_buf() })?;
        Ok(Technique::from_source(kind, name, path, source, sha256))
    }

    /// A technique from text (its SHA-256 is the text's).
    pub fn from_text(kind: TechniqueKind, name: TechniqueName, path: impl AsRef<Path>, source: &str) -> Technique {
        let sha256 = Sha256::digest(source.as_bytes()).iter().map(|b| format!("{b:02x}")).collect();
        Technique::from_source(kind, name, path.as_ref(), source.to_string(), sha256)
    }

    fn from_source(kind: TechniqueKind, name: TechniqueName, path: &Path, source: String, sha256: String) -> Technique {
        let (guarded, loops) = guard_loops(&source);
        Technique { kind, name, path: path.to_path_buf(), source, guarded, loops, sha256, allow_unproven: false }
    }

    /// `bsdf:NAME` (how headers and reports name it).
    pub fn label(&self) -> String {
        format!("{}:{}", self.kind.name(), self.name)
    }

    /// The lights a `light` technique samples (none for other kinds): spherical lights where the
    /// file defines `sample_light_technique` or `pdf_light_technique`, triangle lights where it
    /// defines `sample_triangle_light_technique` or `pdf_triangle_light_technique`, disk and
    /// cylinder lights where it defines `sample_disk_light_technique` or
    /// `pdf_disk_light_technique`, `sample_cylinder_light_technique` or
    /// `pdf_cylinder_light_technique` (a shape's two functions go together: one without the
    /// other is refused by validation, which names the missing one). Lights of a shape it does
    /// not define keep the built-in strategy.
    pub fn light_shapes(&self) -> LightShapes {
        if self.kind != TechniqueKind::Light {
            return LightShapes::default();
        }
        let defined = defined_functions(&self.source);
        let has = |name: &str| defined.iter().any(|f| f == name);
        LightShapes {
            spheres: has("sample_light_technique") || has("pdf_light_technique"),
            triangles: has("sample_triangle_light_technique") || has("pdf_triangle_light_technique"),
            disks: has("sample_disk_light_technique") || has("pdf_disk_light_technique"),
            cylinders: has("sample_cylinder_light_technique") || has("pdf_cylinder_light_technique"),
        }
    }

    /// The materials a `bsdf` technique samples (none for other kinds): Phong materials where
    /// the file defines `sample_bsdf_technique` or `pdf_bsdf_technique`, the microfacet normals of
    /// every rough kind (roughconductor, roughdielectric, roughplastic, principled's specular)
    /// where it defines `sample_microfacet_technique` or `pdf_microfacet_technique` (one alpha:
    /// isotropic materials only) or `sample_microfacet_uv_technique` or
    /// `pdf_microfacet_uv_technique` (alpha_u and alpha_v: anisotropic materials too). Materials it
    /// does not sample keep the built-in strategies.
    pub fn bsdf_targets(&self) -> BsdfTargets {
        if self.kind != TechniqueKind::Bsdf {
            return BsdfTargets::default();
        }
        let defined = defined_functions(&self.source);
        let has = |name: &str| defined.iter().any(|f| f == name);
        BsdfTargets {
            phong: has("sample_bsdf_technique") || has("pdf_bsdf_technique"),
            microfacet: has("sample_microfacet_technique") || has("pdf_microfacet_technique"),
            microfacet_uv: has("sample_microfacet_uv_technique") || has("pdf_microfacet_uv_technique"),
        }
    }
}

/// What a `bsdf` technique samples (`Technique::bsdf_targets`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct BsdfTargets {
    pub phong: bool,
    /// The microfacet pair of one alpha.
    pub microfacet: bool,
    /// The microfacet pair of two, (alpha_u, alpha_v).
    pub microfacet_uv: bool,
}

impl BsdfTargets {
    /// Whether it samples microfacet normals, by either pair.
    pub fn samples_microfacet(&self) -> bool {
        self.microfacet || self.microfacet_uv
    }
}

/// The shapes of light a `light` technique samples (`Technique::light_shapes`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LightShapes {
    pub spheres: bool,
    pub triangles: bool,
    pub disks: bool,
    pub cylinders: bool,
}

/// What a result records of the techniques `method` uses (`loaded` holds their files):
/// `KIND=NAME@SHA256` for each, space-separated; empty where it uses none. A technique the
/// method names but `loaded` lacks is recorded without a hash (`KIND=NAME@?`).
pub fn stamp(method: &crate::method::Method, loaded: &[Technique]) -> String {
    method
        .techniques()
        .map(|(kind, name)| {
            let sha = loaded.iter().find(|t| t.kind == kind && t.name == name).map_or("?", |t| t.sha256.as_str());
            format!("{}={name}@{sha}", kind.name())
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// `method` with the techniques of a `stamp` (their names; the hashes are for people).
pub fn method_from_stamp(method: crate::method::Method, stamp: &str) -> Result<crate::method::Method, String> {
    let mut method = method;
    for item in stamp.split_whitespace() {
        let (kind, rest) = item.split_once('=').ok_or_else(|| format!("`{item}` is not KIND=NAME@SHA256"))?;
        let kind = crate::names::parse_name::<TechniqueKind>("technique kind", kind).map_err(|e| e.to_string())?;
        let name = rest.split_once('@').map_or(rest, |(n, _)| n);
        method = method.with_technique(kind, TechniqueName::new(name).map_err(|e| e.to_string())?);
    }
    Ok(method)
}

/// The techniques a scene or command has loaded, at most one name per kind each.
pub fn check_unique(techniques: &[Technique]) -> Result<(), TechniqueError> {
    for (i, a) in techniques.iter().enumerate() {
        if let Some(b) = techniques[..i].iter().find(|b| b.name == a.name) {
            return Err(TechniqueError::Duplicate { name: a.name.to_string(), first: b.path.clone(), second: a.path.clone() });
        }
    }
    Ok(())
}

/// Walks WGSL `source` outside its comments (`//` to the end of the line, `/* */` nested):
/// `identifier(start, end)` for each identifier or keyword, `other(i)` for each other byte.
fn scan(source: &str, mut identifier: impl FnMut(usize, usize), mut other: impl FnMut(usize)) {
    let bytes = source.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        if c == b'/' && bytes.get(i + 1) == Some(&b'/') {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if c == b'/' && bytes.get(i + 1) == Some(&b'*') {
            // WGSL block comments nest.
            let mut depth = 0;
            while i < bytes.len() {
                if bytes[i] == b'/' && bytes.get(i + 1) == Some(&b'*') {
                    depth += 1;
                    i += 2;
                } else if bytes[i] == b'*' && bytes.get(i + 1) == Some(&b'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            continue;
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            identifier(start, i);
            continue;
        }
        other(i);
        i += 1;
    }
}

/// The names of the functions `source` defines (each identifier after the keyword `fn`).
pub fn defined_functions(source: &str) -> Vec<String> {
    let mut names = Vec::new();
    let after_fn = std::cell::Cell::new(false);
    scan(
        source,
        |start, end| {
            let word = &source[start..end];
            if after_fn.get() {
                names.push(word.to_string());
            }
            after_fn.set(word == "fn");
        },
        |i| {
            if !source.as_bytes()[i].is_ascii_whitespace() {
                after_fn.set(false);
            }
        },
    );
    names
}

/// `source` with `LOOP_GUARD` at the top of every loop body, and the number of loops: after the
/// `{` that opens the body of each `loop`, `while` and `for` (comments and identifiers that
/// merely contain those words are skipped; a `for` header's parentheses are skipped whole).
/// Text is only inserted, never a newline, so lines keep their numbers.
pub fn guard_loops(source: &str) -> (String, usize) {
    use std::cell::{Cell, RefCell};
    // Where each guard goes (after the byte at that index), found by the scan.
    let inserts = RefCell::new(Vec::new());
    let loops = Cell::new(0);
    // Set after a loop keyword: insert the guard after the next `{` outside parentheses.
    let pending = Cell::new(false);
    let parens = Cell::new(0i32);
    scan(
        source,
        |start, end| {
            if matches!(&source[start..end], "loop" | "while" | "for") {
                pending.set(true);
                parens.set(0);
                loops.set(loops.get() + 1);
            }
        },
        |i| {
            if !pending.get() {
                return;
            }
            match source.as_bytes()[i] {
                b'(' => parens.set(parens.get() + 1),
                b')' => parens.set(parens.get() - 1),
                b'{' if parens.get() == 0 => {
                    inserts.borrow_mut().push(i);
                    pending.set(false);
                }
                _ => {}
            }
        },
    );
    let (inserts, loops) = (inserts.into_inner(), loops.get());
    let mut out = String::with_capacity(source.len() + inserts.len() * (LOOP_GUARD.len() + 1));
    let mut copied = 0;
    for i in inserts {
        out.push_str(&source[copied..=i]);
        out.push(' ');
        out.push_str(LOOP_GUARD);
        copied = i + 1;
    }
    out.push_str(&source[copied..]);
    (out, loops)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_loop_body_gets_the_guard_and_lines_keep_their_numbers() {
        let src = "// a for loop in a comment: for (;;) {}\nfn f() -> f32 {\n  var s = 0.0;\n  for (var i = 0u; i < 4u; i++) { s += 1.0; }\n  while (s < 10.0) { s += 1.0; }\n  loop { s += 1.0; if (s > 20.0) { break; } }\n  /* loop { } */ let format = 1.0; let whiley = 2.0;\n  return s + format + whiley;\n}\n";
        let (guarded, loops) = guard_loops(src);
        assert_eq!(loops, 3);
        assert_eq!(guarded.matches(LOOP_GUARD).count(), 3);
        assert_eq!(guarded.lines().count(), src.lines().count());
        assert!(guarded.contains(&format!("for (var i = 0u; i < 4u; i++) {{ {LOOP_GUARD} s += 1.0; }}")));
        assert!(guarded.lines().next().unwrap().ends_with("for (;;) {}"), "comments are left alone");
    }

    #[test]
    fn defined_functions_are_found_outside_comments() {
        let src = "// fn commented_out() {}\nfn sample_triangle_light_technique(x: vec3f) -> vec3f { return x; }\n/* fn sample_light_technique() */\nfn  helper_fn2 (a: f32) -> f32 { let fn_like = a; return fn_like; }\n";
        assert_eq!(defined_functions(src), ["sample_triangle_light_technique", "helper_fn2"]);
        let t = Technique::from_text(TechniqueKind::Light, TechniqueName::new("t").unwrap(), "t.wgsl", src);
        assert_eq!(t.light_shapes(), LightShapes { triangles: true, ..Default::default() });
        let t = Technique::from_text(TechniqueKind::Bsdf, TechniqueName::new("t").unwrap(), "t.wgsl", src);
        assert_eq!(t.light_shapes(), LightShapes::default());
    }

    #[test]
    fn specs_name_their_kind_and_file() {
        assert!(matches!(Technique::from_spec("phong.wgsl"), Err(TechniqueError::Spec(_))));
        assert!(matches!(Technique::from_spec("lens:x.wgsl"), Err(TechniqueError::Kind { .. })));
        let e = Technique::from_spec("bsdf:/nonexistent/my_lobe.wgsl").unwrap_err();
        assert!(e.to_string().contains("/nonexistent/my_lobe.wgsl"), "{e}");
        assert!(matches!(Technique::from_spec("bsdf:/tmp/my lobe.wgsl"), Err(TechniqueError::Name { .. })));
    }
}
