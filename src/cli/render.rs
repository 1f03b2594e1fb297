//! `pathlab render`: headless batch rendering to EXR (and optionally a PNG preview).

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use anyhow::{bail, Context};
use clap::Args;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use pathlab::gpu::{adapter_summary, Gpu, PathTracerPipelines};
use pathlab::method::{BsdfSampling, LightSampling, Method, Preset, Sampler};
use pathlab::output::{write_exr, write_png, Metadata};
use pathlab::render::{Budget, Readback, Renderer};

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

fn method_of(args: &RenderArgs) -> Method {
    let mut m = args.method.method();
    if let Some(s) = args.sampler {
        m.sampler = s;
    }
    if let Some(b) = args.bsdf {
        m.bsdf = b;
    }
    if let Some(l) = args.lights {
        m.lights = l;
    }
    m
}

fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from(format!("{stem}.exr"))
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
    let method = method_of(&args);
    let output = args.output.clone().unwrap_or_else(|| default_output(&args.scene));

    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    let pipelines = PathTracerPipelines::new(&gpu.device);
    let mut renderer = Renderer::new(&gpu, &pipelines, &scene, method, args.seed)?;

    let cancel = Arc::new(AtomicBool::new(false));
    {
        let cancel = cancel.clone();
        // A second Ctrl-C while the image is being written falls through to the default.
        let _ = ctrlc::set_handler(move || cancel.store(true, Ordering::Relaxed));
    }
    let bar = progress_bar(budget, args.quiet);
    let stats = renderer.render(budget, &cancel, |p| match budget {
        Budget::Samples(_) => bar.set_position(p.spp_done),
        Budget::Time(_) => {
            bar.set_position(p.elapsed.as_millis() as u64);
            bar.set_message(format!("{} spp", p.spp_done));
        }
    })?;
    bar.finish_and_clear();
    let Readback { film, rays } = renderer.readback()?;

    let preset = method.preset().map_or("custom", Preset::name);
    let metadata: Metadata = [
        ("spp", stats.spp.to_string()),
        ("method", preset.to_string()),
        ("sampler", method.sampler.name().to_string()),
        ("bsdf", method.bsdf.name().to_string()),
        ("lights", method.lights.name().to_string()),
        ("seed", args.seed.to_string()),
        ("max_depth", scene.render.max_depth.to_string()),
        ("render_seconds", format!("{:.6}", stats.seconds)),
        ("rays", rays.to_string()),
        ("scene", args.scene.display().to_string()),
        ("adapter", gpu.info.name.clone()),
        ("version", pathlab::VERSION.to_string()),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    write_exr(&output, &film, &metadata, args.variance).with_context(|| "writing the EXR")?;
    let rate = stats.spp as f64 * film.mean.len() as f64 / stats.seconds.max(1e-9);
    eprintln!(
        "wrote {} ({}x{}, {} spp, method {} [{}], {:.2} s, {:.3} M pixel samples/s, {:.3} M rays/s)",
        output.display(),
        film.width,
        film.height,
        stats.spp,
        preset,
        method,
        stats.seconds,
        rate / 1e6,
        rays as f64 / stats.seconds.max(1e-9) / 1e6
    );
    if let Some(png) = &args.png {
        write_png(png, &film, args.exposure).with_context(|| "writing the PNG preview")?;
        eprintln!("wrote {}", png.display());
    }
    if stats.interrupted {
        eprintln!("interrupted: the image holds the {} spp finished before Ctrl-C", stats.spp);
        return Ok(EXIT_INTERRUPTED);
    }
    Ok(0)
}

fn progress_bar(budget: Budget, quiet: bool) -> ProgressBar {
    let visible = !quiet && std::io::stderr().is_terminal();
    let bar = match budget {
        Budget::Samples(n) => ProgressBar::new(n).with_style(
            ProgressStyle::with_template("{bar:40} {pos}/{len} spp  {per_sec}  ETA {eta}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        ),
        Budget::Time(t) => ProgressBar::new(t.as_millis() as u64).with_style(
            ProgressStyle::with_template("{bar:40} {msg}  {elapsed} / {duration}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        ),
    };
    if !visible {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    bar
}
