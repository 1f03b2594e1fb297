//! Proving a researcher's technique before it renders (`pathlab check-technique`, and before
//! first use in every command): naga validation at the file's line and column
//! (`shaders::validate_technique`), then on configurations drawn from the scene the chi-square
//! harness (`chi2`) of the kernel-compiled sampler against its own pdf, and a coverage check.
//!
//! Configurations: for a `bsdf` technique, for Phong materials every distinct Phong material of
//! the scene (the study's three where it has none) at incidences 0, 45 and 85 degrees, for
//! microfacet normals up to four distinct rough materials of the scene at 0, 45 and 80 degrees
//! (`microfacet_configurations`); for a `light`
//! technique, for each shape it samples (`Technique::light_shapes`): every distinct radius of
//! the scene's spherical lights (1 where it has none), seen from a near point (1.5 radii from
//! the centre) and a far one (30 radii), with the shading normal towards the light and tilted 70
//! degrees from it; up to four distinct triangles of the scene's triangle lights (a right
//! triangle where it has none), each from near on its normal, near at 60 degrees, at 80 degrees
//! and far (`triangle_configurations`); disks likewise, and up to four distinct cylinders, each
//! from near, near one end, far and inside (`quadric_lights`).
//!
//! Each configuration is two tests: the chi-square test, and the coverage test, a z-test of the
//! technique's estimate of an integral against the built-in strategy's (both with the
//! configuration's samples): for a BSDF the albedo, the integral of f cos over the sphere; for
//! a light its solid angle, the integral of 1 over the directions that meet it (a surface that
//! transmits takes light from below its tangent plane too). The coverage test
//! catches a pdf that agrees with its sampler but not with the integrand: zero where the
//! integrand is not, or one whose sampler and pdf are wrong together. Before the samples are
//! binned, the support is checked on the 4 x 4 quadrature points of every cell: a point where
//! the integrand is positive and the pdf 0 is a hard failure. The verdict passes when no test
//! fails at the Šidák-corrected level for a family-wise false-rejection probability of
//! `ALPHA` = 0.01 over all tests of the check (a correct technique is refused with probability
//! at most 0.01), and nothing failed hard (a fault, a pdf that does not integrate to 1 within
//! 1e-3, samples where the pdf is 0, a reported pdf that is not the pdf function's).

mod histogram;
mod quadric_lights;

use std::path::Path;

use crate::chi2::{self, Chi2Failure, Chi2Outcome, Routine};
use crate::gpu::Gpu;
use crate::method::TechniqueKind;
use crate::scene::{Bsdf, BsdfData, Scene, Technique, TechniqueError};
use crate::shaders::{self, TechniqueFiles};

pub use histogram::write_histogram;

/// Family-wise false-rejection probability of a check of a correct technique.
pub const ALPHA: f64 = 0.01;

/// Samples per configuration by default.
pub const DEFAULT_SAMPLES: u32 = 1 << 20;

/// One configuration a technique is tested on.
#[derive(Debug, Clone)]
pub struct Configuration {
    pub name: String,
    /// The technique, as the kernel runs it.
    pub technique: Routine,
    /// The built-in strategy of its kind on the same configuration (for the coverage test).
    pub builtin: Routine,
}

/// The result of one configuration.
#[derive(Debug, Clone)]
pub struct ConfigurationResult {
    pub name: String,
    /// The chi-square test's p-value (None: a hard failure came first).
    pub p_value: Option<f64>,
    /// The coverage z-test's two-sided p-value, and the two estimates (mean, standard error).
    pub coverage: Option<(f64, (f64, f64), (f64, f64))>,
    /// A hard failure, if any.
    pub failure: Option<Chi2Failure>,
    /// The technique's binned samples, where they were binned.
    pub outcome: Option<Chi2Outcome>,
}

impl ConfigurationResult {
    /// The smaller of its p-values (0 for a hard failure).
    pub fn worst_p(&self) -> f64 {
        if self.failure.is_some() {
            return 0.0;
        }
        self.p_value.unwrap_or(0.0).min(self.coverage.map_or(1.0, |c| c.0))
    }
}

/// A technique's verdict.
#[derive(Debug, Clone)]
pub struct Verdict {
    /// `bsdf:NAME`.
    pub label: String,
    pub sha256: String,
    pub samples: u32,
    /// The per-test level (Šidák-corrected for `ALPHA` over every test of the check).
    pub level: f64,
    pub results: Vec<ConfigurationResult>,
    /// What the scene gave the configurations (or why defaults were used).
    pub source: String,
}

impl Verdict {
    /// Whether every configuration passed (and there was one: a technique the scene gives no
    /// configuration, an env technique without a map, is not proven by nothing).
    pub fn passed(&self) -> bool {
        !self.results.is_empty() && self.results.iter().all(|r| r.failure.is_none() && r.worst_p() >= self.level)
    }

    /// The configuration with the smallest p-value (a failing one first).
    pub fn worst(&self) -> Option<&ConfigurationResult> {
        self.results.iter().min_by(|a, b| a.worst_p().total_cmp(&b.worst_p()))
    }

    /// The report, one line per configuration, then the verdict.
    pub fn report(&self) -> String {
        let mut out = format!("{} (sha256 {}): {} configurations from {}, {} samples each, level {:.2e} per test (alpha {ALPHA} over the check)\n", self.label, self.sha256, self.results.len(), self.source, self.samples, self.level);
        for r in &self.results {
            let chi = r.p_value.map_or("-".to_string(), |p| format!("{p:.4}"));
            let cov = r.coverage.map_or("-".to_string(), |(p, t, b)| format!("{p:.4} (technique {:.5} ± {:.5}, built-in {:.5} ± {:.5})", t.0, t.1, b.0, b.1));
            let status = match &r.failure {
                Some(f) => format!("FAILS: {f}"),
                None if r.worst_p() < self.level => "FAILS: p below the level".to_string(),
                None => "ok".to_string(),
            };
            out += &format!("  {}: chi-square p = {chi}, coverage p = {cov}: {status}\n", r.name);
        }
        match (self.passed(), self.worst()) {
            (true, _) => out += &format!("verdict: PROVEN ({} passes every test)\n", self.label),
            (false, Some(w)) => {
                let why = match &w.failure {
                    Some(f) => f.to_string(),
                    None => format!("p = {:.3e} < {:.2e}", w.worst_p(), self.level),
                };
                out += &format!("verdict: REFUSED ({} fails at {}: {why})\n", self.label, w.name);
            }
            (false, None) => out += &format!("verdict: REFUSED ({}: {})\n", self.label, self.source),
        }
        out
    }
}

