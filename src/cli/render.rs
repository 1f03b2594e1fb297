//! `pathlab render`: headless batch rendering to EXR (and optionally a PNG preview).

use std::path::PathBuf;
use std::time::Duration;

use anyhow::bail;
use clap::Args;

use pathlab::display::{DisplayTransform, Transfer};
use pathlab::estimate::target::Target;
use pathlab::gpu::{adapter_summary, Gpu, PathTracerPipelines};
use pathlab::method::{BsdfSampling, LightSampling, LightSelect, EnvSampling, LobeSelection, Method, MethodParts, MicrofacetSampling, Sampler, TriangleSampling};
use pathlab::render::{ctrl_c_flag, default_output, Budget, CheckpointPlan, ErrorPlan, OutputFiles, RenderJob, Resume, MAX_SPP};
use pathlab::scene::{ApplicableOptions, Overrides};
use pathlab::shard::{default_part_name, shard_range};

use pathlab::progress::Reporter as _;

use super::progress::Terminal;
use super::{load_scene, named, parse_duration, parse_method, EXIT_INTERRUPTED};

/// Samples per pixel when neither `--spp`, `--time` nor the scene's `render.spp` says.
const DEFAULT_SPP: u64 = 64;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Sampling method: a preset (plain, halton, cosine, phong, nee, mis, best), mis-balance, a
    /// biased demonstration (phong-lobe-only, nee-double-count), or its parts
    /// SAMPLER/BSDF/LIGHTS; each may add +SELECT, +solid-angle, +ndf, +env (e.g. mis+power). The
    /// flags below replace its parts. Default: `best`, and `best+env` under an environment map.
    #[arg(long, value_parser = parse_method)]
    method: Option<Method>,
    /// Override the preset's sampler.
    #[arg(long, value_parser = named::<Sampler>())]
    sampler: Option<Sampler>,
    /// Override the preset's BSDF sampling.
    #[arg(long, value_parser = named::<BsdfSampling>())]
    bsdf: Option<BsdfSampling>,
    /// Override the preset's light sampling.
    #[arg(long, value_parser = named::<LightSampling>())]
    lights: Option<LightSampling>,
    /// Which lights next event estimation samples per vertex (default: `power` for scenes
    /// with emissive meshes, else `all`).
    #[arg(long, value_parser = named::<LightSelect>())]
    light_select: Option<LightSelect>,
    /// How triangle lights are sampled (default: area). Noted once where the scene has no
    /// emissive triangles or the method samples no lights.
    #[arg(long, value_parser = named::<TriangleSampling>())]
    triangle_sampling: Option<TriangleSampling>,
    /// How rough conductors' microfacet normals are sampled where the BSDF strategy samples the
    /// material (`--bsdf phong`): visible normals (vndf, Mitsuba's default) or the distribution.
    /// Noted once where the scene has no rough conductor or the strategy is another.
    #[arg(long, value_parser = named::<MicrofacetSampling>())]
    microfacet_sampling: Option<MicrofacetSampling>,
    /// How layered BSDFs (plastic) pick the lobe they sample, under every BSDF strategy:
    /// `fresnel` (Mitsuba's: the albedos' weight times the coating's Fresnel term at the
    /// incident direction) or `fixed` (the albedos' weight alone). Noted once where the scene
    /// has no plastic.
    #[arg(long, value_parser = named::<LobeSelection>())]
    lobe_selection: Option<LobeSelection>,
    /// Next event estimation samples the constant environment as a light, and rays that
    /// escape take the MIS weight against it (as the method suffix `+env`; default: found by
    /// escaping rays alone). Noted once where the environment is black or the method samples
    /// no lights.
    #[arg(long)]
    sample_environment: bool,
    /// How next event estimation draws directions towards an environment map (with
    /// `--sample-environment` or `+env`): `env-luminance` (Mitsuba's: by luminance times
    /// sin theta) or `env-uniform` (as the method suffix `+env-uniform`).
    #[arg(long, value_parser = named::<EnvSampling>())]
    env_sampling: Option<EnvSampling>,
    /// Samples per pixel (default: the scene's render.spp, else 64).
    #[arg(long, conflicts_with = "time")]
    spp: Option<u64>,
    /// Render only sample indices START..END (END exclusive) of every pixel, into a partial
    /// file for `pathlab merge` (the raw accumulators, not an image).
    #[arg(long, value_name = "START..END", value_parser = pathlab::shard::parse_range, conflicts_with_all = ["time", "spp", "shard"])]
    samples: Option<std::ops::Range<u64>>,
    /// Render the I-th (0-based) of N equal sample ranges of --spp into a partial file.
    #[arg(long, value_name = "I/N", value_parser = pathlab::shard::parse_shard, conflicts_with = "time")]
    shard: Option<(u64, u64)>,
    /// Save the raw accumulators to this file during the render (every --checkpoint-every),
    /// so that `--resume FILE` can continue after a crash or kill.
    #[arg(long, conflicts_with = "resume")]
    checkpoint: Option<PathBuf>,
    /// Continue the render saved in this checkpoint (same scene, method, seed, size, depth),
    /// saving to it as it goes.
    #[arg(long)]
    resume: Option<PathBuf>,
    /// Render until the estimated relMSE (no reference needed) is at most this; --spp and
    /// --time become upper bounds.
    #[arg(long, conflicts_with_all = ["target_psnr", "samples", "shard", "checkpoint", "resume"], allow_negative_numbers = true)]
    target_rel_error: Option<f64>,
    /// Render until the estimated PSNR of the display image is at least this (dB).
    #[arg(long, conflicts_with_all = ["samples", "shard", "checkpoint", "resume"])]
    target_psnr: Option<f64>,
    /// Interval between checkpoints: seconds, or with a unit (30s, 5m, 2h).
    #[arg(long, default_value = "5m", value_parser = parse_duration)]
    checkpoint_every: Duration,
    /// Render for this many seconds instead of a sample count.
    #[arg(long)]
    time: Option<f64>,
    /// Image width (default: the scene's).
    #[arg(long)]
    width: Option<u32>,
    /// Image height (default: the scene's).
    #[arg(long)]
    height: Option<u32>,
    /// Path segments (default: the scene's render.max_depth).
    #[arg(long)]
    max_depth: Option<u32>,
    /// Russian roulette from this scattering vertex on (the first is 1), or `off` (default:
    /// the scene's render.rr_depth, else off).
    #[arg(long)]
    rr_depth: Option<super::RrDepth>,
    /// Random seed; the same seed gives the same image, bit for bit.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Output EXR, a name ending in .exr (default: <scene stem>.exr in the current directory).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write an 8-bit sRGB PNG preview here.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Exposure of the PNG preview, in stops (default: the scene's [display] exposure, else 0).
    #[arg(long, allow_negative_numbers = true)]
    exposure: Option<f32>,
    /// Display transform of the PNG preview: `srgb` or `gamma:G` (default: the scene's
    /// [display] table, else srgb).
    #[arg(long)]
    display: Option<Transfer>,
    /// Add per-pixel variance-of-the-mean channels (variance.R/G/B) to the EXR.
    #[arg(long)]
    variance: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
    /// Use the first adapter whose name contains this (also: PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
    #[command(flatten)]
    techniques: super::technique::TechniqueArgs,
}

