//! `--technique KIND:FILE.wgsl` (a researcher's sampling technique) for the commands that
//! render, and `pathlab check-technique`.

use std::path::PathBuf;

use anyhow::bail;
use clap::Args;

use pathlab::gpu::Gpu;
use pathlab::method::Method;
use pathlab::scene::{Scene, Technique};
use pathlab::technique::{self, CheckOptions, Verdict};

/// The flags every rendering command takes for researchers' techniques.
#[derive(Args, Debug, Clone, Default)]
pub struct TechniqueArgs {
    /// A sampling technique of your own, KIND:FILE.wgsl (KIND `bsdf`: directions at Phong
    /// materials; `light`: points on spherical lights; `env`: directions towards the
    /// environment map), implementing the contract of
    /// shaders/technique.wgsl; repeatable. Methods use it as +KIND=NAME (NAME: the file's
    /// stem); a method that names no technique of its kind uses it. It must pass its check
    /// (`pathlab check-technique`) first.
    #[arg(long = "technique", value_name = "KIND:FILE.wgsl")]
    pub techniques: Vec<String>,
    /// Use a technique that fails its check anyway: every result made with it is marked
    /// unproven.
    #[arg(long)]
    pub allow_unproven: bool,
}

impl TechniqueArgs {
    /// Reads every technique into `scene.techniques` (after those of the scene's
    /// `[techniques]`), and validates them all (naga, no GPU).
    pub fn load(&self, scene: &mut Scene) -> anyhow::Result<()> {
        for spec in &self.techniques {
            let mut t = Technique::from_spec(spec)?;
            t.allow_unproven = self.allow_unproven;
            scene.techniques.push(t);
        }
        if self.allow_unproven {
            scene.techniques.iter_mut().for_each(|t| t.allow_unproven = true);
        }
        pathlab::scene::technique::check_unique(&scene.techniques)?;
        for t in &scene.techniques {
            pathlab::shaders::validate_technique(t)?;
        }
        Ok(())
    }

    /// `method`, using each technique given on the command line whose kind it names none of
    /// (a scene's `[techniques]` are used by name: `+KIND=NAME`).
    pub fn apply(&self, method: Method, scene: &Scene) -> Method {
        let mut method = method;
        for t in scene.techniques.iter().filter(|t| self.techniques.iter().any(|s| Technique::from_spec(s).is_ok_and(|g| g.path == t.path))) {
            if !method.techniques().any(|(kind, _)| kind == t.kind) {
                method = method.with_technique(t.kind, t.name);
            }
        }
        method
    }

    /// Proves every loaded technique (`prove`); returns the names of those used unproven.
    pub fn prove_all(&self, gpu: &Gpu, scene: &Scene) -> anyhow::Result<Vec<pathlab::method::TechniqueName>> {
        let mut unproven = Vec::new();
        for t in &scene.techniques {
            let method = Method::from_name("mis")?.with_technique(t.kind, t.name);
            if self.prove(gpu, scene, &method)?.is_some_and(|v| v != "proven") {
                unproven.push(t.name);
            }
        }
        Ok(unproven)
    }

    /// Proves the techniques `method` uses on `scene` before they render (`technique::prove`,
    /// which decides; here the reports are printed and a failing one's histogram written). A
    /// refused one stops the command with its report, unless `--allow-unproven`. Returns the
    /// header attribute to record: `proven`, or `UNPROVEN: ...`.
    pub fn prove(&self, gpu: &Gpu, scene: &Scene, method: &Method) -> anyhow::Result<Option<String>> {
        let files = pathlab::shaders::TechniqueFiles::of(method, &scene.techniques)?;
        for t in files.all() {
            eprintln!("checking technique {} (chi-square and coverage on the scene's configurations)...", t.label());
        }
        // Checked once per file and scene: `prove` below reads the same verdicts.
        for (verdict, t) in technique::verdicts(gpu, scene, method)?.iter().zip(files.all()) {
            if verdict.passed() {
                eprintln!("technique {}: proven ({} configurations)", t.label(), verdict.results.len());
                continue;
            }
            let histogram = histogram_path(t);
            if technique::write_worst_histogram(verdict, &histogram)? {
                eprintln!("histogram of the worst configuration of {}: {}", t.label(), histogram.display());
            }
            if t.allow_unproven {
                eprintln!("warning: technique {} is UNPROVEN (--allow-unproven):\n{}", t.label(), verdict.report());
            }
        }
        Ok(technique::prove(gpu, scene, method)?)
    }
}

/// The study's method names with a row for every loaded technique beside each method whose
/// strategy it replaces (`names`: the chosen methods, `None`: every preset): a bsdf technique
/// beside the methods that sample the material with its own strategy, a light technique beside
/// those that sample lights. Where none of the methods can use a technique, its `mis` row.
pub fn with_technique_rows(names: Option<Vec<String>>, scene: &Scene) -> anyhow::Result<Option<Vec<String>>> {
    if scene.techniques.is_empty() {
        return Ok(names);
    }
    use pathlab::method::{BsdfSampling, LightSampling, Preset, TechniqueKind};
    let names = names.unwrap_or_else(|| pathlab::study::default_methods(scene));
    let mut rows = names.clone();
    for t in &scene.techniques {
        let mut added = false;
        for name in &names {
            let m = Method::from_name(name)?;
            let uses = match t.kind {
                TechniqueKind::Bsdf => m.bsdf == BsdfSampling::Phong,
                TechniqueKind::Light => m.lights != LightSampling::None && !m.lights.is_biased(),
                // Next event estimation of the environment: `+env=NAME` turns it on.
                TechniqueKind::Env => m.lights != LightSampling::None && !m.lights.is_biased() && scene.environment_map.is_some(),
            };
            if m.techniques().any(|(k, n)| k == t.kind && n == t.name) {
                // Listed with the technique already.
                added = true;
            } else if uses && !m.is_biased() && !m.techniques().any(|(k, _)| k == t.kind) {
                // A technique that samples microfacet normals (and no Phong material) replaces
                // `--microfacet-sampling`: methods that differ only in it give one row.
                let targets = t.bsdf_targets();
                let m = if targets.samples_microfacet() && !targets.phong { Method { microfacet: pathlab::method::MicrofacetSampling::Vndf, ..m } } else { m };
                let row = m.with_technique(t.kind, t.name).name();
                if !rows.contains(&row) {
                    rows.push(row);
                }
                added = true;
            }
        }
        if !added {
            rows.push(Preset::Mis.method().with_technique(t.kind, t.name).name());
        }
    }
    Ok(Some(rows))
}