/// Options of a check.
#[derive(Debug, Clone, Copy)]
pub struct CheckOptions {
    pub samples: u32,
    pub seed: u32,
    /// Stop at the first configuration that fails hard (what a refusal needs).
    pub stop_at_failure: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        CheckOptions { samples: DEFAULT_SAMPLES, seed: 1, stop_at_failure: true }
    }
}

/// Validates `technique` (no GPU), then tests it on `scene`'s configurations.
pub fn check(gpu: &Gpu, technique: &Technique, scene: &Scene, options: CheckOptions, mut progress: impl FnMut(usize, usize, &str)) -> Result<Verdict, TechniqueError> {
    shaders::validate_technique(technique)?;
    if technique.kind == TechniqueKind::Bsdf && technique.bsdf_targets().microfacet && !technique.bsdf_targets().microfacet_uv {
        if let Some(m) = scene.materials.iter().find(|m| m.bsdf.is_anisotropic()) {
            return Err(TechniqueError::Anisotropic { label: technique.label(), material: m.name.clone() });
        }
    }
    let (configurations, source) = configurations(technique, scene);
    let tests = configurations.len() * 2;
    let level = crate::stats::sidak(ALPHA, tests.max(1));
    let files = TechniqueFiles::only(technique);
    let mut results = Vec::new();
    for (k, c) in configurations.iter().enumerate() {
        progress(k, configurations.len(), &c.name);
        let seed = options.seed.wrapping_mul(1000).wrapping_add(k as u32);
        let result = match chi2::binned(gpu, &c.technique, files, options.samples, seed) {
            Err(failure) => ConfigurationResult { name: c.name.clone(), p_value: None, coverage: None, failure: Some(failure), outcome: None },
            Ok(mut outcome) => {
                let failure = outcome.failure.take();
                let coverage = if failure.is_none() {
                    // Only the built-in's estimate is needed (the suite proves the built-in itself).
                    let builtin = chi2::binned(gpu, &c.builtin, TechniqueFiles::default(), options.samples, seed ^ 0x5eed).map_err(|e| TechniqueError::Invalid {
                        message: format!("the built-in strategy's kernel failed at {} (a bug of pathlab): {e}", c.name),
                    })?;
                    let (t, b) = (outcome.estimate, builtin.estimate);
                    // Where both estimates have no variance (cosine sampling of a diffuse BRDF:
                    // every sample is kd), only f32 rounding tells them apart: 1e-5 relative.
                    let rounding = 1e-5 * t.0.abs().max(b.0.abs());
                    let z = (t.0 - b.0) / (t.1 * t.1 + b.1 * b.1 + rounding * rounding).sqrt().max(1e-300);
                    let p = 2.0 * (1.0 - crate::stats::normal_cdf(z.abs()));
                    Some((p, t, b))
                } else {
                    None
                };
                ConfigurationResult { name: c.name.clone(), p_value: Some(outcome.p_value), coverage, failure, outcome: Some(outcome) }
            }
        };
        let hard = result.failure.is_some();
        results.push(result);
        if hard && options.stop_at_failure {
            break;
        }
    }
    Ok(Verdict { label: technique.label(), sha256: technique.sha256.clone(), samples: options.samples, level, results, source })
}

/// What the results of `method` on `scene` record of its techniques (`technique_verdict`):
/// `None` where it uses none, `proven`, or `UNPROVEN: ...` where a technique allowed unproven
/// failed its check; a failing technique not allowed is refused (`TechniqueError::Refused`).
pub fn prove(gpu: &Gpu, scene: &Scene, method: &crate::method::Method) -> Result<Option<String>, TechniqueError> {
    let verdicts = verdicts(gpu, scene, method)?;
    if verdicts.is_empty() {
        return Ok(None);
    }
    let files = TechniqueFiles::of(method, &scene.techniques)?;
    let mut unproven = Vec::new();
    for (v, t) in verdicts.iter().zip(files.all()) {
        if !v.passed() {
            if !t.allow_unproven {
                return Err(TechniqueError::Refused { label: v.label.clone(), report: v.report() });
            }
            unproven.push(v.label.clone());
        }
    }
    Ok(Some(if unproven.is_empty() { "proven".to_string() } else { format!("UNPROVEN: {} failed the check (allowed unproven)", unproven.join(", ")) }))
}

/// The verdicts of the techniques `method` uses on `scene`, each checked once per process for
/// its file's hash and the scene's content (`check` with the default options).
pub fn verdicts(gpu: &Gpu, scene: &Scene, method: &crate::method::Method) -> Result<Vec<Verdict>, TechniqueError> {
    use std::collections::HashMap;
    use std::sync::{Mutex, OnceLock};
    static CACHE: OnceLock<Mutex<HashMap<(String, String), Verdict>>> = OnceLock::new();
    let files = TechniqueFiles::of(method, &scene.techniques)?;
    let mut verdicts = Vec::new();
    for t in files.all() {
        let key = (t.sha256.clone(), scene.content_hash());
        let cached = CACHE.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner()).get(&key).cloned();
        let verdict = match cached {
            Some(v) => v,
            None => {
                let v = check(gpu, t, scene, CheckOptions::default(), |_, _, _| {})?;
                CACHE.get_or_init(Default::default).lock().unwrap_or_else(|e| e.into_inner()).insert(key, v.clone());
                v
            }
        };
        verdicts.push(verdict);
    }
    Ok(verdicts)
}

/// The configurations of `technique` on `scene`, and where they came from.
pub fn configurations(technique: &Technique, scene: &Scene) -> (Vec<Configuration>, String) {
    match technique.kind {
        TechniqueKind::Bsdf => {
            let targets = technique.bsdf_targets();
            gather(scene, &[(targets.phong, phong_configurations), (targets.samples_microfacet(), microfacet_configurations)])
        }
        TechniqueKind::Light => {
            let shapes = technique.light_shapes();
            gather(
                scene,
                &[
                    (shapes.spheres, sphere_configurations),
                    (shapes.triangles, triangle_configurations),
                    (shapes.disks, quadric_lights::disk_configurations),
                    (shapes.cylinders, quadric_lights::cylinder_configurations),
                ],
            )
        }
        TechniqueKind::Env => match &scene.environment_map {
            Some(map) => {
                let packed = map.pack();
                let name = map.file.file_name().map_or_else(|| map.file.display().to_string(), |n| n.to_string_lossy().into_owned());
                let configs = [([0.0, 1.0, 0.0], "up (+y)"), ([1.0, 0.0, 0.0], "the horizon (+x)"), ([0.0, -1.0, 0.0], "down (-y)")]
                    .map(|(n, what)| environment_configuration(&packed, n, what))
                    .into();
                (configs, format!("the scene's environment map {name}, normals up, at the horizon and down"))
            }
            None => (Vec::new(), "no configuration: an env technique samples an environment map, and the scene has none".to_string()),
        },
    }
}

