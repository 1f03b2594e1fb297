//! `pathlab study`: the variance-reduction study as one command.
//!
//! 1. `reference`: the ground truth, loaded or rendered with checkpoints and cached;
//! 2. `runs`: every method at every spp and every wall-time budget over K seeds, each scored
//!    against the reference (records saved one by one, so a rerun continues);
//! 3. `analysis`: the equal-sample and equal-time tables, efficiency, convergence fits and the
//!    time to a target error;
//! 4. `verdict`: bias verdicts at the highest spp;
//! 5. `report`: `report.md`, `results.json`, the plots, the CSV and the image grid.

pub mod analysis;
pub mod options;
pub mod reference;
pub mod regions;
pub mod report;
pub mod runs;
pub mod verdict;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use crate::display::DisplayTransform;
use crate::gpu::{Gpu, PathTracerPipelines};
use crate::method::Method;
use crate::metrics::MetricsError;
use crate::output::{read_exr, OutputError};
use crate::progress::{Reporter, Task};
use crate::render::{warm_up, Budget, CheckpointError, RenderError, RenderJob};
use crate::scene::Scene;

pub use options::{default_methods, StudyOptions};
pub use reference::{Reference, ReferenceSource};
use runs::{RunRecord, RunSpec, Table};

#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error("{0}")]
    Input(String),
    /// A size or depth override that is impossible (named by the scene file's field).
    #[error(transparent)]
    Override(#[from] crate::scene::OverrideError),
    #[error(transparent)]
    Render(#[from] RenderError),
    #[error(transparent)]
    Checkpoint(#[from] CheckpointError),
    #[error(transparent)]
    Output(#[from] OutputError),
    #[error(transparent)]
    Metrics(#[from] MetricsError),
    #[error("cannot use the study directory {}: {source}", path.display())]
    Dir {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// A method of the study, by name.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyMethod {
    pub name: String,
    pub method: Method,
    /// A deliberately biased demonstration.
    pub biased: bool,
}

impl StudyMethod {
    pub fn by_name(name: &str) -> Result<StudyMethod, StudyError> {
        let method = Method::from_name(name).map_err(|e| StudyError::Input(e.to_string()))?;
        Ok(StudyMethod { name: method.name(), method, biased: method.is_biased() })
    }
}

/// Everything a study needs, checked by `Study::validate` before any GPU work.
#[derive(Debug, Clone)]
pub struct Study {
    /// The scene with the study's size and depth applied.
    pub scene: Scene,
    pub scene_path: PathBuf,
    pub out: PathBuf,
    pub methods: Vec<StudyMethod>,
    pub spp: Vec<u64>,
    pub times: Vec<f64>,
    pub seeds: u32,
    pub reference: ReferenceSource,
    /// Named rectangles whose relMSE every run also measures (`--regions`), at the study's size.
    pub regions: Vec<regions::Region>,
    pub display: DisplayTransform,
    /// Target relMSE for the time-to-target column (default: plain's at the largest spp).
    pub target: Option<f64>,
    pub checkpoint_every: Duration,
    /// The command line, for the report.
    pub command: String,
    /// How the study's size changes the scene's framing, if it does (told when it runs).
    pub reframing: Option<crate::scene::Reframing>,
    /// Methods left out of the study, each with why (told when it runs).
    pub left_out: Vec<String>,
}

/// How a study ended.
#[derive(Debug)]
pub enum StudyOutcome {
    Finished { report: PathBuf },
    Interrupted,
}

impl Study {
    /// Checks the settings and prepares the directory (no GPU work). A loaded reference is
    /// read here, so a missing or mis-sized file is reported before anything renders.
    pub fn validate(&self) -> Result<Option<Reference>, StudyError> {
        let bad = |m: String| Err(StudyError::Input(m));
        if self.methods.is_empty() {
            return bad("--methods names no method".into());
        }
        if self.spp.is_empty() || self.spp.contains(&0) {
            return bad("--spp needs positive sample counts".into());
        }
        if self.times.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
            return bad("--time needs positive numbers of seconds".into());
        }
        if self.seeds == 0 {
            return bad("--seeds must be at least 1".into());
        }
        if self.target.is_some_and(|t| !(t.is_finite() && t > 0.0)) {
            return bad("--target must be a positive relative MSE".into());
        }
        let (w, h) = (self.scene.render.width, self.scene.render.height);
        if w < crate::metrics::ssim::MIN_SIZE || h < crate::metrics::ssim::MIN_SIZE {
            return bad(format!("the study needs images of at least 7x7 pixels (SSIM's window), not {w}x{h}"));
        }
        if let ReferenceSource::Render { spp: 0, .. } = self.reference {
            return bad("--reference-spp must be at least 1".into());
        }
        for sub in ["", "runs", "images"] {
            let path = self.out.join(sub);
            std::fs::create_dir_all(&path).map_err(|source| StudyError::Dir { path: path.clone(), source })?;
        }
        let probe = self.out.join(".pathlab-write-test");
        std::fs::write(&probe, b"").map_err(|source| StudyError::Dir { path: self.out.clone(), source })?;
        let _ = std::fs::remove_file(probe);
        match &self.reference {
            ReferenceSource::File(path) => Ok(Some(reference::load_file(path, &self.scene)?)),
            ReferenceSource::Render { .. } => Ok(None),
        }
    }

    fn job(&self, method: &StudyMethod, budget: Budget, seed: u32) -> RenderJob {
        RenderJob::new(self.scene.clone(), self.scene_path.clone(), method.method, seed, budget)
    }

    /// The largest spp: its images (every seed) feed the bias verdicts.
    fn top_spp(&self) -> u64 {
        self.spp.iter().copied().max().unwrap_or(1)
    }

    /// Runs the study; `loaded` is what `validate` returned.
    pub fn run(
        &self,
        loaded: Option<Reference>,
        gpu: &Gpu,
        pipelines: &PathTracerPipelines,
        cancel: &AtomicBool,
        reporter: &dyn Reporter,
    ) -> Result<StudyOutcome, StudyError> {
        let dir = &self.out;
        let started = std::time::Instant::now();
        if let Some(reframing) = &self.reframing {
            reporter.note(&format!("note: {reframing}"));
        }
        for why in &self.left_out {
            reporter.note(&format!("note: {why}"));
        }
        reporter.stage("[1/4] reference");
        let reference = match (&self.reference, loaded) {
            (_, Some(r)) => r,
            (ReferenceSource::Render { method, spp }, None) => {
                match reference::render(dir, &self.scene, *method, *spp, self.checkpoint_every, gpu, pipelines, cancel, reporter)? {
                    Some(r) => r,
                    None => return Ok(StudyOutcome::Interrupted),
                }
            }
            (ReferenceSource::File(_), None) => unreachable!("validate loads file references"),
        };
        for w in &reference.warnings {
            reporter.warn(w);
        }

        // Every pipeline compiled before anything is timed.
        for m in &self.methods {
            warm_up(gpu, pipelines, &self.scene, m.method)?;
        }

        let mut specs: Vec<RunSpec> = Vec::new();
        for m in &self.methods {
            for &spp in &self.spp {
                for seed in 1..=self.seeds {
                    specs.push(RunSpec { table: Table::EqualSamples, method: m, budget: Budget::Samples(spp), seed });
                }
            }
        }
        for m in &self.methods {
            for &t in &self.times {
                for seed in 1..=self.seeds {
                    specs.push(RunSpec { table: Table::EqualTime, method: m, budget: runs::time_budget(t), seed });
                }
            }
        }
        reporter.stage(&format!(
            "[2/4] {} runs: {} methods x ({} spp budgets + {} time budgets) x {} seeds",
            specs.len(),
            self.methods.len(),
            self.spp.len(),
            self.times.len(),
            self.seeds
        ));
        reporter.begin(Task::Runs(specs.len() as u64));
        let mut records: Vec<RunRecord> = Vec::new();
        let mut reused = 0;
        for (done, spec) in specs.iter().enumerate() {
            reporter.update(done as f64, &spec.stem());
            let job = self.job(spec.method, spec.budget, spec.seed);
            let record = match runs::cached(dir, spec, &job, &reference, &self.display, &self.regions) {
                Some(r) if self.image_present(spec) => {
                    reused += 1;
                    r
                }
                _ => match runs::execute(dir, spec, &job, &reference, &self.display, &self.regions, self.keep_image(spec), gpu, pipelines, cancel)? {
                    Some(r) => r,
                    None => {
                        reporter.end();
                        return Ok(StudyOutcome::Interrupted);
                    }
                },
            };
            records.push(record);
            if cancel.load(Ordering::Relaxed) {
                reporter.end();
                return Ok(StudyOutcome::Interrupted);
            }
        }
        reporter.end();
        if reused > 0 {
            reporter.note(&format!("      {reused} runs reused from {}", dir.join("runs").display()));
        }

        reporter.stage(&format!("[3/4] bias verdicts at {} spp x {} seeds", self.top_spp(), self.seeds));
        let mut verdicts = Vec::new();
        for m in &self.methods {
            let films = (1..=self.seeds)
                .map(|s| read_exr(&runs::image_path(dir, &m.name, self.top_spp(), s)).map(|(f, _)| f))
                .collect::<Result<Vec<_>, _>>()?;
            verdicts.push(verdict::verdict(&self.scene, m, &films, &reference.film, self.methods.len()));
        }

        reporter.stage("[4/4] report");
        let report = report::write(self, &reference, &records, &verdicts, gpu, started.elapsed().as_secs_f64(), reporter)?;
        Ok(StudyOutcome::Finished { report })
    }

    /// Images kept: every seed at the top spp (bias verdicts), seed 1 at every spp (the grid).
    fn keep_image(&self, spec: &RunSpec) -> bool {
        match spec.budget {
            Budget::Samples(n) => spec.table == Table::EqualSamples && (n == self.top_spp() || spec.seed == 1),
            Budget::Time(_) => false,
        }
    }

    fn image_present(&self, spec: &RunSpec) -> bool {
        match spec.budget {
            Budget::Samples(n) if self.keep_image(spec) => runs::image_path(&self.out, &spec.method.name, n, spec.seed).exists(),
            _ => true,
        }
    }
}

/// Parses a comma-separated list.
pub fn parse_list<T: std::str::FromStr>(s: &str, what: &str) -> Result<Vec<T>, StudyError> {
    s.split(',')
        .map(str::trim)
        .filter(|x| !x.is_empty())
        .map(|x| x.parse::<T>().map_err(|_| StudyError::Input(format!("{what}: cannot read `{x}`"))))
        .collect()
}

/// The study's default directory layout, for documentation and tests.
pub fn layout(dir: &Path) -> Vec<PathBuf> {
    ["report.md", "results.json", "convergence.csv", "relmse_vs_spp.png", "relmse_vs_seconds.png", "grid.png", "reference.exr"]
        .iter()
        .map(|f| dir.join(f))
        .collect()
}
