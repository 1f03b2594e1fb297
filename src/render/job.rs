//! One render from a scene to its files, the one way every command renders (`render`, the
//! study's runs and reference, `advise`'s pilots, the viewer's saves share its header): the
//! renderer for a method and seed, the stop rules (a sample count or a time, a target error,
//! Ctrl-C through the cancel flag), the checkpoint plan, and the files written atomically.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};
use std::time::Duration;

use crate::display::DisplayTransform;
use crate::estimate::target::Target;
use crate::estimate::{ErrorEstimate, Estimator};
use crate::film::Film;
use crate::gpu::{Gpu, PathTracerPipelines};
use crate::method::Method;
use crate::output::{write_exr, write_png, Metadata, OutputError};
use crate::scene::Scene;

use super::to_target::render_to_target;
use super::{
    render_checkpointed, Budget, CheckpointError, CheckpointKey, CheckpointPlan, ImageHeader, Progress, RenderError, RenderStats, Renderer,
    MAX_SPP,
};

/// Estimating the error while rendering, without a reference (`estimate`): to stop once a
/// target is reached, or (no target) to record the estimates as a pilot does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorPlan {
    pub target: Option<Target>,
    /// Check every so often; `None`: as often as the checks' own cost allows (~2% of the time).
    pub every: Option<Duration>,
    /// The display transform of a PSNR estimate.
    pub display: DisplayTransform,
    /// Pixels a check estimates from (evenly spaced rows); `None`: `to_target::CHECK_PIXELS`.
    pub check_pixels: Option<u32>,
}

/// What to render: the scene (with any size or depth overrides applied), where it came from,
/// the method, the seed, when to stop, the first sample index, and where to checkpoint.
#[derive(Debug, Clone)]
pub struct RenderJob {
    pub scene: Scene,
    pub scene_path: PathBuf,
    pub method: Method,
    pub seed: u32,
    /// Samples per pixel or wall time; with an error plan, the upper bound.
    pub budget: Budget,
    /// Stop at a target error (or record estimates): renders in randomisations, see `estimate`.
    pub error: Option<ErrorPlan>,
    /// Sample index of the first sample (0 except for a sample range of a split render).
    pub first_sample: u64,
    /// Save the accumulators during the render (needs a sample budget).
    pub checkpoint: Option<CheckpointPlan>,
    /// What the header records of the method's techniques' check (`technique::prove`).
    pub technique_verdict: Option<String>,
}

/// The error estimates of a render with an error plan.
#[derive(Debug, Clone)]
pub struct ErrorTrack {
    pub estimate: ErrorEstimate,
    pub estimator: Estimator,
    pub reached: bool,
    /// Estimates made along the way, and the wall time they took.
    pub checks: u32,
    pub check_seconds: f64,
    /// Every check: (seconds of rendering so far, spp, estimate).
    pub history: Vec<(f64, u64, ErrorEstimate)>,
}

/// A finished (or interrupted) render.
#[derive(Debug, Clone)]
pub struct RenderOutcome {
    pub film: Film,
    /// Rays traced (camera, bounce and shadow), counted by the kernel.
    pub rays: u64,
    /// Samples in which a researcher's technique faulted and contributed 0 (not kept in
    /// checkpoints: counted from the session that rendered them).
    pub faults: u64,
    pub stats: RenderStats,
    /// With an error plan: the estimates.
    pub error: Option<ErrorTrack>,
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

impl RenderJob {
    /// A job of `budget` from sample index 0, without checkpoints or error plan.
    pub fn new(scene: Scene, scene_path: PathBuf, method: Method, seed: u32, budget: Budget) -> RenderJob {
        RenderJob { scene, scene_path, method, seed, budget, error: None, first_sample: 0, checkpoint: None, technique_verdict: None }
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
            rr_depth: self.scene.render.rr_depth,
            techniques: crate::scene::technique::stamp(&self.method, &self.scene.techniques),
        }
    }

    /// Checks the accumulators this job would continue from (`render --resume`, a part's
    /// existing file) without a GPU, so that a bad file is refused before any GPU work.
    pub fn check_saved(&self) -> Result<(), CheckpointError> {
        if let (Some(plan), Budget::Samples(spp)) = (&self.checkpoint, self.budget) {
            plan.saved(&self.checkpoint_key(), self.first_sample, spp)?;
        }
        Ok(())
    }