/// The configurations of the parts of a technique's kind that it implements (each `(implemented,
/// its configurations)`), one after the other, and their sources.
fn gather(scene: &Scene, parts: &[(bool, fn(&Scene) -> (Vec<Configuration>, String))]) -> (Vec<Configuration>, String) {
    let mut configs = Vec::new();
    let mut sources = Vec::new();
    for (implemented, part) in parts {
        if *implemented {
            let (c, source) = part(scene);
            configs.extend(c);
            sources.push(source);
        }
    }
    (configs, sources.join("; "))
}

/// A Phong technique's configurations: every distinct Phong material of the scene (the study's
/// three where it has none) at incidences 0, 45 and 85 degrees.
fn phong_configurations(scene: &Scene) -> (Vec<Configuration>, String) {
    let mut materials: Vec<([f64; 3], [f64; 3], f64, f64)> = Vec::new();
    for m in &scene.materials {
        if let Some(p) = m.bsdf.as_phong() {
            let [_, p1, _, _] = Bsdf::Phong(p.clone()).pack(&mut BsdfData::default());
            let key = (p.diffuse.to_array(), p.specular.to_array(), p.glossiness, p1[3] as f64);
            if !materials.contains(&key) {
                materials.push(key);
            }
        }
    }
    let source = if materials.is_empty() {
        // The study's diffuse, glossy and mostly specular materials.
        materials = vec![([0.8; 3], [0.0; 3], 1.0, 0.0), ([0.5; 3], [0.5; 3], 20.0, 0.5), ([0.1; 3], [0.9; 3], 200.0, 0.9)];
        "the study's materials (the scene has no Phong material, where a bsdf technique applies)".to_string()
    } else {
        format!("the scene's {} Phong material(s)", materials.len())
    };
    let configs = materials
        .iter()
        .flat_map(|&(kd, ks, n, p_spec)| [0.0, 45.0, 85.0].map(move |theta| phong_configuration(kd, ks, n, p_spec, theta)))
        .collect();
    (configs, source)
}

/// Microfacet materials a microfacet technique is checked on, at most.
const MAX_MICROFACET_MATERIALS: usize = 4;

/// A microfacet technique's configurations: up to `MAX_MICROFACET_MATERIALS` distinct
/// (distribution, alpha_u, alpha_v, transmits) of the scene's rough materials, the first of each
/// class (distribution, transmits, anisotropic) before the others (a texture's mean
/// roughness; principled's alpha max(0.001, roughness^2) of GGX, divided and multiplied by
/// sqrt(1 - 0.9 anisotropic) along u and v; where it has none, GGX of 0.1 and 0.5 and Beckmann
/// of 0.3, reflecting), each at incidences 0, 45 and 80 degrees (for an anisotropic roughness,
/// at 30 degrees of azimuth from u: along neither axis).
fn microfacet_configurations(scene: &Scene) -> (Vec<Configuration>, String) {
    use crate::scene::Distribution;
    let mut materials: Vec<(Distribution, [f64; 2], bool)> = Vec::new();
    let uv = |r: &crate::scene::Roughness| [r.alpha, r.alpha_v.unwrap_or(r.alpha)];
    // Principled's (alpha_u, alpha_v) of its roughness and anisotropy.
    let principled = |roughness: f64, anisotropic: f64| {
        let (r2, aspect) = (roughness.powi(2), (1.0 - 0.9 * anisotropic).sqrt());
        [(r2 / aspect).max(0.001), (r2 * aspect).max(0.001)]
    };
    for m in &scene.materials {
        let key = match &m.bsdf {
            Bsdf::RoughConductor(c) => (c.distribution, uv(&c.roughness), false),
            Bsdf::RoughPlastic(p) => (p.distribution, [p.alpha; 2], false),
            Bsdf::RoughDielectric(d) => (d.distribution, uv(&d.roughness), true),
            Bsdf::Principled(p) => (Distribution::Ggx, principled(p.weight("roughness"), p.anisotropic.value), m.bsdf.transmits()),
            Bsdf::PrincipledThin(p) => (Distribution::Ggx, principled(p.weight("roughness"), p.weight("anisotropic")), false),
            Bsdf::PolarizedPlastic(p) => (p.distribution, uv(&p.roughness), false),
            _ => continue,
        };
        if !materials.contains(&key) {
            materials.push(key);
        }
    }
    // The first material of each class (distribution, transmits, anisotropic), then the others
    // in the scene's order, up to MAX_MICROFACET_MATERIALS.
    let class = |&(d, alpha_uv, transmits): &(Distribution, [f64; 2], bool)| (d, transmits, alpha_uv[0] != alpha_uv[1]);
    let (mut firsts, mut rest): (Vec<_>, Vec<_>) = (Vec::new(), Vec::new());
    for m in materials {
        if firsts.iter().any(|f| class(f) == class(&m)) {
            rest.push(m);
        } else {
            firsts.push(m);
        }
    }
    let mut materials: Vec<_> = firsts.into_iter().chain(rest).take(MAX_MICROFACET_MATERIALS).collect();
    let source = if materials.is_empty() {
        materials = vec![(Distribution::Ggx, [0.1; 2], false), (Distribution::Ggx, [0.5; 2], false), (Distribution::Beckmann, [0.3; 2], false)];
        "GGX of alpha 0.1 and 0.5 and Beckmann of 0.3, reflecting (the scene has no microfacet material, where a microfacet technique applies)".to_string()
    } else {
        format!("the scene's {} microfacet material(s)", materials.len())
    };
    let configs = materials
        .iter()
        .flat_map(|&(d, alpha_uv, transmits)| [0.0, 45.0, 80.0].map(move |theta| microfacet_configuration(d, alpha_uv, transmits, theta)))
        .collect();
    (configs, source)
}

