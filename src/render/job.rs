//! One render from a scene to its files, shared by `pathlab render`, the study and (later) the
//! viewer and the cluster commands: the renderer for a method and seed, the budget, progress,
//! cancellation (Ctrl-C), the EXR header and the files written atomically.

use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::display::DisplayTransform;
use crate::gpu::{Gpu, PathTracerPipelines};
use crate::method::{Method, Preset};
use crate::output::{write_exr, write_png, Metadata, OutputError};
use crate::scene::Scene;

use super::{
    render_checkpointed, Budget, CheckpointError, CheckpointKey, CheckpointPlan, Film, Progress, RenderError, RenderStats, Renderer,
};

/// What to render: the scene (with any size or depth overrides applied), where it came from,
/// the method, the seed, the budget, the first sample index, and where to checkpoint.
#[derive(Debug, Clone)]
pub struct RenderJob {
    pub scene: Scene,
    pub scene_path: PathBuf,
    pub method: Method,
    pub seed: u32,
    pub budget: Budget,
    /// Sample index of the first sample (0 except for a sample range of a split render).
    pub first_sample: u64,
    /// Save the accumulators during the render (needs a sample budget).
    pub checkpoint: Option<CheckpointPlan>,
}

/// A finished (or interrupted) render.
#[derive(Debug, Clone)]
pub struct RenderOutcome {
    pub film: Film,
    /// Rays traced (camera, bounce and shadow), counted by the kernel.
    pub rays: u64,
    pub stats: RenderStats,
}

/// Where a render's files go.
#[derive(Debug, Clone, Default)]
pub struct OutputFiles {
    pub exr: PathBuf,
    /// Also a PNG of the display image.
    pub png: Option<PathBuf>,
    /// The display transform of the PNG.
    pub display: DisplayTransform,
    /// Add variance-of-the-mean channels to the EXR.
    pub variance: bool,
}

/// The name a method is recorded under: its preset's, or `custom`.
pub fn method_label(method: &Method) -> &'static str {
    method.preset().map_or("custom", Preset::name)
}

/// The header fields saying what produced an image (every EXR pathlab writes has them):
/// spp, method (preset name or `custom`) and its parts, seed, max_depth, rays, version.
pub fn provenance(method: &Method, seed: u32, max_depth: u32, spp: u64, rays: u64) -> Metadata {
    [
        ("spp", spp.to_string()),
        ("method", method_label(method).to_string()),
        ("sampler", method.sampler.name().to_string()),
        ("bsdf", method.bsdf.name().to_string()),
        ("lights", method.lights.name().to_string()),
        ("seed", seed.to_string()),
        ("max_depth", max_depth.to_string()),
        ("rays", rays.to_string()),
        ("version", crate::VERSION.to_string()),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect()
}

/// Renders one sample per pixel of `method` and throws it away: drivers that compile at the
/// first dispatch (lavapipe) do it now, before anything is timed.
pub fn warm_up(gpu: &Gpu, pipelines: &PathTracerPipelines, scene: &Scene, method: Method) -> Result<(), RenderError> {
    Renderer::new(gpu, pipelines, scene, method, 0)?.render(Budget::Samples(1), &AtomicBool::new(false), |_| {})?;
    Ok(())
}

/// A flag set by Ctrl-C (SIGINT) for the rest of the process. The handler is installed once;
/// a second Ctrl-C while the flag is already set falls through to the default (exit).
pub fn ctrl_c_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        let _ = ctrlc::set_handler(move || {
            if f.swap(true, Ordering::Relaxed) {
                std::process::exit(130);
            }
        });
        flag
    })
    .clone()
}

/// A progress bar for `budget` on stderr, hidden when `quiet` or stderr is not a terminal.
pub fn progress_bar(budget: Budget, quiet: bool) -> ProgressBar {
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
    if quiet || !std::io::stderr().is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    bar
}

