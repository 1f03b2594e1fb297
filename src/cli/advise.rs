//! `pathlab advise SCENE --target-rel-error E | --target-psnr DB`: short pilots of each method,
//! the predicted time to the target, the winner; `--verify` renders it (the work is in
//! `pathlab::estimate::advise`).

use std::path::PathBuf;
use std::time::Duration;

use anyhow::bail;
use clap::Args;
use serde::Serialize;

use pathlab::advise::{advise, Advice};
use pathlab::estimate::target::Target;
use pathlab::gpu::{adapter_summary, Gpu, PathTracerPipelines};
use pathlab::method::Method;
use pathlab::render::{ctrl_c_flag, Budget, ErrorPlan, RenderJob, MAX_SPP};

use super::{load_scene, SceneOverrides};

#[derive(Args)]
pub struct AdviseArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Target estimated relMSE.
    #[arg(long, conflicts_with = "target_psnr", required_unless_present = "target_psnr", allow_negative_numbers = true)]
    target_rel_error: Option<f64>,
    /// Target estimated PSNR of the display image (dB).
    #[arg(long)]
    target_psnr: Option<f64>,
    /// Methods to pilot, comma-separated (default: every preset; under an environment map
    /// also its sampling strategies without and with MIS, as `study`).
    #[arg(long)]
    methods: Option<String>,
    /// Seconds of each pilot.
    #[arg(long, default_value_t = 2.0)]
    pilot_seconds: f64,
    // --size, --max-depth, --display (of a PSNR target).
    #[command(flatten)]
    overrides: SceneOverrides,
    /// Then render the winner to the target and compare predicted with achieved.
    #[arg(long)]
    verify: bool,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Use the first adapter whose name contains this (also: PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
    /// Each technique is piloted beside the methods whose strategy it replaces (as in
    /// `study`), after its check.
    #[command(flatten)]
    techniques: super::technique::TechniqueArgs,
}

#[derive(Serialize)]
struct Verification {
    method: Method,
    predicted_seconds: Option<f64>,
    seconds: f64,
    spp: u64,
    estimated_rel_mse: f64,
    estimated_psnr: Option<f64>,
    reached: bool,
}

#[derive(Serialize)]
struct Report {
    scene: String,
    width: u32,
    height: u32,
    max_depth: u32,
    target: Target,
    display: String,
    pilot_seconds: f64,
    advice: Vec<Advice>,
    verify: Option<Verification>,
    /// Techniques allowed unproven (`--allow-unproven`): rows whose method uses one are marked.
    unproven: Vec<String>,
}

impl Report {
    /// A method's name, marked `(UNPROVEN)` where it uses a technique allowed unproven.
    fn row_name(&self, method: &Method) -> String {
        let name = method.name();
        if method.techniques().any(|(_, t)| self.unproven.contains(&t.to_string())) {
            format!("{name} (UNPROVEN)")
        } else {
            name
        }
    }
}