/// Microfacet normals of `distribution` and roughness `alpha_uv` seen from incidence `theta`
/// degrees (the macro-normal +z; for an anisotropic roughness, at 30 degrees of azimuth from the
/// frame's x, where alpha_u lies): the technique through `sample_microfacet_uv` and
/// `pdf_microfacet_uv` (what every rough kind calls), and the built-in visible normals (the
/// anisotropic formulas compiled in, `ANISOTROPIC_ROUGHNESS`, where alpha_u and alpha_v differ).
/// Binned about the macro-normal, in s bins spaced geometrically from alpha^2 / 10 (a tenth of
/// the normals' spread in s, of the smaller alpha) up to alpha 0.3. The integrand is the visible
/// normals' density over the normals the material needs: those whose mirror direction of wo is
/// above the surface for a reflecting material, every visible one for one that `transmits` (a
/// rough dielectric refracts about them): its integral is the share of visible normals that
/// scatter, which the coverage test compares.
fn microfacet_configuration(distribution: crate::scene::Distribution, alpha_uv: [f64; 2], transmits: bool, theta: f64) -> Configuration {
    let t = theta.to_radians();
    let anisotropic = alpha_uv[0] != alpha_uv[1];
    let phi = if anisotropic { 30f64.to_radians() } else { 0.0 };
    let common = format!(
        "const ROUTINE_WO: vec3f = vec3f({:?}, {:?}, {:?});\n\
         const ROUTINE_ALPHA_UV: vec2f = vec2f({:?}, {:?});\n\
         const ROUTINE_DISTRIBUTION: u32 = {}u;\n\
         const ROUTINE_TRANSMITS: bool = {transmits};\n\
         fn routine_integrand(d: vec3f) -> f32 {{\n\
             let visible = pdf_visible_normals(ROUTINE_WO, d, ROUTINE_ALPHA_UV, ROUTINE_DISTRIBUTION);\n\
             let mirrored = 2.0 * dot(ROUTINE_WO, d) * d - ROUTINE_WO;\n\
             return select(0.0, visible, d.z > 0.0 && (ROUTINE_TRANSMITS || mirrored.z > 0.0));\n\
         }}\n\
         fn routine_pdf(d: vec3f) -> f32 {{ return select(0.0, pdf_microfacet_uv(ROUTINE_WO, d, ROUTINE_ALPHA_UV, ROUTINE_DISTRIBUTION), d.z > 0.0); }}\n\
         fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
             let s = sample_microfacet_uv(ROUTINE_WO, u, ROUTINE_ALPHA_UV, ROUTINE_DISTRIBUTION);\n\
             let estimate = select(0.0, routine_integrand(s.m) / s.pdf, s.pdf > 0.0);\n\
             return Drawn(vec4f(s.m, s.pdf), vec4f(0.0, 0.0, estimate, 0.0));\n\
         }}\n",
        (t.sin() * phi.cos()) as f32,
        (t.sin() * phi.sin()) as f32,
        t.cos() as f32,
        alpha_uv[0] as f32,
        alpha_uv[1] as f32,
        distribution.constant(),
    );
    // (To 4 decimals: a principled material's alpha is a product.)
    let [u, v] = alpha_uv.map(|a| (a * 1e4).round() / 1e4);
    let roughness = if anisotropic { format!("alpha_u={u} alpha_v={v}") } else { format!("alpha={u}") };
    let azimuth = if anisotropic { ", 30 degrees from u" } else { "" };
    let name = format!("{} {roughness} ({}) at {theta} degrees{azimuth}", distribution.name(), if transmits { "reflecting and refracting" } else { "reflecting" });
    let with = |constant: (&'static str, f64)| {
        let mut constants = vec![constant];
        if anisotropic {
            constants.push(("ANISOTROPIC_ROUGHNESS", 1.0));
        }
        constants
    };
    let alpha = alpha_uv[0].min(alpha_uv[1]);
    Pair {
        name,
        technique: (common.clone(), with(("BSDF_TECHNIQUE", 1.0))),
        builtin: (common, with(("MICROFACET_SAMPLING", crate::method::MicrofacetSampling::Vndf.constant() as f64))),
        s_split: if alpha <= 0.3 { -(alpha * alpha / 10.0).max(1e-12) } else { 2.0 },
        pdf_tolerance: 1e-3,
        pdf_floor: 1e-30,
        bins: chi2::DEFAULT_BINS,
        environment_map: Vec::new(),
    }
    .configuration()
}

/// A spherical-light technique's configurations: every distinct radius of the scene's spherical
/// lights (1 where it has none), from near and far, the normal towards the light and tilted.
fn sphere_configurations(scene: &Scene) -> (Vec<Configuration>, String) {
    let mut radii: Vec<f64> = Vec::new();
    for l in scene.lights_of(crate::scene::EmitterKind::Sphere) {
        if let crate::scene::Light::Sphere(s) = l {
            let radius = scene.spheres[s].radius;
            if !radii.contains(&radius) {
                radii.push(radius);
            }
        }
    }
    let source = if radii.is_empty() {
        radii.push(1.0);
        "a unit sphere (the scene has no spherical light, where a light technique applies)".to_string()
    } else {
        format!("the scene's {} spherical light radius(es)", radii.len())
    };
    let configs = radii
        .iter()
        .flat_map(|&r| [(1.5, 0.0), (1.5, 70.0), (30.0, 0.0), (30.0, 70.0)].map(move |(ratio, tilt)| sphere_configuration(r, ratio, tilt)))
        .collect();
    (configs, source)
}

/// Triangle lights a triangle-light technique is checked on, at most.
const MAX_TRIANGLES: usize = 4;

/// A triangle-light technique's configurations: up to `MAX_TRIANGLES` distinct triangles of the
/// scene's emissive meshes (distinct in shape: their edges differ; the first ones of the scene,
/// a right triangle where it has none), each seen from four points: near (half the triangle's
/// size, sqrt(area), from its centroid) on its normal, with the shading normal towards it;
/// near and 60 degrees off its normal; at 80 degrees, nearly in its plane (where a
/// solid-angle density varies most over the triangle); far (30 sizes) on its normal, the
/// shading normal tilted 70 degrees.
fn triangle_configurations(scene: &Scene) -> (Vec<Configuration>, String) {
    let mut triangles: Vec<[glam::DVec3; 3]> = Vec::new();
    for l in scene.lights_of(crate::scene::EmitterKind::Triangle) {
        if let crate::scene::Light::Triangle { mesh, triangle } = l {
            let m = &scene.meshes[mesh];
            let p = m.triangles[triangle].map(|v| m.positions[v as usize]);
            let edges = |t: &[glam::DVec3; 3]| (t[1] - t[0], t[2] - t[0]);
            if !triangles.iter().any(|t| edges(t) == edges(&p)) {
                triangles.push(p);
            }
            if triangles.len() == MAX_TRIANGLES {
                break;
            }
        }
    }
    let source = if triangles.is_empty() {
        triangles.push([glam::DVec3::ZERO, glam::DVec3::X, glam::DVec3::Y]);
        "a right triangle of unit legs (the scene has no triangle light, where a triangle-light technique applies)".to_string()
    } else {
        format!("{} of the scene's triangle lights", triangles.len())
    };
    let configs = triangles
        .iter()
        .enumerate()
        .flat_map(|(k, &p)| [(0.5, 0.0, 0.0), (0.5, 60.0, 0.0), (1.0, 80.0, 0.0), (30.0, 0.0, 70.0)].map(move |(dist, angle, tilt)| triangle_configuration(k, p, dist, angle, tilt)))
        .collect();
    (configs, source)
}