    /// Renders until a stop rule holds (budget, target, `cancel`), saving checkpoints when
    /// planned, and reads the film back.
    pub fn run(
        &self,
        gpu: &Gpu,
        pipelines: &PathTracerPipelines,
        cancel: &AtomicBool,
        mut progress: impl FnMut(Progress),
    ) -> Result<RenderOutcome, CheckpointError> {
        if let Some(plan) = &self.error {
            return self.run_to_target(plan, gpu, pipelines, cancel, progress);
        }
        let mut renderer = Renderer::new(gpu, pipelines, &self.scene, self.method, self.seed)?;
        if self.first_sample > 0 {
            renderer.start_at_sample(self.first_sample)?;
        }
        let Some(plan) = &self.checkpoint else {
            let stats = renderer.render(self.budget, cancel, &mut progress)?;
            let readback = renderer.readback()?;
            return Ok(RenderOutcome { film: readback.film, rays: readback.rays, faults: readback.faults, stats, error: None });
        };
        let Budget::Samples(spp) = self.budget else {
            return Err(CheckpointError::Invalid { path: plan.path.clone(), message: "checkpoints need a sample budget (--spp), not a time".into() });
        };
        let (saved, interrupted) = render_checkpointed(&mut renderer, &self.checkpoint_key(), spp, plan, cancel, progress)?;
        // Seconds of every session that rendered these samples.
        let stats = RenderStats { spp: saved.spp, seconds: saved.render_seconds, frames: 0, interrupted };
        Ok(RenderOutcome { film: saved.film(), rays: saved.rays(), faults: saved.faults(), stats, error: None })
    }

    /// The randomised loop of `to_target`, bounded by the budget.
    fn run_to_target(
        &self,
        plan: &ErrorPlan,
        gpu: &Gpu,
        pipelines: &PathTracerPipelines,
        cancel: &AtomicBool,
        progress: impl FnMut(Progress),
    ) -> Result<RenderOutcome, CheckpointError> {
        if self.checkpoint.is_some() || self.first_sample > 0 {
            return Err(RenderError::Unsupported("a target error cannot be combined with checkpoints or sample ranges").into());
        }
        let (max_spp, max_time) = match self.budget {
            Budget::Samples(n) => (Some(n.min(MAX_SPP)), None),
            Budget::Time(t) => (None, Some(t)),
        };
        let out = render_to_target(
            gpu,
            pipelines,
            &self.scene,
            self.method,
            self.seed,
            plan.target,
            &plan.display,
            max_spp,
            max_time,
            plan.every,
            plan.check_pixels.unwrap_or(super::to_target::CHECK_PIXELS),
            cancel,
            progress,
        )?;
        Ok(RenderOutcome {
            stats: RenderStats { spp: out.film.spp, seconds: out.seconds, frames: 0, interrupted: out.interrupted },
            film: out.film,
            rays: out.rays,
            faults: out.faults,
            error: Some(ErrorTrack {
                estimate: out.estimate,
                estimator: out.estimator,
                reached: out.reached,
                checks: out.checks,
                check_seconds: out.check_seconds,
                history: out.history,
            }),
        })
    }

    /// The header of `outcome`'s image.
    pub fn header(&self, outcome: &RenderOutcome, adapter: &str) -> ImageHeader {
        ImageHeader {
            method: self.method,
            seed: self.seed,
            max_depth: self.scene.render.max_depth,
            rr_depth: self.scene.render.rr_depth,
            spp: outcome.stats.spp,
            rays: outcome.rays,
            render_seconds: outcome.stats.seconds,
            scene_hash: self.scene.content_hash(),
            scene: Some(self.scene_path.clone()),
            display: Some(self.scene.display),
            adapter: Some(adapter.to_string()),
            techniques: crate::scene::technique::stamp(&self.method, &self.scene.techniques),
            technique_faults: Some(outcome.faults),
        }
    }

    /// The EXR header of `outcome`, with the error plan's results when there was one.
    pub fn metadata(&self, outcome: &RenderOutcome, adapter: &str) -> Metadata {
        let mut extra: Vec<(&str, String)> = Vec::new();
        if let Some(v) = &self.technique_verdict {
            extra.push(("technique_verdict", v.clone()));
        }
        if let (Some(plan), Some(track)) = (&self.error, &outcome.error) {
            match plan.target {
                Some(Target::RelMse(t)) => extra.push(("target_rel_mse", t.to_string())),
                Some(Target::Psnr(db)) => extra.push(("target_psnr", db.to_string())),
                None => {}
            }
            extra.extend([
                ("estimated_rel_mse", format!("{:.6e}", track.estimate.rel_mse)),
                ("estimated_psnr", track.estimate.psnr.map_or("-".into(), |p| format!("{p:.4}"))),
                ("estimator", track.estimator.describe()),
                ("target_reached", track.reached.to_string()),
            ]);
        }
        self.header(outcome, adapter).metadata(&extra)
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
