//! `pathlab view`: the interactive window (see `pathlab::viewer`).

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{bail, Context};
use clap::Args;

use pathlab::method::Method;
use pathlab::output::read_exr;
use pathlab::viewer::{View, ViewerOptions};

use super::{load_scene, named, parse_method, parse_size, SceneOverrides};

#[derive(Args)]
pub struct ViewArgs {
    /// Scene file (TOML); edits to it are picked up while the window is open.
    scene: PathBuf,
    /// Method (a preset or a biased demonstration: plain, halton, cosine, phong, nee, mis, best,
    /// phong-lobe-only, nee-double-count). Default: `best`, and `best+env` under an environment
    /// map.
    #[arg(long, value_parser = parse_method)]
    method: Option<Method>,
    /// Start in the split view with this method in the right half (equal time for both).
    #[arg(long, value_parser = parse_method)]
    compare: Option<Method>,
    /// Reference image (EXR of the same size) for error views, PSNR, SSIM and relMSE.
    #[arg(long)]
    reference: Option<PathBuf>,
    #[command(flatten)]
    overrides: SceneOverrides,
    /// Seed of the first method (the second uses seed + 1).
    #[arg(long, default_value_t = 0)]
    seed: u32,
    /// Initial view: radiance, stderr, abs-error, rel-error.
    #[arg(long, default_value = "radiance", value_parser = named::<View>())]
    view: View,
    /// Exposure in stops.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    exposure: f32,
    /// Window size WxH (points). On a software rasteriser (lavapipe) the UI costs about 25 ms
    /// per frame at 1024x640 and 40 ms at 1280x800 of the same cores the renderer uses.
    #[arg(long, default_value = "1024x640", value_parser = parse_size)]
    window: (u32, u32),
    /// Exit after this many UI frames (with --screenshot: save the window's pixels first).
    #[arg(long)]
    frames: Option<u64>,
    /// Save the window's framebuffer as PNG after --frames frames, then exit.
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Print the final spp, frames per second and samples per second as one JSON line.
    #[arg(long)]
    log_stats: bool,
    /// Directory that S (save) writes into.
    #[arg(long, default_value = ".")]
    save_dir: PathBuf,
    /// Open paused (no samples until Space).
    #[arg(long)]
    paused: bool,
    /// Frame time the samples per frame adapt to, in milliseconds: the renderer gets what the
    /// UI leaves of it (45 ms: about 22 frames per second).
    #[arg(long, default_value_t = 45)]
    frame_ms: u64,
    /// Adapter whose name contains this (default: the best; or PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
    /// The method (and --compare) use each technique whose kind they name none of; it is
    /// checked before the window opens.
    #[command(flatten)]
    techniques: super::technique::TechniqueArgs,
}

pub fn run(args: ViewArgs) -> anyhow::Result<i32> {
    // Everything the user gave is checked before a window or a device is opened.
    let mut scene = load_scene(&args.scene)?;
    args.techniques.load(&mut scene)?;
    let mut display = args.overrides.apply(&mut scene, None)?;
    display.exposure = args.exposure;
    if args.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    if !(5..=1000).contains(&args.frame_ms) {
        bail!("--frame-ms must be between 5 and 1000");
    }
    let reference = match &args.reference {
        Some(path) => {
            let (film, _) = read_exr(path).with_context(|| format!("reading the reference {}", path.display()))?;
            if (film.width, film.height) != (scene.render.width, scene.render.height) {
                bail!(
                    "the reference {} is {}x{}, the image {}x{}: pass --size {}x{}",
                    path.display(),
                    film.width,
                    film.height,
                    scene.render.width,
                    scene.render.height,
                    film.width,
                    film.height
                );
            }
            Some(film)
        }
        None => None,
    };
    if args.view.needs_reference() && reference.is_none() {
        bail!("--view {} needs --reference", args.view.name());
    }
    if !args.save_dir.is_dir() {
        bail!("--save-dir {} is not a directory", args.save_dir.display());
    }
    if !scene.techniques.is_empty() {
        // Proven (or allowed unproven) before any window opens.
        let gpu = pathlab::gpu::Gpu::new(args.adapter.as_deref())?;
        args.techniques.prove_all(&gpu, &scene)?;
    }
    let named = args.method.unwrap_or_else(|| Method::from_name(scene.default_method_name()).expect("the default method is a method"));
    let (method, compare) = (args.techniques.apply(named, &scene), args.compare.map(|c| args.techniques.apply(c, &scene)));
    let options = ViewerOptions {
        scene,
        size: args.overrides.size,
        max_depth: args.overrides.max_depth,
        rr_depth: args.overrides.rr_depth.map(|r| r.0),
        defines: super::defines(),
        method,
        compare,
        seed: args.seed,
        reference,
        display,
        view: args.view,
        window: args.window,
        frames: args.frames,
        screenshot: args.screenshot,
        save_dir: args.save_dir,
        frame_budget: Duration::from_millis(args.frame_ms),
        paused: args.paused,
        adapter: args.adapter,
        reporter: std::sync::Arc::new(super::progress::Terminal::new(false)),
    };
    let report = pathlab::viewer::run(options)?;
    if args.log_stats {
        println!("{}", serde_json::to_string(&report)?);
    }
    Ok(0)
}