fn v3(v: [f64; 3]) -> String {
    format!("vec3f({:?}, {:?}, {:?})", v[0] as f32, v[1] as f32, v[2] as f32)
}

/// A Phong material (kd, ks, exponent n, the lobe probability of pathlab's mixture) at
/// incidence `theta` degrees, shading normal +z: the technique through `sample_phong_technique`
/// and `pdf_phong_technique` (what the path tracer calls), and the built-in mixture. Binned
/// around the mirror direction, in s bins spaced geometrically from 0.1 / (n + 1) (a tenth of
/// the Phong lobe's width in s): the study's exponents reach 3000, a lobe a few cells wide on a
/// uniform grid.
fn phong_configuration(kd: [f64; 3], ks: [f64; 3], n: f64, p_spec: f64, theta: f64) -> Configuration {
    let t = theta.to_radians();
    let common = format!(
        "fn routine_material() -> Phong {{ return Phong({}, {}, {:?}, {:?}); }}\n\
         fn routine_wo() -> vec3f {{ return vec3f({:?}, 0.0, {:?}); }}\n\
         // The binning frame: +z along the mirror direction of wo.\n\
         fn routine_frame() -> Frame {{ return frame_from_normal(vec3f({:?}, 0.0, {:?})); }}\n\
         fn routine_integrand(d: vec3f) -> f32 {{\n\
             let wi = frame_to_world(routine_frame(), d);\n\
             let f = eval_phong(routine_material(), vec3f(0.0, 0.0, 1.0), routine_wo(), wi);\n\
             return (f.x + f.y + f.z) / 3.0 * max(wi.z, 0.0);\n\
         }}\n",
        v3(kd),
        v3(ks),
        n as f32,
        p_spec as f32,
        t.sin() as f32,
        t.cos() as f32,
        -t.sin() as f32,
        t.cos() as f32,
    );
    let routine = |sample: &str, pdf: &str| -> String {
        format!(
            "{common}\
             fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
                 let m = routine_material(); let n_s = vec3f(0.0, 0.0, 1.0); let wo = routine_wo();\n\
                 let bs = {sample}(m, n_s, wo, u, u_lobe);\n\
                 let expect = path_weight(eval_phong(m, n_s, wo, bs.wi), dot(bs.wi, n_s), bs.pdf);\n\
                 let err = max3(abs(bs.weight - expect)) / max(max3(abs(expect)), 1e-30);\n\
                 let estimate = (bs.weight.x + bs.weight.y + bs.weight.z) / 3.0;\n\
                 return Drawn(vec4f(frame_to_local(routine_frame(), bs.wi), bs.pdf), vec4f(err, 0.0, estimate, 0.0));\n\
             }}\n\
             fn routine_pdf(d: vec3f) -> f32 {{ let wi = frame_to_world(routine_frame(), d); return {pdf}; }}\n"
        )
    };
    let name = format!("phong kd={:.3} ks={:.3} n={n} at {theta} degrees", kd[1], ks[1]);
    Pair {
        name,
        technique: (routine("sample_phong_technique", "pdf_phong_technique(routine_material(), vec3f(0.0, 0.0, 1.0), routine_wo(), wi)"), vec![("BSDF_TECHNIQUE", 1.0)]),
        builtin: (
            routine("sample_phong", "eval_pdf_phong(routine_material(), vec3f(0.0, 0.0, 1.0), routine_wo(), wi).pdf"),
            vec![("BSDF_SAMPLING", crate::method::BsdfSampling::Phong.constant() as f64), ("HAS_SPECULAR", 1.0)],
        ),
        s_split: -(0.1 / (n + 1.0)).min(1e-2),
        // The direction's round trip through the binning frame moves its cosine to the mirror
        // direction by a few ulps of 1 (6e-8 each; measured up to 2.4e-7 at 85 degrees): a
        // density cos^n computed from an f32 cosine then moves by up to ~n 2.4e-7 relative.
        pdf_tolerance: 1e-4 + 4e-7 * n,
        // (Densities are of order 1 / pi: 1e-6 absolute, where the round trip moves the cosine
        // lobe by ~3e-8 at the horizon.)
        pdf_floor: 1e-2,
        bins: chi2::DEFAULT_BINS,
        environment_map: Vec::new(),
    }
    .configuration()
}