/// Moves `bar` (made by `progress_bar` for `budget`) to `p`.
pub fn show_progress(bar: &ProgressBar, budget: Budget, p: Progress) {
    match budget {
        Budget::Samples(_) => bar.set_position(p.spp_done),
        Budget::Time(_) => {
            bar.set_position(p.elapsed.as_millis() as u64);
            bar.set_message(format!("{} spp", p.spp_done));
        }
    }
}

impl RenderJob {
    /// A job of `budget` from sample index 0, without checkpoints.
    pub fn new(scene: Scene, scene_path: PathBuf, method: Method, seed: u32, budget: Budget) -> RenderJob {
        RenderJob { scene, scene_path, method, seed, budget, first_sample: 0, checkpoint: None }
    }

    /// What a checkpoint of this job must match.
    pub fn checkpoint_key(&self) -> CheckpointKey {
        CheckpointKey {
            scene_hash: self.scene.content_hash(),
            method: self.method,
            seed: self.seed,
            width: self.scene.render.width,
            height: self.scene.render.height,
            max_depth: self.scene.render.max_depth,
        }
    }

    /// Renders until the budget is met or `cancel` is set (saving checkpoints when planned),
    /// and reads the film back.
    pub fn run(
        &self,
        gpu: &Gpu,
        pipelines: &PathTracerPipelines,
        cancel: &AtomicBool,
        progress: impl FnMut(Progress),
    ) -> Result<RenderOutcome, CheckpointError> {
        let mut renderer = Renderer::new(gpu, pipelines, &self.scene, self.method, self.seed)?;
        if self.first_sample > 0 {
            renderer.start_at_sample(self.first_sample)?;
        }
        let Some(plan) = &self.checkpoint else {
            let stats = renderer.render(self.budget, cancel, progress)?;
            let readback = renderer.readback()?;
            return Ok(RenderOutcome { film: readback.film, rays: readback.rays, stats });
        };
        let Budget::Samples(spp) = self.budget else {
            return Err(CheckpointError::Invalid { path: plan.path.clone(), message: "checkpoints need a sample budget (--spp), not a time".into() });
        };
        let (saved, interrupted) = render_checkpointed(&mut renderer, &self.checkpoint_key(), spp, plan, cancel, progress)?;
        // Seconds of every session that rendered these samples.
        let stats = RenderStats { spp: saved.spp, seconds: saved.render_seconds, frames: 0, interrupted };
        Ok(RenderOutcome { film: saved.film(), rays: saved.rays(), stats })
    }

    /// The EXR header of `outcome`: `pathlab:KEY` attributes.
    pub fn metadata(&self, outcome: &RenderOutcome, adapter: &str) -> Metadata {
        let mut metadata = provenance(&self.method, self.seed, self.scene.render.max_depth, outcome.stats.spp, outcome.rays);
        metadata.extend(
            [
                ("render_seconds", format!("{:.6}", outcome.stats.seconds)),
                ("scene", self.scene_path.display().to_string()),
                ("scene_hash", self.scene.content_hash()),
                ("display", self.scene.display.transfer.to_string()),
                ("exposure", self.scene.display.exposure.to_string()),
                ("adapter", adapter.to_string()),
            ]
            .map(|(k, v)| (k.to_string(), v)),
        );
        metadata
    }

    /// Writes the EXR (and PNG) of `outcome`, each atomically; `extra` joins the header.
    pub fn write(&self, outcome: &RenderOutcome, adapter: &str, files: &OutputFiles, extra: &Metadata) -> Result<(), OutputError> {
        let mut metadata = self.metadata(outcome, adapter);
        metadata.extend(extra.iter().cloned());
        write_exr(&files.exr, &outcome.film, &metadata, files.variance)?;
        if let Some(png) = &files.png {
            write_png(png, &files.display.film(&outcome.film))?;
        }
        Ok(())
    }
}

/// `<scene stem>.exr` in the current directory.
pub fn default_output(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
    PathBuf::from(format!("{stem}.exr"))
}