/// A note for each of the method's finer flags given where it cannot change the image.
fn inapplicable_flags(args: &RenderArgs, scene: &pathlab::scene::Scene, method: &Method) -> Vec<String> {
    let has = ApplicableOptions::of_scene(scene);
    let can = has.with_method(method);
    let no_lights = format!("the method samples no lights (--lights {})", method.lights);
    let mut notes = Vec::new();
    if args.light_select.is_some() && !can.light_select {
        let why = if has.light_select { no_lights.clone() } else { "the scene has one light".to_string() };
        notes.push(format!("--light-select has no effect: {why}"));
    }
    if args.triangle_sampling.is_some() && !can.triangle_sampling {
        let why = if has.triangle_sampling { no_lights.clone() } else { "the scene has no emissive triangles".to_string() };
        notes.push(format!("--triangle-sampling has no effect: {why}"));
    }
    if args.microfacet_sampling.is_some() && !can.microfacet_sampling {
        let why = if has.microfacet_sampling {
            format!("the BSDF strategy is {}, not the material's own (phong)", method.bsdf)
        } else {
            "the scene has no rough conductor".to_string()
        };
        notes.push(format!("--microfacet-sampling has no effect: {why}"));
    }
    if args.lobe_selection.is_some() && !can.lobe_selection {
        notes.push("--lobe-selection has no effect: the scene has no layered material (plastic)".to_string());
    }
    if args.sample_environment && !can.environment_sampling {
        let why = if has.environment_sampling { no_lights.clone() } else { "the scene's environment is black".to_string() };
        notes.push(format!("--sample-environment has no effect: {why}"));
    }
    if args.env_sampling.is_some() && !can.env_sampling {
        let why = if !has.env_sampling { "the scene's environment is not a map" } else { "the method does not sample the environment (add --sample-environment or +env)" };
        notes.push(format!("--env-sampling has no effect: {why}"));
    }
    notes
}

