//! `pathlab bench`: samples per second of every method at several image sizes, with device time
//! from GPU timestamps, host overhead and pipeline compile time. `--json` for machines: one
//! record per (method, size), keyed so it joins with error measurements on
//! (scene, method, width, height, max_depth).

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use anyhow::{bail, Context};
use clap::Args;
use serde::Serialize;

use pathlab::gpu::{adapter_summary, Gpu, PathTracerPipelines, PipelineKey, SceneFeatures};
use pathlab::method::{Method, Preset};
use pathlab::render::{Budget, Renderer};
use pathlab::scene::Scene;

use super::{load_scene, parse_size};

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file (default: the study scene).
    #[arg(default_value = "assets/scenes/study.toml")]
    scene: PathBuf,
    /// Methods to measure, comma-separated: any method name, as `render --method` (default:
    /// every preset).
    #[arg(long, value_parser = super::parse_method, value_delimiter = ',')]
    methods: Vec<Method>,
    /// Image sizes, WxH (default: 256x128 and 1024x512).
    #[arg(long = "size", value_parser = parse_size)]
    sizes: Vec<(u32, u32)>,
    /// Measured seconds per (method, size), after a warm-up.
    #[arg(long, default_value_t = 3.0)]
    seconds: f64,
    /// Path segments (default: the scene's).
    #[arg(long)]
    max_depth: Option<u32>,
    /// Russian roulette from this scattering vertex on, or `off` (default: the scene's).
    #[arg(long)]
    rr_depth: Option<super::RrDepth>,
    /// Print JSON records instead of a table.
    #[arg(long)]
    json: bool,
    /// Use the first adapter whose name contains this (also: PATHLAB_ADAPTER).
    #[arg(long)]
    adapter: Option<String>,
    /// Each technique is measured beside the methods whose strategy it replaces (as in
    /// `study`); bench measures speed, so it does not run the technique's check.
    #[command(flatten)]
    techniques: super::technique::TechniqueArgs,
    /// After each measurement, measure the same method with every optional feature of the
    /// kernel on (not specialised to the scene), for the speed-up of specialisation.
    #[arg(long)]
    unspecialised: bool,
}


/// One measurement.
#[derive(Serialize)]
pub struct Record {
    scene: String,
    method: String,
    sampler: String,
    bsdf: String,
    lights: String,
    width: u32,
    height: u32,
    max_depth: u32,
    /// Whether the pipeline was specialised to the scene's features (false: every optional
    /// feature on, `--unspecialised`).
    specialised: bool,
    /// Samples per pixel rendered in the measured interval.
    spp: u64,
    frames: u64,
    wall_seconds: f64,
    pixel_samples_per_second: f64,
    /// Camera, bounce and shadow rays traced in the measured interval, counted by the kernel.
    rays: u64,
    rays_per_second: f64,
    rays_per_sample: f64,
    /// Device time of the measured frames, from timestamp queries (null if unsupported).
    device_seconds: Option<f64>,
    /// Share of wall time not covered by device work: (wall - device) / wall.
    host_overhead: Option<f64>,
    /// `create_compute_pipeline` time. Drivers may defer compilation to the first dispatch
    /// (lavapipe does), so see also `first_frame_seconds`.
    pipeline_create_seconds: f64,
    /// Wall time of the first 1-spp frame after creation (includes any deferred compile).
    first_frame_seconds: f64,
    adapter: String,
}

pub fn run(args: BenchArgs) -> anyhow::Result<i32> {
    let mut base = load_scene(&args.scene)?;
    args.techniques.load(&mut base)?;
    if !(args.seconds.is_finite() && args.seconds > 0.0) {
        bail!("--seconds must be positive");
    }
    let methods: Vec<Method> = if args.methods.is_empty() { Preset::ALL.iter().map(|p| p.method()).collect() } else { args.methods.clone() };
    let methods: Vec<Method> = match super::technique::with_technique_rows(Some(methods.iter().map(|m| m.name()).collect()), &base)? {
        Some(names) => names.iter().map(|n| Method::from_name(n)).collect::<Result<_, _>>()?,
        None => methods,
    };
    // Methods that cannot see one of the scene's lights are left out, and said (before any GPU work).
    let (methods, blind): (Vec<Method>, Vec<Method>) = methods.into_iter().partition(|m| base.why_left_out(m).is_none());
    for why in blind.iter().filter_map(|m| base.why_left_out(m)) {
        eprintln!("note: {why}");
    }
    if methods.is_empty() {
        bail!("no method left to measure: every one given cannot see the scene's delta lights");
    }
    let sizes = if args.sizes.is_empty() { vec![(256, 128), (1024, 512)] } else { args.sizes.clone() };
    let gpu = Gpu::new(args.adapter.as_deref())?;
    eprintln!("adapter: {}", adapter_summary(&gpu.info));
    let mut records = Vec::new();
    let variants: &[bool] = if args.unspecialised { &[true, false] } else { &[true] };
    for &(width, height) in &sizes {
        for &method in &methods {
            for &specialised in variants {
                let mut scene = base.clone();
                scene.render.width = width;
                scene.render.height = height;
                scene.render.max_depth = args.max_depth.unwrap_or(scene.render.max_depth);
                if let Some(super::RrDepth(rr)) = args.rr_depth {
                    scene.render.rr_depth = rr;
                }
                let record = measure(&gpu, &scene, &args, method, specialised)
                    .with_context(|| format!("{} at {width}x{height}", method.name()))?;
                if !args.json {
                    print_row(&record, records.is_empty());
                }
                records.push(record);
            }
        }
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&records)?);
    }
    Ok(0)
}

