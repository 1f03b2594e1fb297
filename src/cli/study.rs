//! `pathlab study SCENE --out DIR`: the variance-reduction study in one command (the work is in
//! `pathlab::study`).

use std::path::PathBuf;
use std::time::Duration;

use anyhow::bail;
use clap::Args;

use pathlab::gpu::{adapter_summary, Gpu, PathTracerPipelines};
use pathlab::render::ctrl_c_flag;
use pathlab::study::{parse_list, ReferenceSource, Study, StudyMethod, StudyOutcome};

use super::progress::Terminal;
use super::{load_scene, SceneOverrides, EXIT_INTERRUPTED};

#[derive(Args)]
pub struct StudyArgs {
    /// Scene file (TOML, or Mitsuba 3 XML).
    scene: PathBuf,
    /// Directory for the report, the reference and every run (created; a rerun continues).
    #[arg(long)]
    out: PathBuf,
    /// Methods, comma-separated: presets, and the biased demonstrations phong-lobe-only,
    /// nee-double-count. Default: every preset.
    #[arg(long)]
    methods: Option<String>,
    /// Samples-per-pixel budgets of the equal-sample table. Default 1,4,10,64,1000.
    #[arg(long)]
    spp: Option<String>,
    /// Wall-time budgets (seconds) of the equal-time table. Default 0.5,2,8.
    #[arg(long)]
    time: Option<String>,
    /// Independent seeds per cell. Default 3.
    #[arg(long)]
    seeds: Option<u32>,
    /// Use this EXR as the reference instead of rendering one.
    #[arg(long, conflicts_with_all = ["reference_spp", "reference_method"])]
    reference: Option<PathBuf>,
    /// Samples per pixel of the rendered reference. Default 100000.
    #[arg(long)]
    reference_spp: Option<u64>,
    /// Method of the rendered reference (any preset; the study's own choice was `plain`).
    #[arg(long, default_value = "best")]
    reference_method: String,
    // --size (default: the scene's, or the reference file's), --max-depth, --display.
    #[command(flatten)]
    overrides: SceneOverrides,
    /// Target relMSE for the time-to-target column (default: what plain reaches at the largest spp).
    #[arg(long)]
    target: Option<f64>,
    /// Named pixel rectangles (TOML: `size = [W, H]`, then `[[region]]` with name, x, y,
    /// width, height), whose relMSE every run also measures: a region table in the report.
    #[arg(long)]
    regions: Option<PathBuf>,
    /// Seconds between checkpoints of the reference render.
    #[arg(long, default_value_t = 300.0)]
    checkpoint_every: f64,
    /// A small study for trying things out and for CI: 128x64, spp 1,4,10,64,256, time
    /// 0.1,0.3, 2 seeds, a 4096-spp reference (each overridable by its own flag).
    #[arg(long)]
    quick: bool,
    /// No progress bars.
    #[arg(short, long)]
    quiet: bool,
    /// Use the first adapter whose name contains this (also: PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
}

pub fn run(args: StudyArgs) -> anyhow::Result<i32> {
    let mut scene = load_scene(&args.scene)?;
    let q = args.quick;
    let methods = args.methods.clone().unwrap_or_else(|| "plain,halton,cosine,phong,nee,mis,best".into());
    let methods = methods.split(',').map(str::trim).filter(|s| !s.is_empty()).map(StudyMethod::by_name).collect::<Result<Vec<_>, _>>()?;
    let spp: Vec<u64> = parse_list(args.spp.as_deref().unwrap_or(if q { "1,4,10,64,256" } else { "1,4,10,64,1000" }), "--spp")?;
    let times: Vec<f64> = parse_list(args.time.as_deref().unwrap_or(if q { "0.1,0.3" } else { "0.5,2,8" }), "--time")?;
    if !(args.checkpoint_every.is_finite() && args.checkpoint_every > 0.0) {
        bail!("--checkpoint-every must be a positive number of seconds");
    }
    let reference = match &args.reference {
        Some(path) => ReferenceSource::File(path.clone()),
        None => {
            let m = StudyMethod::by_name(&args.reference_method)?;
            if m.biased {
                bail!("--reference-method {} is a biased demonstration; a reference must be unbiased", m.name);
            }
            ReferenceSource::Render { method: m.method, spp: args.reference_spp.unwrap_or(if q { 4096 } else { 100_000 }) }
        }
    };
    // Size: --size, else the reference file's, else --quick's, else the scene's.
    let file_size = match &args.reference {
        Some(p) if args.overrides.size.is_none() => {
            let (film, _) = pathlab::output::read_exr(p)?;
            Some((film.width, film.height))
        }
        _ => None,
    };
    let display = args.overrides.apply(&mut scene, file_size.or(q.then_some((128, 64))))?;
    let regions = match &args.regions {
        Some(path) => pathlab::study::regions::load(path, scene.render.width, scene.render.height)?,
        None => Vec::new(),
    };
    let study = Study {
        scene,
        scene_path: args.scene.clone(),
        out: args.out.clone(),
        methods,
        spp,
        times,
        seeds: args.seeds.unwrap_or(if q { 2 } else { 3 }),
        reference,
        regions,
        display,
        target: args.target,
        checkpoint_every: Duration::from_secs_f64(args.checkpoint_every),
        command: std::env::args().map(|a| if a.contains(' ') { format!("'{a}'") } else { a }).collect::<Vec<_>>().join(" "),
    };
    let loaded = study.validate()?;

    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    let pipelines = PathTracerPipelines::new(&gpu.device);
    let cancel = ctrl_c_flag();
    match study.run(loaded, &gpu, &pipelines, &cancel, &Terminal::new(args.quiet))? {
        StudyOutcome::Finished { report } => {
            eprintln!("wrote {}", report.display());
            Ok(0)
        }
        StudyOutcome::Interrupted => {
            eprintln!("interrupted: finished steps are kept in {}; run the same command again to continue", args.out.display());
            Ok(EXIT_INTERRUPTED)
        }
    }
}