/// A sphere of `radius` at `ratio` radii from the shading point x (the origin), whose shading
/// normal is tilted `tilt` degrees from the direction to the sphere's centre: the technique
/// through `sample_sphere_light_technique` and `pdf_sphere_light_technique` (what the path
/// tracer calls), and the built-in cone. The technique's samples are binned where they land on
/// the sphere, by the direction d from the centre (+z towards x: the centre is at -z): the
/// density there is the solid-angle density at x times cos(theta_light) r^2 / dist^2, finite
/// up to the edge of the visible cap (s = 1 - r / dist_centre, a bin edge), where the
/// solid-angle density of sampling by area diverges and 4 x 4 quadrature points over the
/// directions at x could not integrate it. Points beyond the cap are hidden by the sphere:
/// lost samples, which contribute nothing. The integrand is 1 over the directions that meet the
/// sphere (a transmitting surface takes light from below its tangent plane too): the coverage
/// test compares estimates of the light's solid angle.
fn sphere_configuration(radius: f64, ratio: f64, tilt: f64) -> Configuration {
    let s_cap = 1.0 - 1.0 / ratio;
    let t = tilt.to_radians();
    let common = format!(
        "const ROUTINE_C: vec3f = vec3f(0.0, 0.0, {:?});\n\
         const ROUTINE_R: f32 = {:?};\n\
         const ROUTINE_S_CAP: f32 = {:?};\n\
         fn routine_n() -> vec3f {{ return vec3f({:?}, 0.0, {:?}); }}\n\
         // The point of the sphere in direction d from its centre, and whether x sees it.\n\
         fn routine_point(d: vec3f) -> vec3f {{ return ROUTINE_C + ROUTINE_R * d; }}\n\
         fn routine_visible(d: vec3f) -> bool {{ return 1.0 - d.z < ROUTINE_S_CAP; }}\n\
         // d(solid angle at x) / d(solid angle of d at the centre): cos(theta_light) r^2 / dist^2.\n\
         fn routine_jacobian(d: vec3f) -> f32 {{\n\
             let to_x = -routine_point(d);\n\
             let dist2 = dot(to_x, to_x);\n\
             return max(dot(d, to_x), 0.0) / sqrt(dist2) * ROUTINE_R * ROUTINE_R / dist2;\n\
         }}\n\
         // 1 over the directions that meet the sphere (its solid angle): a surface that transmits\n\
         // takes light from below its tangent plane too, so the support is the whole visible cap.\n\
         fn routine_integrand(d: vec3f) -> f32 {{ return select(0.0, routine_jacobian(d), routine_visible(d)); }}\n\
         // The technique's density at the point p itself (the path tracer's wrapper finds p again\n\
         // from the direction, which f32 conditions badly where the sight line grazes the sphere).\n\
         fn routine_technique_pdf(p: vec3f) -> f32 {{\n\
             technique_iterations = 0u;\n\
             return technique_density(pdf_light_technique(vec3f(0.0), routine_n(), SphereLight(ROUTINE_C, ROUTINE_R), p));\n\
         }}\n",
        -(radius * ratio) as f32,
        radius as f32,
        s_cap as f32,
        t.sin() as f32,
        -t.cos() as f32,
    );
    let technique = format!(
        "{common}\
         fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
             let ls = sample_sphere_light_technique(ROUTINE_C, ROUTINE_R, vec3f(0.0), routine_n(), u);\n\
             let p = ls.wi * ls.dist;\n\
             let d = normalize(p - ROUTINE_C);\n\
             let far = dot(p - ROUTINE_C, -p) <= 0.0;\n\
             let pdf = routine_technique_pdf(p);\n\
             let estimate = select(0.0, 1.0 / pdf, !far && pdf > 0.0);\n\
             // (The technique reports no density of its own: pathlab asks its pdf, as here.)\n\
             return Drawn(vec4f(d, routine_pdf(d)), vec4f(0.0, select(0.0, 1.0, far), estimate, 0.0));\n\
         }}\n\
         fn routine_pdf(d: vec3f) -> f32 {{\n\
             if (!routine_visible(d)) {{ return 0.0; }}\n\
             return routine_technique_pdf(routine_point(d)) * routine_jacobian(d);\n\
         }}\n"
    );
    let builtin = format!(
        "{common}\
         fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
             let ls = sample_sphere_light_cone(ROUTINE_C, ROUTINE_R, vec3f(0.0), u);\n\
             let estimate = select(0.0, 1.0 / ls.pdf, ls.pdf > 0.0);\n\
             return Drawn(vec4f(ls.wi, ls.pdf), vec4f(0.0, 0.0, estimate, 0.0));\n\
         }}\n\
         fn routine_pdf(d: vec3f) -> f32 {{ return pdf_sphere_light(ROUTINE_C, ROUTINE_R, vec3f(0.0), false, d); }}\n"
    );
    let name = format!("sphere r={radius} seen from {ratio} radii, normal tilted {tilt} degrees");
    // The edge of the visible cap is a bin edge.
    Pair::light(name, (technique, vec![("LIGHT_TECHNIQUE", 1.0)]), (builtin, vec![]), s_cap, chi2::DEFAULT_BINS, Vec::new())
}

/// WGSL of the unit square (u0, u1) written as binning directions, s = 1 - cos = 2 u0 and
/// phi = 2 pi u1, for lights binned on a square they are the image of (the harness's cells then
/// tile the square): `routine_s`, `routine_uv` (a binning direction's (u0, u1)) and
/// `routine_dir` (back). d(binning solid angle) = 4 pi du0 du1.
const SQUARE_AS_DIRECTIONS: &str = "\
fn routine_s(d: vec3f) -> f32 { return select(1.0 - d.z, (d.x * d.x + d.y * d.y) / (1.0 + d.z), d.z > 0.0); }
// (u0, u1) of a binning direction, and the binning direction of (u0, u1).
fn routine_uv(d: vec3f) -> vec2f {
    var u1 = atan2_accurate(d.y, d.x) * (0.5 * INV_PI);
    u1 = u1 - floor(u1);
    return vec2f(clamp(0.5 * routine_s(d), 0.0, 1.0), u1);
}
fn routine_dir(uv: vec2f) -> vec3f {
    let s = 2.0 * uv.x;
    let sin_t = safe_sqrt(s * (2.0 - s));
    return vec3f(sin_t * cos(2.0 * PI * uv.y), sin_t * sin(2.0 * PI * uv.y), 1.0 - s);
}
";

/// A planar light (a triangle, a disk) of `area` and unit `normal` seen from a point at `dist`
/// times its size (sqrt(area)) from its centre (the origin), `angle` degrees off its normal
/// (towards `along`, in its plane), whose shading normal is tilted `tilt` degrees from the
/// direction to the centre: the point x and its shading normal n.
fn planar_viewpoint(normal: glam::DVec3, along: glam::DVec3, area: f64, dist: f64, angle: f64, tilt: f64) -> (glam::DVec3, glam::DVec3) {
    let (a, t) = (angle.to_radians(), tilt.to_radians());
    let x = dist * area.sqrt() * (a.cos() * normal + a.sin() * along);
    let towards = (-x).normalize();
    let side = towards.cross(normal).try_normalize().unwrap_or(along);
    (x, t.cos() * towards + t.sin() * side)
}