pub fn run(args: AdviseArgs) -> anyhow::Result<i32> {
    let mut scene = load_scene(&args.scene)?;
    args.techniques.load(&mut scene)?;
    let target = match (args.target_rel_error, args.target_psnr) {
        (Some(e), _) if !(e.is_finite() && e > 0.0) => bail!("--target-rel-error must be a positive relative MSE"),
        (Some(e), _) => Target::RelMse(e),
        (None, Some(db)) if !db.is_finite() => bail!("--target-psnr must be a number of dB"),
        (None, Some(db)) => Target::Psnr(db),
        (None, None) => bail!("give --target-rel-error or --target-psnr"),
    };
    if !(args.pilot_seconds.is_finite() && args.pilot_seconds > 0.0) {
        bail!("--pilot-seconds must be positive");
    }
    let mut methods = Vec::new();
    let names: Vec<String> = match &args.methods {
        Some(m) => m.split(',').map(str::trim).filter(|s| !s.is_empty()).map(String::from).collect(),
        None => pathlab::study::default_methods(&scene),
    };
    let names = if names.is_empty() { names } else { super::technique::with_technique_rows(Some(names), &scene)?.unwrap_or_default() };
    for name in &names {
        let m = Method::from_name(name)?;
        if m.is_biased() {
            bail!("{name} is a biased demonstration: its error does not fall to any target");
        }
        methods.push(m);
    }
    if methods.is_empty() {
        bail!("--methods names no method");
    }
    // Methods that cannot see one of the scene's lights are left out, and said.
    let (seeing, blind): (Vec<Method>, Vec<Method>) = methods.into_iter().partition(|m| scene.why_left_out(m).is_none());
    for why in blind.iter().filter_map(|m| scene.why_left_out(m)) {
        eprintln!("note: {why}");
    }
    let methods = seeing;
    if methods.is_empty() {
        bail!("no method left to advise on: every one given cannot see the scene's delta lights");
    }
    let display = args.overrides.apply(&mut scene, None)?;

    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    // A technique allowed unproven is piloted as such, and said so.
    let unproven = args.techniques.prove_all(&gpu, &scene)?;
    if !unproven.is_empty() {
        let names: Vec<String> = unproven.iter().map(|n| n.to_string()).collect();
        eprintln!("warning: the advice covers UNPROVEN techniques ({}): their errors may not fall to the target", names.join(", "));
    }
    let pipelines = PathTracerPipelines::new(&gpu);
    let cancel = ctrl_c_flag();
    eprintln!("piloting {} methods for {} s each", methods.len(), args.pilot_seconds);
    let advice = advise(&gpu, &pipelines, &scene, &methods, target, &display, Duration::from_secs_f64(args.pilot_seconds), &cancel)?;
    let mut verify = None;
    if args.verify {
        if let Some(winner) = advice.first().filter(|a| a.predicted_seconds.is_some()) {
            eprintln!("verifying: rendering {} to the target", winner.method.name());
            let mut job = RenderJob::new(scene.clone(), args.scene.clone(), winner.method, 2, Budget::Samples(MAX_SPP));
            job.error = Some(ErrorPlan { target: Some(target), every: None, display, check_pixels: None });
            let outcome = job.run(&gpu, &pipelines, &cancel, |_| {})?;
            let out = outcome.error.as_ref().expect("a job with an error plan tracks its error");
            verify = Some(Verification {
                method: winner.method,
                predicted_seconds: winner.predicted_seconds,
                seconds: outcome.stats.seconds - out.check_seconds,
                spp: outcome.film.spp,
                estimated_rel_mse: out.estimate.rel_mse,
                estimated_psnr: out.estimate.psnr,
                reached: out.reached,
            });
        }
    }
    let report = Report {
        scene: args.scene.display().to_string(),
        width: scene.render.width,
        height: scene.render.height,
        max_depth: scene.render.max_depth,
        target,
        display: display.to_string(),
        pilot_seconds: args.pilot_seconds,
        advice,
        verify,
        unproven: unproven.iter().map(|n| n.to_string()).collect(),
    };
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_table(&report);
    }
    Ok(0)
}

fn print_table(r: &Report) {
    let target = match r.target {
        Target::RelMse(e) => format!("relMSE <= {e:e}"),
        Target::Psnr(db) => format!("PSNR >= {db} dB ({})", r.display),
    };
    println!("{} at {}x{}, max_depth {}: time to {target} (pilots of {} s)", r.scene, r.width, r.height, r.max_depth, r.pilot_seconds);
    // The method column as wide as the longest name (`mis+power+solid-angle`).
    let w = r.advice.iter().map(|a| r.row_name(&a.method).len()).max().unwrap_or(0).max(8);
    println!("{:<w$} {:>12} {:>12} {:>7} {:>12} {:>22} {:>12} {:>9}", "method", "M samples/s", "pilot error", "slope", "seconds", "range", "spp", "vs plain");
    let f = |x: Option<f64>, d: usize| x.map_or("-".to_string(), |v| format!("{v:.d$}"));
    for a in &r.advice {
        println!(
            "{:<w$} {:>12.2} {:>12.3e} {:>7} {:>12} {:>22} {:>12} {:>9}",
            r.row_name(&a.method),
            a.pixel_samples_per_second / 1e6,
            a.pilot_error,
            f(a.slope, 2),
            f(a.predicted_seconds, 2),
            a.range.map_or("-".into(), |(lo, hi)| format!("{lo:.2} .. {hi:.2}")),
            f(a.predicted_spp, 0),
            a.speedup_vs_plain.map_or("-".into(), |s| format!("{s:.1}x"))
        );
    }
    if let Some(w) = r.advice.first().filter(|a| a.predicted_seconds.is_some()) {
        println!("winner: {} ({})", r.row_name(&w.method), w.speedup_vs_plain.map_or("plain not piloted".into(), |s| format!("{s:.1}x faster than plain")));
    }
    if let Some(v) = &r.verify {
        println!(
            "verify: {} reached the target in {:.2} s at {} spp (predicted {} s; estimated relMSE {:.3e}{}){}",
            v.method.name(),
            v.seconds,
            v.spp,
            v.predicted_seconds.map_or("-".into(), |p| format!("{p:.2}")),
            v.estimated_rel_mse,
            v.estimated_psnr.map_or(String::new(), |p| format!(", PSNR {p:.2} dB")),
            if v.reached { "" } else { " - NOT reached" }
        );
    }
}