pub fn run(args: RenderArgs) -> anyhow::Result<i32> {
    // Everything the user gave is checked before any GPU work.
    if let Some(o) = &args.output
        && !o.extension().is_some_and(|e| e.eq_ignore_ascii_case("exr"))
    {
        bail!("-o {}: render writes OpenEXR; give a name ending in .exr (and --png for an 8-bit preview)", o.display());
    }
    let mut scene = load_scene(&args.scene)?;
    args.techniques.load(&mut scene)?;
    let overrides = Overrides {
        width: args.width,
        height: args.height,
        max_depth: args.max_depth,
        rr_depth: args.rr_depth.map(|super::RrDepth(rr)| rr),
        spp: None,
    };
    if let Some(reframing) = overrides.apply(&mut scene).map_err(super::flag_error)? {
        eprintln!("note: {reframing}");
    }
    let spp = match args.spp {
        Some(0) => bail!("--spp must be at least 1"),
        Some(n) => n,
        None => scene.render.spp.unwrap_or(DEFAULT_SPP),
    };
    let budget = match args.time {
        Some(t) if !(t.is_finite() && t > 0.0) => bail!("--time must be a positive number of seconds"),
        Some(t) => Budget::Time(Duration::from_secs_f64(t)),
        None => Budget::Samples(spp),
    };
    if args.exposure.is_some_and(|e| !e.is_finite()) {
        bail!("--exposure must be finite");
    }
    let parts = MethodParts {
        sampler: args.sampler,
        bsdf: args.bsdf,
        lights: args.lights,
        select: args.light_select,
        triangles: args.triangle_sampling,
        microfacet: args.microfacet_sampling,
        lobes: args.lobe_selection,
        environment: args.sample_environment.then_some(true),
        env_sampling: args.env_sampling,
        bsdf_technique: None,
        light_technique: None,
        env_technique: None,
    };
    let named = args.method.unwrap_or_else(|| Method::from_name(scene.default_method_name()).expect("the default method is a method"));
    let method = args.techniques.apply(parts.apply(named), &scene);
    // A technique the method names must be loaded: said before any GPU work.
    pathlab::shaders::TechniqueFiles::of(&method, &scene.techniques)?;
    for note in inapplicable_flags(&args, &scene, &method) {
        eprintln!("note: {note}");
    }
    // A part of a split render: a sample range, written as raw accumulators.
    let part = match (&args.samples, args.shard) {
        (Some(r), _) => Some((r.clone(), None)),
        (None, Some((i, n))) => {
            if n > spp {
                bail!("--shard {i}/{n}: {spp} spp cannot be split into {n} non-empty ranges");
            }
            Some((shard_range(i, n, spp), Some(spp)))
        }
        (None, None) => None,
    };
    let files = OutputFiles {
        exr: args.output.clone().unwrap_or_else(|| match &part {
            Some((range, _)) => default_part_name(&args.scene, range),
            None => default_output(&args.scene),
        }),
        png: args.png.clone(),
        display: DisplayTransform {
            transfer: args.display.unwrap_or(scene.display.transfer),
            exposure: args.exposure.unwrap_or(scene.display.exposure),
        },
        variance: args.variance,
    };
    // A method that cannot see one of the scene's lights is refused before any GPU work.
    pathlab::render::RenderError::check_sees_lights(&scene, &method)?;
    let mut job = RenderJob::new(scene, args.scene.clone(), method, args.seed, budget);
    let resume = if args.resume.is_some() { Resume::Required } else { Resume::Never };
    if let Some((range, planned_total)) = &part {
        if args.png.is_some() || args.variance || args.checkpoint.is_some() {
            bail!("a sample range is written as a partial file for `pathlab merge`: --png, --variance and --checkpoint apply to the merged image");
        }
        job.budget = Budget::Samples(range.end - range.start);
        job.first_sample = range.start;
        let path = args.resume.clone().unwrap_or_else(|| files.exr.clone());
        job.checkpoint = Some(CheckpointPlan { path, every: args.checkpoint_every, resume, planned_total: *planned_total });
    } else if let Some(path) = args.checkpoint.clone().or(args.resume.clone()) {
        if args.time.is_some() {
            bail!("--checkpoint and --resume need a sample budget (--spp), not --time");
        }
        job.checkpoint = Some(CheckpointPlan { path, every: args.checkpoint_every, resume, planned_total: None });
    }
    let target = match (args.target_rel_error, args.target_psnr) {
        (Some(e), _) if !(e.is_finite() && e > 0.0) => bail!("--target-rel-error must be a positive relative MSE"),
        (Some(e), _) => Some(Target::RelMse(e)),
        (None, Some(db)) if !db.is_finite() => bail!("--target-psnr must be a number of dB"),
        (None, Some(db)) => Some(Target::Psnr(db)),
        (None, None) => None,
    };
    if let Some(target) = target {
        // --spp and --time are upper bounds of a render to a target (none: up to 2^32 spp).
        job.budget = match args.time {
            Some(t) => Budget::Time(Duration::from_secs_f64(t)),
            None => Budget::Samples(args.spp.unwrap_or(MAX_SPP)),
        };
        job.error = Some(ErrorPlan { target: Some(target), every: None, display: files.display, check_pixels: None });
        return render_target(&args, &mut job, target, &files);
    }
    let budget = job.budget;
    // A file to continue is checked before any GPU work.
    job.check_saved()?;

    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    job.technique_verdict = args.techniques.prove(&gpu, &job.scene, &method)?;
    let pipelines = PathTracerPipelines::new(&gpu);
    let cancel = ctrl_c_flag();
    let terminal = Terminal::new(args.quiet);
    terminal.begin_budget(budget);
    let outcome = job.run(&gpu, &pipelines, &cancel, |p| terminal.frame(p))?;
    terminal.end();
    let (film, stats) = (&outcome.film, &outcome.stats);
    if let (Some((range, _)), Some(plan)) = (&part, &job.checkpoint) {
        eprintln!(
            "wrote {} (samples {}..{} of {}x{}, method {}, {:.2} s)",
            plan.path.display(),
            range.start,
            range.start + stats.spp,
            film.width,
            film.height,
            method.name(),
            stats.seconds
        );
        if stats.interrupted {
            eprintln!("interrupted: continue with --resume {}", plan.path.display());
            return Ok(EXIT_INTERRUPTED);
        }
        return Ok(0);
    }
    job.write(&outcome, &gpu.info.name, &files, &Vec::new())?;
    if outcome.faults > 0 {
        eprintln!("warning: {} samples had a technique fault (a non-finite or negative number, or a stopped loop) and contributed 0", outcome.faults);
    }

    let rate = stats.spp as f64 * film.mean.len() as f64 / stats.seconds.max(1e-9);
    eprintln!(
        "wrote {} ({}x{}, {} spp, method {} [{}], {:.2} s, {:.3} M pixel samples/s, {:.3} M rays/s)",
        files.exr.display(),
        film.width,
        film.height,
        stats.spp,
        method.name(),
        method,
        stats.seconds,
        rate / 1e6,
        outcome.rays as f64 / stats.seconds.max(1e-9) / 1e6
    );
    if let Some(png) = &files.png {
        eprintln!("wrote {}", png.display());
    }
    if stats.interrupted {
        eprintln!("interrupted: the image holds the {} spp finished before Ctrl-C", stats.spp);
        if let Some(plan) = &job.checkpoint {
            eprintln!("continue with --resume {}", plan.path.display());
        }
        return Ok(EXIT_INTERRUPTED);
    }
    Ok(0)
}

