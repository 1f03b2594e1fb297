//! The study's ground truth: loaded from an EXR, or rendered (default `best` at 100,000 spp)
//! with checkpoints so that a reference of hours survives interruption, and cached in the study
//! directory for later studies of the same scene, method, size and spp.
//!
//! Files: `DIR/reference.exr` (mean and variance, header with the scene hash and the spp) and
//! `DIR/reference.checkpoint.exr` (the raw accumulators: continued by a rerun, bit-identical to
//! an uninterrupted render; kept after completion so a larger `--reference-spp` continues it).

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use crate::gpu::{Gpu, PathTracerPipelines};
use crate::method::Method;
use crate::output::{read_exr_image, Metadata};
use crate::progress::{Reporter, Task};
use crate::render::{Budget, CheckpointKey, CheckpointPlan, OutputFiles, RenderJob, Resume};
use crate::film::Film;
use crate::scene::Scene;

use super::StudyError;

/// Seed of rendered references (the study's own runs use seeds 1..=K).
pub const REFERENCE_SEED: u32 = 1_000_003;

/// Where the reference comes from.
#[derive(Debug, Clone)]
pub enum ReferenceSource {
    /// An EXR made elsewhere (another renderer, a cluster, an earlier study).
    File(PathBuf),
    /// Rendered by the study.
    Render { method: Method, spp: u64 },
}

/// The reference as the study uses it.
#[derive(Debug, Clone)]
pub struct Reference {
    pub film: Film,
    /// True when the film carries per-pixel variances (rendered ones always do).
    pub has_variance: bool,
    /// One line saying what it is, for the report and the run records' cache keys.
    pub description: String,
    /// Rendering time over every session, when pathlab rendered it.
    pub render_seconds: Option<f64>,
    /// Its own expected relMSE: mean over pixels of var / (ref^2 + 0.01), from its variance.
    pub expected_rel_mse: Option<f64>,
    /// What the user should know about it (told when the study starts).
    pub warnings: Vec<String>,
}

/// The reference's own expected relMSE: its per-pixel variance of the mean over
/// (mean^2 + 0.01), the estimate `estimate::within_pixel` makes.
pub fn expected_rel_mse(film: &Film) -> f64 {
    crate::estimate::within_pixel(film, None).rel_mse
}

pub fn exr_path(dir: &Path) -> PathBuf {
    dir.join("reference.exr")
}

pub fn checkpoint_path(dir: &Path) -> PathBuf {
    dir.join("reference.checkpoint.exr")
}

fn meta<'a>(metadata: &'a Metadata, key: &str) -> Option<&'a str> {
    metadata.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str())
}

/// Loads a reference file (before any GPU work), refusing one of another size, one that
/// pathlab made of another scene or max_depth (its header says so), and one with a non-finite
/// pixel (`read_exr_image`). A file from elsewhere (no pathlab header) is taken as it is.
pub fn load_file(path: &Path, scene: &Scene) -> Result<Reference, StudyError> {
    let (width, height) = (scene.render.width, scene.render.height);
    let image = read_exr_image(path)?;
    let recorded = |key: &str| meta(&image.metadata, key);
    let mut warnings = Vec::new();
    if let Some(depth) = recorded("max_depth") {
        if depth != scene.render.max_depth.to_string() {
            return Err(StudyError::Input(format!(
                "the reference {} was rendered with max_depth {depth}, the study renders max_depth {} (use --max-depth {depth})",
                path.display(),
                scene.render.max_depth
            )));
        }
    }
    if let Some(hash) = recorded("scene_hash") {
        let current = scene.content_hash();
        // 0.1.0 hashed the scene's debug text: its hashes cannot be compared with today's.
        let comparable = recorded("version").is_some_and(|v| v != "0.1.0");
        if !comparable {
            warnings.push(format!(
                "the reference {} was made by pathlab 0.1.0, whose scene hash cannot be compared with this scene's: \
                 make sure it is of this scene",
                path.display()
            ));
        }
        if comparable && hash != current && (image.film.width, image.film.height) == (width, height) {
            return Err(StudyError::Input(format!(
                "the reference {} was rendered from another scene (its pathlab:scene_hash is {hash}, this scene's is {current}): \
                 a reference must be of the scene it scores",
                path.display()
            )));
        }
    }
    let film = image.film;
    if (film.width, film.height) != (width, height) {
        return Err(StudyError::Input(format!(
            "the reference {} is {}x{}, the study renders {width}x{height} (use --size {}x{})",
            path.display(),
            film.width,
            film.height,
            film.width,
            film.height
        )));
    }
    let expected = image.has_variance.then(|| expected_rel_mse(&film));
    Ok(Reference {
        warnings,
        description: format!("{} ({} spp, loaded)", path.display(), film.spp),
        render_seconds: meta(&image.metadata, "render_seconds").and_then(|s| s.parse().ok()),
        has_variance: image.has_variance,
        expected_rel_mse: expected,
        film,
    })
}