/// `<technique stem>-check.png` in the current directory.
fn histogram_path(t: &Technique) -> PathBuf {
    PathBuf::from(format!("{}-check.png", t.name))
}

#[derive(Args)]
pub struct CheckTechniqueArgs {
    /// The technique: KIND:FILE.wgsl (KIND bsdf, light or env).
    technique: String,
    /// The scene whose materials or lights give the configurations (default: the study scene's
    /// defaults, the study's three materials, a unit sphere or a right triangle).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Samples per configuration.
    #[arg(long, default_value_t = technique::DEFAULT_SAMPLES)]
    samples: u32,
    /// Seed of the check.
    #[arg(long, default_value_t = 1)]
    seed: u32,
    /// Run every configuration even after one fails hard.
    #[arg(long)]
    all: bool,
    /// Where to write the worst configuration's histogram (default:
    /// <technique stem>-check.png in the current directory, written when the check fails).
    #[arg(long)]
    histogram: Option<PathBuf>,
    /// Use the first adapter whose name contains this (also: PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
    /// Print the verdict as JSON (`VerdictJson`) instead of the report; the exit status is the
    /// same.
    #[arg(long)]
    json: bool,
}

/// `check-technique --json`: the verdict and every configuration's tests, as the report gives
/// them.
#[derive(serde::Serialize)]
struct VerdictJson {
    technique: String,
    sha256: String,
    /// "proven" or "refused".
    verdict: &'static str,
    samples: u32,
    /// The per-test level (Šidák-corrected over the check).
    level: f64,
    source: String,
    /// The worst configuration's name (a failing one first).
    worst: Option<String>,
    configurations: Vec<ConfigurationJson>,
    /// The worst configuration's histogram, where one was written.
    histogram: Option<PathBuf>,
}

#[derive(serde::Serialize)]
struct ConfigurationJson {
    name: String,
    chi_square_p: Option<f64>,
    coverage_p: Option<f64>,
    /// Σ f/p over the samples: the technique's estimate and the built-in's, (mean, standard
    /// error) each.
    coverage_technique: Option<(f64, f64)>,
    coverage_builtin: Option<(f64, f64)>,
    /// A hard failure (bad pdf, wrong normalisation, samples outside the support, ...).
    failure: Option<String>,
    passed: bool,
}

impl VerdictJson {
    fn of(v: &Verdict, histogram: Option<PathBuf>) -> VerdictJson {
        VerdictJson {
            technique: v.label.clone(),
            sha256: v.sha256.clone(),
            verdict: if v.passed() { "proven" } else { "refused" },
            samples: v.samples,
            level: v.level,
            source: v.source.clone(),
            worst: v.worst().map(|w| w.name.clone()),
            configurations: v
                .results
                .iter()
                .map(|r| ConfigurationJson {
                    name: r.name.clone(),
                    chi_square_p: r.p_value,
                    coverage_p: r.coverage.map(|c| c.0),
                    coverage_technique: r.coverage.map(|c| c.1),
                    coverage_builtin: r.coverage.map(|c| c.2),
                    failure: r.failure.as_ref().map(|f| f.to_string()),
                    passed: r.failure.is_none() && r.worst_p() >= v.level,
                })
                .collect(),
            histogram,
        }
    }
}

/// Prints the verdict; exit status 0 when proven, 2 when refused.
pub fn run_check(args: CheckTechniqueArgs) -> anyhow::Result<i32> {
    let t = Technique::from_spec(&args.technique)?;
    if args.samples < 1000 {
        bail!("--samples must be at least 1000 (the chi-square test pools cells expecting fewer than 5)");
    }
    let scene = match &args.scene {
        Some(path) => super::load_scene(path)?,
        None => Scene::parse(include_str!("../../assets/scenes/study.toml"), "assets/scenes/study.toml")?,
    };
    // Validation needs no GPU: a syntax error is reported before any adapter is opened.
    pathlab::shaders::validate_technique(&t)?;
    let gpu = Gpu::new(args.adapter.as_deref())?;
    let options = CheckOptions { samples: args.samples, seed: args.seed, stop_at_failure: !args.all };
    let verdict: Verdict = technique::check(&gpu, &t, &scene, options, |k, n, name| eprintln!("[{}/{n}] {name}", k + 1))?;
    if !args.json {
        print!("{}", verdict.report());
    }
    let histogram = args.histogram.clone().unwrap_or_else(|| histogram_path(&t));
    let written = (args.histogram.is_some() || !verdict.passed()) && technique::write_worst_histogram(&verdict, &histogram)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&VerdictJson::of(&verdict, written.then_some(histogram)))?);
    } else if written {
        println!("histogram of the worst configuration: {}", histogram.display());
    }
    Ok(if verdict.passed() { 0 } else { 2 })
}