/// `--target-rel-error` / `--target-psnr`: the job renders until its estimate meets the target.
fn render_target(args: &RenderArgs, job: &mut RenderJob, target: Target, files: &OutputFiles) -> anyhow::Result<i32> {
    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    job.technique_verdict = args.techniques.prove(&gpu, &job.scene, &job.method)?;
    let pipelines = PathTracerPipelines::new(&gpu);
    let cancel = ctrl_c_flag();
    let bar = indicatif::ProgressBar::new_spinner();
    if args.quiet || !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let outcome = job.run(&gpu, &pipelines, &cancel, |p| {
        let est = p.estimate.map_or("estimating".to_string(), |e| match target {
            Target::RelMse(t) => format!("relMSE ~{:.3e} (target {t:.3e})", e.rel_mse),
            Target::Psnr(db) => format!("PSNR ~{:.2} dB (target {db} dB)", e.psnr.unwrap_or(0.0)),
        });
        let eta = p.eta.map_or(String::new(), |d| format!(", ETA {:.1} s", d.as_secs_f64()));
        bar.set_message(format!("{} spp, {:.1} s, {est}{eta}", p.spp_done, p.elapsed.as_secs_f64()));
        bar.tick();
    })?;
    bar.finish_and_clear();
    let out = outcome.error.as_ref().expect("a job with an error plan tracks its error");
    job.write(&outcome, &gpu.info.name, files, &Vec::new())?;
    eprintln!(
        "wrote {} ({} spp, {:.2} s; estimated relMSE {:.3e}, PSNR {} under {}; {}; target {}; {} checks took {:.2}% of the time)",
        files.exr.display(),
        outcome.stats.spp,
        outcome.stats.seconds,
        out.estimate.rel_mse,
        out.estimate.psnr.map_or("-".into(), |p| format!("{p:.2} dB")),
        files.display,
        out.estimator.describe(),
        if out.reached { "reached" } else { "NOT reached (an upper bound stopped it)" },
        out.checks,
        100.0 * out.check_seconds / outcome.stats.seconds.max(1e-9)
    );
    if let Some(png) = &files.png {
        eprintln!("wrote {}", png.display());
    }
    if outcome.stats.interrupted {
        eprintln!("interrupted: the image holds the {} spp finished before Ctrl-C", outcome.stats.spp);
        return Ok(EXIT_INTERRUPTED);
    }
    Ok(if out.reached { 0 } else { 3 })
}