/// One (method, size, specialisation) measurement: a fresh pipeline cache (so the record
/// carries its own compile time), a 1-spp first frame, 0.5 s of warm-up, then the timed interval.
fn measure(gpu: &Gpu, scene: &Scene, args: &BenchArgs, method: Method, specialised: bool) -> anyhow::Result<Record> {
    let never = AtomicBool::new(false);
    let features = SceneFeatures::of(scene);
    let features = if specialised { features } else { features.all_on() };
    let pipelines = PathTracerPipelines::new(&gpu);
    let techniques = pathlab::shaders::TechniqueFiles::of(&method, &scene.techniques)?;
    let (_, created) = pipelines.get(&gpu.device, PipelineKey::new(method, features, scene.default_light_select()), techniques);
    let mut renderer = if specialised {
        Renderer::new(gpu, &pipelines, scene, method, 0)?
    } else {
        Renderer::unspecialised(gpu, &pipelines, scene, method, 0)?
    };
    let first = renderer.render(Budget::Samples(1), &never, |_| {})?;
    // Warm-up: first dispatches, and the frame size settles.
    renderer.render(Budget::Time(Duration::from_secs_f64(0.5)), &never, |_| {})?;
    let timed = renderer.enable_timestamps();
    let (spp_before, rays_before) = (renderer.spp(), renderer.readback()?.rays);
    let stats = renderer.render(Budget::Time(Duration::from_secs_f64(args.seconds)), &never, |_| {})?;
    let (spp, rays) = (renderer.spp() - spp_before, renderer.readback()?.rays - rays_before);
    let device = if timed { renderer.device_time()? } else { None };
    // Device time covers at most the first frames: scale to all when it does not.
    let device_seconds = device.filter(|(_, n)| *n > 0).map(|(d, n)| d.as_secs_f64() * stats.frames as f64 / n as f64);
    let (width, height) = (scene.render.width, scene.render.height);
    let samples = width as f64 * height as f64 * spp as f64;
    Ok(Record {
        scene: args.scene.display().to_string(),
        method: method.name(),
        sampler: method.sampler.name().into(),
        bsdf: method.bsdf.name().into(),
        lights: method.lights.name().into(),
        width,
        height,
        max_depth: scene.render.max_depth,
        specialised,
        spp,
        frames: stats.frames,
        wall_seconds: stats.seconds,
        pixel_samples_per_second: samples / stats.seconds,
        rays,
        rays_per_second: rays as f64 / stats.seconds,
        rays_per_sample: rays as f64 / samples,
        device_seconds,
        host_overhead: device_seconds.map(|d| ((stats.seconds - d) / stats.seconds).max(0.0)),
        pipeline_create_seconds: created.compile_time.as_secs_f64(),
        first_frame_seconds: first.seconds,
        adapter: gpu.info.name.clone(),
    })
}

fn print_row(r: &Record, header: bool) {
    if header {
        println!(
            "{:<15} {:>10} {:>6} {:>12} {:>10} {:>9} {:>8} {:>9} {:>7} {:>9} {:>9}",
            "method",
            "size",
            "spp",
            "M samples/s",
            "M rays/s",
            "rays/spl",
            "wall s",
            "device s",
            "host %",
            "create s",
            "1st frame"
        );
    }
    let opt = |v: Option<f64>, scale: f64| v.map_or("-".to_string(), |x| format!("{:.3}", x * scale));
    println!(
        "{:<15} {:>10} {:>6} {:>12.3} {:>10.3} {:>9.3} {:>8.3} {:>9} {:>7} {:>9.3} {:>9.3}",
        if r.specialised { r.method.clone() } else { format!("{} (all on)", r.method) },
        format!("{}x{}", r.width, r.height),
        r.spp,
        r.pixel_samples_per_second / 1e6,
        r.rays_per_second / 1e6,
        r.rays_per_sample,
        r.wall_seconds,
        opt(r.device_seconds, 1.0),
        opt(r.host_overhead, 100.0),
        r.pipeline_create_seconds,
        r.first_frame_seconds
    );
}