/// The rendered reference's identity: what must match for a cached one to be reused.
fn rendered_description(method: &Method, spp: u64, key: &CheckpointKey) -> String {
    format!(
        "{} at {spp} spp, seed {}, {}x{}, max_depth {}, scene {}",
        method.name(),
        key.seed,
        key.width,
        key.height,
        key.max_depth,
        key.scene_hash
    )
}

/// Renders the reference (or reuses the cached one). Returns `None` when interrupted, after
/// saving a checkpoint.
#[allow(clippy::too_many_arguments)]
pub fn render(
    dir: &Path,
    scene: &Scene,
    method: Method,
    spp: u64,
    every: Duration,
    gpu: &Gpu,
    pipelines: &PathTracerPipelines,
    cancel: &AtomicBool,
    reporter: &dyn Reporter,
) -> Result<Option<Reference>, StudyError> {
    let checkpoint = checkpoint_path(dir);
    let mut job = RenderJob::new(scene.clone(), scene.path.clone(), method, REFERENCE_SEED, Budget::Samples(spp));
    job.checkpoint = Some(CheckpointPlan { path: checkpoint.clone(), every, resume: Resume::IfPresent, planned_total: None });
    let description = rendered_description(&method, spp, &job.checkpoint_key());
    let cached = exr_path(dir);
    if cached.exists() {
        if let Ok(image) = read_exr_image(&cached) {
            if meta(&image.metadata, "reference") == Some(description.as_str()) && image.has_variance {
                reporter.note(&format!("reference: reusing {} ({description})", cached.display()));
                return Ok(Some(Reference {
                    warnings: Vec::new(),
                    expected_rel_mse: Some(expected_rel_mse(&image.film)),
                    render_seconds: meta(&image.metadata, "render_seconds").and_then(|s| s.parse().ok()),
                    film: image.film,
                    has_variance: true,
                    description,
                }));
            }
        }
    }
    if checkpoint.exists() {
        reporter.note(&format!("reference: continuing from {}", checkpoint.display()));
    }
    reporter.note(&format!("reference: rendering {description} (checkpoint every {} s)", every.as_secs_f64()));
    reporter.begin(Task::Samples(spp));
    let outcome = job.run(gpu, pipelines, cancel, |p| reporter.update(p.spp_done as f64, ""))?;
    reporter.end();
    let stats = outcome.stats;
    if stats.interrupted {
        reporter.note(&format!("reference: interrupted at {} of {spp} spp; checkpoint saved in {}", stats.spp, checkpoint.display()));
        return Ok(None);
    }
    let files = OutputFiles { exr: cached.clone(), png: None, display: scene.display, variance: true };
    job.write(&outcome, &gpu.info.name, &files, &vec![("reference".to_string(), description.clone())])?;
    reporter.note(&format!("reference: {} spp in {:.1} s, wrote {}", stats.spp, stats.seconds, cached.display()));
    let film = outcome.film;
    Ok(Some(Reference {
        warnings: Vec::new(),
        expected_rel_mse: Some(expected_rel_mse(&film)),
        film,
        has_variance: true,
        description,
        render_seconds: Some(stats.seconds),
    }))
}