/// The configuration of a planar light binned on a unit square it is the image of by an
/// area-preserving map (`light`: WGSL defining its constants, `routine_point(uv)` and
/// `routine_uv_of(p)`), seen from x (`ROUTINE_X`, shading normal `ROUTINE_N`; its plane's
/// normal `ROUTINE_NT`, area `ROUTINE_AREA`): the density in the square is the solid-angle
/// density at x times d(omega) / d(bins) = |cos(theta_light)| / dist^2 x area / (4 pi), finite
/// even where the sight line grazes the light, and the integrand that Jacobian (1 over the
/// directions that meet the light: the coverage test compares estimates of its solid angle).
/// The technique is asked its density at p (`technique_pdf`, a WGSL expression of p) and
/// sampled by `technique_sample` (of u, giving a LightSample), the built-in likewise.
fn planar_light_configuration(name: String, light: String, technique: (&str, &str), builtin: (&str, &str), builtin_constants: Vec<(&'static str, f64)>) -> Configuration {
    let common = format!(
        "{light}{SQUARE_AS_DIRECTIONS}\
         // d(solid angle at x) / d(binning solid angle) at the light's point p.\n\
         fn routine_jacobian(p: vec3f) -> f32 {{\n\
             let to_x = ROUTINE_X - p;\n\
             let dist2 = dot(to_x, to_x);\n\
             return abs(dot(ROUTINE_NT, to_x)) / (sqrt(dist2) * dist2) * ROUTINE_AREA * (0.25 * INV_PI);\n\
         }}\n\
         fn routine_integrand(d: vec3f) -> f32 {{ return routine_jacobian(routine_point(routine_uv(d))); }}\n"
    );
    let routines = |pdf: &str, sample: &str| {
        format!(
            "{common}\
             fn routine_pdf(d: vec3f) -> f32 {{ let p = routine_point(routine_uv(d)); return {pdf} * routine_jacobian(p); }}\n\
             fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
                 let ls = {sample};\n\
                 let d = routine_dir(routine_uv_of(ROUTINE_X + ls.wi * ls.dist));\n\
                 let estimate = select(0.0, 1.0 / ls.pdf, ls.pdf > 0.0);\n\
                 // (A technique reports no density of its own: pathlab asks its pdf, as here.)\n\
                 return Drawn(vec4f(d, routine_pdf(d)), vec4f(0.0, 0.0, estimate, 0.0));\n\
             }}\n"
        )
    };
    // The technique's density at the point p itself, its iterations counted from 0.
    let technique_routines = format!(
        "fn routine_technique_pdf(p: vec3f) -> f32 {{\n\
             technique_iterations = 0u;\n\
             return technique_density({});\n\
         }}\n{}",
        technique.0,
        routines("routine_technique_pdf(p)", technique.1)
    );
    Pair::light(name, (technique_routines, vec![("LIGHT_TECHNIQUE", 1.0)]), (routines(builtin.0, builtin.1), builtin_constants), 2.0, (64, 64), Vec::new())
}

/// Triangle `k` with vertices `p` seen from a point at `dist` times its size (sqrt(area)) from its
/// centroid, `angle` degrees off its winding normal (towards its first edge), whose shading
/// normal is tilted `tilt` degrees from the direction to the centroid (`planar_viewpoint`): the
/// technique through `sample_triangle_light_with_technique` and `pdf_triangle_light_technique`
/// (what the path tracer calls), and the built-in solid-angle strategy. Coordinates are taken
/// relative to the centroid (the technique's maths is the same anywhere; f32 keeps its
/// precision). The samples are binned where they land on the triangle, on the unit square it
/// is the image of under the area warp (u0 = (b1 + b2)^2, u1 = b2 / (b1 + b2)): 64 x 64 cells
/// tile the triangle exactly, none cut by an edge (`planar_light_configuration`).
fn triangle_configuration(k: usize, p: [glam::DVec3; 3], dist: f64, angle: f64, tilt: f64) -> Configuration {
    let centroid = (p[0] + p[1] + p[2]) / 3.0;
    let p = p.map(|v| v - centroid);
    let c = (p[1] - p[0]).cross(p[2] - p[0]);
    let (area, normal) = (0.5 * c.length(), c.normalize());
    let (x, n) = planar_viewpoint(normal, (p[1] - p[0]).normalize(), area, dist, angle, tilt);
    let v = |v: glam::DVec3| v3(v.to_array());
    let light = format!(
        "const ROUTINE_P0: vec3f = {};\nconst ROUTINE_P1: vec3f = {};\nconst ROUTINE_P2: vec3f = {};\n\
         const ROUTINE_X: vec3f = {};\nconst ROUTINE_N: vec3f = {};\nconst ROUTINE_NT: vec3f = {};\nconst ROUTINE_AREA: f32 = {:?};\n\
         fn routine_tri() -> TriangleLight {{ return TriangleLight(ROUTINE_P0, ROUTINE_P1, ROUTINE_P2); }}\n\
         // The triangle's point at (u0, u1) of the area warp.\n\
         fn routine_point(uv: vec2f) -> vec3f {{ let s = sqrt(uv.x); return (1.0 - s) * ROUTINE_P0 + (s * (1.0 - uv.y)) * ROUTINE_P1 + (s * uv.y) * ROUTINE_P2; }}\n\
         // (u0, u1) of a point of the triangle, from its barycentrics b1, b2.\n\
         fn routine_uv_of(p: vec3f) -> vec2f {{\n\
             let b = plane_barycentrics(ROUTINE_P0, ROUTINE_P1, ROUTINE_P2, p);\n\
             let sum = clamp(b.x + b.y, 0.0, 1.0);\n\
             return vec2f(sum * sum, select(0.0, clamp(b.y / sum, 0.0, 0.99999994), sum > 0.0));\n\
         }}\n",
        v(p[0]),
        v(p[1]),
        v(p[2]),
        v(x),
        v(n),
        v(normal),
        area as f32,
    );
    planar_light_configuration(
        format!("triangle {k} (area {area:.4}) seen from {dist} sizes, {angle} degrees off its normal, normal tilted {tilt} degrees"),
        light,
        ("pdf_triangle_light_technique(ROUTINE_X, ROUTINE_N, routine_tri(), p)", "sample_triangle_light_with_technique(routine_tri(), ROUTINE_X, ROUTINE_N, u)"),
        (
            "pdf_triangle_light(ROUTINE_P0, ROUTINE_P1, ROUTINE_P2, ROUTINE_X, normalize(p - ROUTINE_X))",
            "sample_triangle_light(ROUTINE_P0, ROUTINE_P1, ROUTINE_P2, ROUTINE_X, u)",
        ),
        vec![("TRIANGLE_SAMPLING", crate::method::TriangleSampling::SolidAngle.constant() as f64)],
    )
}

