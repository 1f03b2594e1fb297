//! The study's individual renders: one method, one budget (samples per pixel or seconds), one
//! seed, scored against the reference. Each finished run is saved as `DIR/runs/NAME.json`, so an
//! interrupted study reruns only what it had not finished; a record made against another
//! reference, scene, size or display transform is not reused.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use serde::{Deserialize, Serialize};

use crate::display::DisplayTransform;
use crate::gpu::{Gpu, PathTracerPipelines};
use crate::metrics::compare;
use crate::names::named_enum;
use crate::method::{BsdfSampling, LightSampling, Method, Sampler};
use crate::output::{write_atomically, write_exr};
use crate::render::{Budget, RenderJob, RenderOutcome};

use super::regions::{self, Region, RegionError};
use super::{Reference, StudyError, StudyMethod};

named_enum! {
    /// Which table a run belongs to.
    pub enum Table("table") {
        /// Every method at the same samples per pixel.
        EqualSamples = "equal-samples",
        /// Every method for the same wall time.
        EqualTime = "equal-time",
    }
}

/// One run's measurements. The scene/method/size fields join with `pathlab bench --json`
/// records on (scene, method, width, height, max_depth).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RunRecord {
    pub table: Table,
    /// The method by its one name (`Method::name`), and its parts.
    pub method: Method,
    pub sampler: Sampler,
    pub bsdf: BsdfSampling,
    pub lights: LightSampling,
    /// A deliberately biased demonstration method.
    pub biased: bool,
    pub scene: String,
    pub scene_hash: String,
    pub width: u32,
    pub height: u32,
    pub max_depth: u32,
    pub seed: u32,
    /// The budget: samples per pixel (equal-samples) or seconds (equal-time).
    pub budget_spp: Option<u64>,
    pub budget_seconds: Option<f64>,
    /// Samples per pixel rendered.
    pub spp: u64,
    /// Wall time of the render (pipeline compiled beforehand; readback not included).
    pub seconds: f64,
    pub pixel_samples_per_second: f64,
    pub rays: u64,
    pub mse: f64,
    pub rel_mse: f64,
    /// Mean bias per channel, test - reference.
    pub bias: [f64; 3],
    pub psnr: f64,
    pub ssim: f64,
    pub flip: f64,
    /// The reference and display transform the metrics were computed against.
    pub reference: String,
    pub display: String,
    pub adapter: String,
    /// relMSE in each of the study's regions (`--regions`), in their order.
    #[serde(default)]
    pub regions: Vec<RegionError>,
}

/// What one run is.
#[derive(Debug, Clone)]
pub struct RunSpec<'a> {
    pub table: Table,
    pub method: &'a StudyMethod,
    pub budget: Budget,
    pub seed: u32,
}

impl RunSpec<'_> {
    /// File stem of its record, e.g. `equal-samples-mis-64spp-s2`.
    pub fn stem(&self) -> String {
        let budget = match self.budget {
            Budget::Samples(n) => format!("{n}spp"),
            Budget::Time(t) => format!("{}s", t.as_secs_f64()),
        };
        format!("{}-{}-{budget}-s{}", self.table.name(), self.method.name, self.seed)
    }
}

/// Where a run's image is kept, when it is kept (see `Study::keep_image`).
pub fn image_path(dir: &Path, method: &str, spp: u64, seed: u32) -> PathBuf {
    dir.join("images").join(format!("{method}-{spp}spp-s{seed}.exr"))
}

/// A saved record of `spec`, if it was made against the same reference, scene, display and
/// regions.
pub fn cached(dir: &Path, spec: &RunSpec, job: &RenderJob, reference: &Reference, display: &DisplayTransform, regions: &[Region]) -> Option<RunRecord> {
    let text = std::fs::read_to_string(dir.join("runs").join(format!("{}.json", spec.stem()))).ok()?;
    let record: RunRecord = serde_json::from_str(&text).ok()?;
    (record.reference == reference.description
        && record.display == display.to_string()
        && record.scene_hash == job.scene.content_hash()
        && (record.width, record.height, record.max_depth) == (job.scene.render.width, job.scene.render.height, job.scene.render.max_depth)
        && record.regions.iter().map(|r| &r.name).eq(regions.iter().map(|r| &r.name)))
        .then_some(record)
}

/// Renders `spec`, scores it, saves its record (and its image when `keep_image`). Returns
/// `None` when interrupted (nothing is saved for an unfinished run).
#[allow(clippy::too_many_arguments)]
pub fn execute(
    dir: &Path,
    spec: &RunSpec,
    job: &RenderJob,
    reference: &Reference,
    display: &DisplayTransform,
    study_regions: &[Region],
    keep_image: bool,
    gpu: &Gpu,
    pipelines: &PathTracerPipelines,
    cancel: &AtomicBool,
) -> Result<Option<RunRecord>, StudyError> {
    let outcome: RenderOutcome = job.run(gpu, pipelines, cancel, |_| {})?;
    if outcome.stats.interrupted {
        return Ok(None);
    }
    let c = compare(&outcome.film, &reference.film, *display, false)?;
    let (w, h) = (job.scene.render.width, job.scene.render.height);
    let m = &spec.method.method;
    let record = RunRecord {
        table: spec.table,
        method: *m,
        sampler: m.sampler,
        bsdf: m.bsdf,
        lights: m.lights,
        biased: spec.method.biased,
        scene: job.scene_path.display().to_string(),
        scene_hash: job.scene.content_hash(),
        width: w,
        height: h,
        max_depth: job.scene.render.max_depth,
        seed: spec.seed,
        budget_spp: match spec.budget {
            Budget::Samples(n) => Some(n),
            Budget::Time(_) => None,
        },
        budget_seconds: match spec.budget {
            Budget::Time(t) => Some(t.as_secs_f64()),
            Budget::Samples(_) => None,
        },
        spp: outcome.stats.spp,
        seconds: outcome.stats.seconds,
        pixel_samples_per_second: outcome.stats.spp as f64 * w as f64 * h as f64 / outcome.stats.seconds.max(1e-9),
        rays: outcome.rays,
        mse: c.mse,
        rel_mse: c.rel_mse,
        bias: c.bias.map(|b| b.bias),
        psnr: c.psnr,
        ssim: c.ssim,
        flip: c.flip,
        reference: reference.description.clone(),
        display: display.to_string(),
        adapter: gpu.info.name.clone(),
        regions: study_regions
            .iter()
            .map(|r| RegionError { name: r.name.clone(), rel_mse: regions::rel_mse(&outcome.film, &reference.film, r) })
            .collect(),
    };
    if keep_image {
        let metadata = job.metadata(&outcome, &gpu.info.name);
        write_exr(&image_path(dir, &spec.method.name, outcome.stats.spp, spec.seed), &outcome.film, &metadata, true)?;
    }
    let json = serde_json::to_string_pretty(&record).map_err(|e| StudyError::Input(e.to_string()))?;
    let path = dir.join("runs").join(format!("{}.json", spec.stem()));
    write_atomically(&path, |w| std::io::Write::write_all(w, json.as_bytes()).map_err(|e| e.to_string()))?;
    Ok(Some(record))
}

/// The budget of an equal-time run.
pub fn time_budget(seconds: f64) -> Budget {
    Budget::Time(Duration::from_secs_f64(seconds))
}
