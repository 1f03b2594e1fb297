//! `pathlab render`: headless batch rendering to EXR (and optionally a PNG preview).

use std::path::PathBuf;
use std::time::Duration;

use anyhow::bail;
use clap::Args;

use pathlab::display::DisplayTransform;
use pathlab::gpu::{adapter_summary, Gpu, PathTracerPipelines};
use pathlab::method::{BsdfSampling, LightSampling, Method, Preset, Sampler};
use pathlab::render::{ctrl_c_flag, default_output, method_label, progress_bar, show_progress, Budget, OutputFiles, RenderJob};

use super::{load_scene, EXIT_INTERRUPTED};

/// Samples per pixel when neither `--spp`, `--time` nor the scene's `render.spp` says.
const DEFAULT_SPP: u64 = 64;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Sampling method preset.
    #[arg(long, value_enum, default_value = "best")]
    method: Preset,
    /// Override the preset's sampler.
    #[arg(long, value_enum)]
    sampler: Option<Sampler>,
    /// Override the preset's BSDF sampling.
    #[arg(long, value_enum)]
    bsdf: Option<BsdfSampling>,
    /// Override the preset's light sampling.
    #[arg(long, value_enum)]
    lights: Option<LightSampling>,
    /// Samples per pixel (default: the scene's render.spp, else 64).
    #[arg(long, conflicts_with = "time")]
    spp: Option<u64>,
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
    /// Random seed; the same seed gives the same image, bit for bit.
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Output EXR (default: <scene stem>.exr in the current directory).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Also write an 8-bit sRGB PNG preview here.
    #[arg(long)]
    png: Option<PathBuf>,
    /// Exposure of the PNG preview, in stops.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
    /// Add per-pixel variance-of-the-mean channels (variance.R/G/B) to the EXR.
    #[arg(long)]
    variance: bool,
    /// No progress bar.
    #[arg(short, long)]
    quiet: bool,
    /// Use the first adapter whose name contains this (also: PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
}

pub(crate) fn method_of(preset: Preset, sampler: Option<Sampler>, bsdf: Option<BsdfSampling>, lights: Option<LightSampling>) -> Method {
    let mut m = preset.method();
    if let Some(s) = sampler {
        m.sampler = s;
    }
    if let Some(b) = bsdf {
        m.bsdf = b;
    }
    if let Some(l) = lights {
        m.lights = l;
    }
    m
}

pub fn run(args: RenderArgs) -> anyhow::Result<i32> {
    // Everything the user gave is checked before any GPU work.
    let mut scene = load_scene(&args.scene)?;
    for (name, value) in [("--width", args.width), ("--height", args.height), ("--max-depth", args.max_depth)] {
        if value == Some(0) {
            bail!("{name} must be at least 1");
        }
    }
    scene.render.width = args.width.unwrap_or(scene.render.width);
    scene.render.height = args.height.unwrap_or(scene.render.height);
    scene.render.max_depth = args.max_depth.unwrap_or(scene.render.max_depth);
    let budget = match (args.spp, args.time) {
        (_, Some(t)) if !(t.is_finite() && t > 0.0) => bail!("--time must be a positive number of seconds"),
        (_, Some(t)) => Budget::Time(Duration::from_secs_f64(t)),
        (Some(0), _) => bail!("--spp must be at least 1"),
        (Some(n), _) => Budget::Samples(n),
        (None, None) => Budget::Samples(scene.render.spp.unwrap_or(DEFAULT_SPP)),
    };
    if !args.exposure.is_finite() {
        bail!("--exposure must be finite");
    }
    let method = method_of(args.method, args.sampler, args.bsdf, args.lights);
    let files = OutputFiles {
        exr: args.output.clone().unwrap_or_else(|| default_output(&args.scene)),
        png: args.png.clone(),
        display: DisplayTransform { exposure: args.exposure, ..DisplayTransform::default() },
        variance: args.variance,
    };
    let job = RenderJob { scene, scene_path: args.scene.clone(), method, seed: args.seed, budget };

    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    let pipelines = PathTracerPipelines::new(&gpu.device);
    let cancel = ctrl_c_flag();
    let bar = progress_bar(budget, args.quiet);
    let outcome = job.run(&gpu, &pipelines, &cancel, |p| show_progress(&bar, budget, p))?;
    bar.finish_and_clear();
    job.write(&outcome, &gpu.info.name, &files)?;

    let (film, stats) = (&outcome.film, &outcome.stats);
    let rate = stats.spp as f64 * film.mean.len() as f64 / stats.seconds.max(1e-9);
    eprintln!(
        "wrote {} ({}x{}, {} spp, method {} [{}], {:.2} s, {:.3} M pixel samples/s, {:.3} M rays/s)",
        files.exr.display(),
        film.width,
        film.height,
        stats.spp,
        method_label(&method),
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
        return Ok(EXIT_INTERRUPTED);
    }
    Ok(0)
}
