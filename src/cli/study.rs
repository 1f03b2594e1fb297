//! `pathlab study SCENE --out DIR`: the variance-reduction study in one command (the work is in
//! `pathlab::study`).

use std::path::PathBuf;
use std::time::Duration;

use anyhow::bail;
use clap::Args;

use pathlab::gpu::{adapter_summary, Gpu, PathTracerPipelines};
use pathlab::render::ctrl_c_flag;
use pathlab::study::{parse_list, StudyError, StudyOptions, StudyOutcome};

use super::progress::Terminal;
use super::{load_scene, RrDepth, SceneOverrides, EXIT_INTERRUPTED};

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
    /// Method of the rendered reference (any unbiased method; the study's own choice was
    /// `plain`). Default `best`, and `best+env` under an environment map.
    #[arg(long)]
    reference_method: Option<String>,
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
    /// A small study for trying things out and for CI: the scene's aspect ratio at 128 pixels
    /// on the longer side, spp 1,4,10,64,256, time 0.1,0.3, 2 seeds, a 4096-spp reference
    /// (each overridable by its own flag).
    #[arg(long)]
    quick: bool,
    /// No progress bars.
    #[arg(short, long)]
    quiet: bool,
    /// Use the first adapter whose name contains this (also: PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
    /// Each technique joins the study beside the methods whose strategy it replaces: a bsdf
    /// technique as `M+bsdf=NAME` for every method M that samples the material (phong, mis,
    /// best), a light technique as `M+light=NAME` for every method that samples lights.
    #[command(flatten)]
    techniques: super::technique::TechniqueArgs,
}

pub fn run(args: StudyArgs) -> anyhow::Result<i32> {
    let mut scene = load_scene(&args.scene)?;
    args.techniques.load(&mut scene)?;
    if !(args.checkpoint_every.is_finite() && args.checkpoint_every > 0.0) {
        bail!("--checkpoint-every must be a positive number of seconds");
    }
    let methods: Option<Vec<String>> = args.methods.as_deref().map(|m| m.split(',').map(str::trim).filter(|s| !s.is_empty()).map(String::from).collect());
    let options = StudyOptions {
        methods: super::technique::with_technique_rows(methods, &scene)?,
        spp: args.spp.as_deref().map(|s| parse_list(s, "--spp")).transpose()?,
        times: args.time.as_deref().map(|s| parse_list(s, "--time")).transpose()?,
        seeds: args.seeds,
        reference: args.reference.clone(),
        reference_spp: args.reference_spp,
        reference_method: args.reference_method.clone(),
        size: args.overrides.size,
        max_depth: args.overrides.max_depth,
        rr_depth: args.overrides.rr_depth.map(|RrDepth(rr)| rr),
        display: args.overrides.display,
        target: args.target,
        regions: args.regions.clone(),
        checkpoint_every: Some(Duration::from_secs_f64(args.checkpoint_every)),
        quick: args.quick,
    };
    let command = std::env::args().map(|a| if a.contains(' ') { format!("'{a}'") } else { a }).collect::<Vec<_>>().join(" ");
    let study = options.study(scene, args.scene.clone(), args.out.clone(), command).map_err(|e| match e {
        StudyError::Override(o) => super::flag_error(o),
        e => e.into(),
    })?;
    let loaded = study.validate()?;

    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    // Every technique is proven before its first run; one allowed unproven marks its rows as
    // the biased demonstrations are marked.
    let unproven = args.techniques.prove_all(&gpu, &study.scene)?;
    let mut study = study;
    for m in study.methods.iter_mut() {
        if m.method.techniques().any(|(_, name)| unproven.contains(&name)) {
            m.biased = true;
        }
    }
    let pipelines = PathTracerPipelines::new(&gpu);
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