/// The environment map `packed` (`EnvironmentMap::pack`) seen from a point with shading normal
/// `n`: the technique through `sample_environment_technique` and `pdf_environment_technique`
/// (what the path tracer calls), and the map's luminance distribution. Binned in the map's own
/// (u, t) square, written as the direction at phi = 2 pi u, s = 1 - cos = 2 t about +z: the
/// cells then follow the map's rows and columns, where a distribution drawn from the map is
/// piecewise constant, and the density in that square is the solid-angle density times
/// d(omega) / d(square) = (pi / 2) sin(pi t). The integrand is the map's luminance, on both
/// sides of the surface (a surface that transmits takes light from below it).
fn environment_configuration(packed: &[f32], n: [f64; 3], what: &str) -> Configuration {
    let (width, height) = (packed[0] as usize, packed[1] as usize);
    let common = format!(
        "const ROUTINE_N: vec3f = {};\n\
         fn routine_luminance(c: vec3f) -> f32 {{ return dot(c, vec3f(0.2126, 0.7152, 0.0722)); }}\n\
         // The binning direction of world direction wi: the map's (u, t) as (phi, s = 2 t).\n\
         fn routine_square(wi: vec3f) -> vec3f {{\n\
             let uv = environment_map_uv(wi);\n\
             let s = 2.0 * uv.y;\n\
             let sin_t = safe_sqrt(s * (2.0 - s));\n\
             return vec3f(sin_t * cos(2.0 * PI * uv.x), sin_t * sin(2.0 * PI * uv.x), 1.0 - s);\n\
         }}\n\
         fn routine_s(d: vec3f) -> f32 {{ return select(1.0 - d.z, (d.x * d.x + d.y * d.y) / (1.0 + d.z), d.z > 0.0); }}\n\
         // The world direction of a binning direction.\n\
         fn routine_world(d: vec3f) -> vec3f {{\n\
             var u = atan2_accurate(d.y, d.x) * (0.5 * INV_PI);\n\
             u = u - floor(u);\n\
             return environment_map_direction(vec2f(u, clamp(0.5 * routine_s(d), 0.0, 1.0)));\n\
         }}\n\
         // d(solid angle) / d(binning solid angle) = (pi / 2) sin(pi t), t = s / 2.\n\
         fn routine_jacobian(d: vec3f) -> f32 {{ return 0.5 * PI * sin(0.5 * PI * routine_s(d)); }}\n\
         fn routine_integrand(d: vec3f) -> f32 {{ return routine_luminance(environment_map_radiance(routine_world(d))) * routine_jacobian(d); }}\n",
        v3(n),
    );
    let technique = format!(
        "{common}\
         fn routine_pdf(d: vec3f) -> f32 {{ return pdf_environment_technique(ROUTINE_N, routine_world(d)) * routine_jacobian(d); }}\n\
         fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
             let s = sample_environment_technique(ROUTINE_N, u);\n\
             let d = routine_square(s.xyz);\n\
             let estimate = select(0.0, routine_luminance(environment_map_radiance(s.xyz)) / s.w, s.w > 0.0);\n\
             // (The technique reports no density of its own: pathlab asks its pdf, as here.)\n\
             return Drawn(vec4f(d, routine_pdf(d)), vec4f(0.0, 0.0, estimate, 0.0));\n\
         }}\n"
    );
    let builtin = format!(
        "{common}\
         fn routine_pdf(d: vec3f) -> f32 {{ return pdf_environment_map(routine_world(d)) * routine_jacobian(d); }}\n\
         fn routine_sample(u: vec2f, u_lobe: f32) -> Drawn {{\n\
             let s = sample_environment_map(u);\n\
             let estimate = select(0.0, routine_luminance(environment_map_radiance(s.xyz)) / s.w, s.w > 0.0);\n\
             let d = routine_square(s.xyz);\n\
             return Drawn(vec4f(d, routine_pdf(d)), vec4f(0.0, 0.0, estimate, 0.0));\n\
         }}\n"
    );
    let name = format!("environment map, normal towards {what}");
    // Two cells per texel each way: the map's distribution is constant over a cell.
    let technique = (technique, vec![("ENV_TECHNIQUE", 1.0), ("HAS_ENVIRONMENT_MAP", 1.0)]);
    Pair::light(name, technique, (builtin, vec![("HAS_ENVIRONMENT_MAP", 1.0)]), 2.0, (2 * width, 2 * height), packed.to_vec())
}

/// A configuration: the technique's routine (its WGSL and pipeline constants; its support
/// checked against `routine_integrand`) and the built-in's, binned alike (`s_split`, `bins`),
/// densities compared to `pdf_tolerance` (relative; `pdf_floor` absolute). Only the built-in's
/// estimate is used (the chi-square suite proves the built-ins).
struct Pair {
    name: String,
    technique: (String, Vec<(&'static str, f64)>),
    builtin: (String, Vec<(&'static str, f64)>),
    s_split: f64,
    pdf_tolerance: f64,
    pdf_floor: f64,
    bins: (usize, usize),
    environment_map: Vec<f32>,
}

impl Pair {
    /// A light's or environment's: densities to 1e-4.
    fn light(name: String, technique: (String, Vec<(&'static str, f64)>), builtin: (String, Vec<(&'static str, f64)>), s_split: f64, bins: (usize, usize), environment_map: Vec<f32>) -> Configuration {
        Pair { name, technique, builtin, s_split, pdf_tolerance: 1e-4, pdf_floor: 1e-30, bins, environment_map }.configuration()
    }

    fn configuration(self) -> Configuration {
        let make = |(wgsl, constants): (String, Vec<(&'static str, f64)>), integrand: bool| Routine {
            name: self.name.clone(),
            wgsl,
            constants,
            s_split: self.s_split,
            pdf_tolerance: self.pdf_tolerance,
            pdf_floor: self.pdf_floor,
            bsdf_data: Vec::new(),
            environment_map: self.environment_map.clone(),
            bins: self.bins,
            integrand,
        };
        Configuration { technique: make(self.technique.clone(), true), builtin: make(self.builtin.clone(), false), name: self.name }
    }
}

/// Writes the worst configuration's histogram (observed against expected) to `path`, if it
/// was binned.
pub fn write_worst_histogram(verdict: &Verdict, path: &Path) -> Result<bool, crate::output::OutputError> {
    let Some(worst) = verdict.worst() else { return Ok(false) };
    let Some(outcome) = &worst.outcome else { return Ok(false) };
    write_histogram(outcome, &format!("{}: {}", verdict.label, worst.name), path)?;
    Ok(true)
}
