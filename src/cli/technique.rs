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
    /// materials; `light`: points on spherical lights), implementing the contract of
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
    /// Reads and validates (naga, no GPU) every technique into `scene.techniques`.
    pub fn load(&self, scene: &mut Scene) -> anyhow::Result<()> {
        for spec in &self.techniques {
            let t = Technique::from_spec(spec)?;
            pathlab::shaders::validate_technique(&t)?;
            scene.techniques.push(t);
        }
        pathlab::scene::technique::check_unique(&scene.techniques)?;
        Ok(())
    }

    /// `method`, using each loaded technique whose kind it names none of.
    pub fn apply(&self, method: Method, scene: &Scene) -> Method {
        let mut method = method;
        for t in &scene.techniques {
            if !method.techniques().any(|(kind, _)| kind == t.kind) {
                method = method.with_technique(t.kind, t.name);
            }
        }
        method
    }

    /// Proves the techniques `method` uses on `scene` before they render. A refused one stops
    /// the command with its report (and its histogram beside `histogram_dir`), unless
    /// `--allow-unproven`. Returns the header attribute to record: `proven`, or `UNPROVEN: ...`.
    pub fn prove(&self, gpu: &Gpu, scene: &Scene, method: &Method) -> anyhow::Result<Option<String>> {
        let mut unproven = Vec::new();
        let mut any = false;
        for (kind, name) in method.techniques() {
            let Some(t) = scene.techniques.iter().find(|t| t.kind == kind && t.name == name) else {
                bail!(pathlab::scene::TechniqueError::NotLoaded { kind, name: name.to_string() });
            };
            any = true;
            eprintln!("checking technique {} (chi-square and coverage on the scene's configurations)...", t.label());
            let verdict = technique::check(gpu, t, scene, CheckOptions::default(), |_, _, _| {})?;
            if verdict.passed() {
                eprintln!("technique {}: proven ({} configurations)", t.label(), verdict.results.len());
                continue;
            }
            let histogram = histogram_path(t);
            let drawn = technique::write_worst_histogram(&verdict, &histogram)?;
            let mut report = verdict.report();
            if drawn {
                report += &format!("histogram of the worst configuration: {}\n", histogram.display());
            }
            if !self.allow_unproven {
                bail!("technique {} is refused:\n{report}(--allow-unproven renders with it anyway, marking every result unproven)", t.label());
            }
            eprintln!("warning: technique {} is UNPROVEN (--allow-unproven):\n{report}", t.label());
            unproven.push(t.label());
        }
        Ok(match (any, unproven.is_empty()) {
            (false, _) => None,
            (true, true) => Some("proven".to_string()),
            (true, false) => Some(format!("UNPROVEN: {} failed the check (--allow-unproven)", unproven.join(", "))),
        })
    }
}

/// `<technique stem>-check.png` in the current directory.
fn histogram_path(t: &Technique) -> PathBuf {
    PathBuf::from(format!("{}-check.png", t.name))
}

#[derive(Args)]
pub struct CheckTechniqueArgs {
    /// The technique: KIND:FILE.wgsl (KIND bsdf or light).
    technique: String,
    /// The scene whose materials or lights give the configurations (default: the study scene's
    /// defaults, the study's three materials or a unit sphere).
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
    print!("{}", verdict.report());
    let histogram = args.histogram.clone().unwrap_or_else(|| histogram_path(&t));
    if (args.histogram.is_some() || !verdict.passed()) && technique::write_worst_histogram(&verdict, &histogram)? {
        println!("histogram of the worst configuration: {}", histogram.display());
    }
    Ok(if verdict.passed() { 0 } else { 2 })
}
