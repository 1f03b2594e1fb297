//! The study's outputs: `results.json` (every number), `convergence.csv` (the points behind the
//! plots), `relmse_vs_spp.png` and `relmse_vs_seconds.png`, `grid.png`, and `report.md` tying
//! them together. All written atomically.

//!
//! `write` gathers the numbers (`results.json` here); `csv`, `plots`, `grid` and `markdown`
//! each write one output from them.

mod csv;
mod grid;
mod markdown;
mod plots;

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::gpu::{adapter_summary, Gpu};
use crate::method::Method;
use crate::output::{write_atomically, OutputError};
use crate::progress::Reporter;

use super::analysis::{convergence, default_target, rows, Convergence, Row};
use super::runs::{RunRecord, Table};
use super::verdict::Verdict;
use super::{Reference, Study, StudyError};

/// The reference's own error is "not negligible" above this share of the smallest relMSE
/// measured against it.
pub const REFERENCE_WARNING_SHARE: f64 = 0.1;

#[derive(Serialize)]
pub(super) struct ReferenceInfo {
    pub(super) description: String,
    pub(super) spp: u64,
    pub(super) render_seconds: Option<f64>,
    pub(super) expected_rel_mse: Option<f64>,
    pub(super) warning: Option<String>,
}

#[derive(Serialize)]
pub(super) struct Machine {
    pub(super) cpu: String,
    pub(super) cores: usize,
    pub(super) os: String,
    pub(super) adapter: String,
}

#[derive(Serialize)]
pub(super) struct Results<'a> {
    pub(super) pathlab_version: &'static str,
    pub(super) command: &'a str,
    pub(super) date_utc: String,
    pub(super) scene: String,
    pub(super) scene_hash: String,
    pub(super) width: u32,
    pub(super) height: u32,
    pub(super) max_depth: u32,
    pub(super) display: String,
    pub(super) seeds: u32,
    pub(super) machine: Machine,
    pub(super) reference: ReferenceInfo,
    pub(super) target_rel_mse: Option<f64>,
    pub(super) equal_samples: Vec<Row>,
    pub(super) equal_time: Vec<Row>,
    pub(super) convergence: Vec<Convergence>,
    pub(super) verdicts: &'a [Verdict],
    pub(super) runs: &'a [RunRecord],
    pub(super) study_seconds: f64,
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("model name")).and_then(|l| l.split(':').nth(1)).map(|m| m.trim().to_string()))
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// Today's date (UTC) as YYYY-MM-DD.
fn today_utc() -> String {
    humantime::format_rfc3339_seconds(std::time::SystemTime::now()).to_string()[..10].to_string()
}

pub(super) fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    write_atomically(path, |w| std::io::Write::write_all(w, text.as_bytes()).map_err(|e| e.to_string()))
}




/// Writes every output; returns the report's path.
pub fn write(
    study: &Study,
    reference: &Reference,
    records: &[RunRecord],
    verdicts: &[Verdict],
    gpu: &Gpu,
    study_seconds: f64,
    reporter: &dyn Reporter,
) -> Result<PathBuf, StudyError> {
    let dir = &study.out;
    let methods: Vec<Method> = study.methods.iter().map(|m| m.method).collect();
    let spp_budgets: Vec<f64> = study.spp.iter().map(|&n| n as f64).collect();
    let equal_samples = rows(records, Table::EqualSamples, &methods, &spp_budgets);
    let equal_time = rows(records, Table::EqualTime, &methods, &study.times);
    let target = study.target.or_else(|| default_target(&equal_samples));
    let conv = convergence(records, &methods, target.unwrap_or(0.0));
    let smallest = records.iter().map(|r| r.rel_mse).fold(f64::INFINITY, f64::min);
    let warning = reference.expected_rel_mse.filter(|&e| e > REFERENCE_WARNING_SHARE * smallest).map(|e| {
        format!(
            "the reference's own expected relMSE ({e:.2e}) is more than {:.0}% of the smallest relMSE measured against it ({smallest:.2e}): \
             errors near it are inflated by the reference's noise; render a longer reference",
            100.0 * REFERENCE_WARNING_SHARE
        )
    });
    if let Some(w) = &warning {
        reporter.warn(w);
    }
    let adapter = adapter_summary(&gpu.info);
    let results = Results {
        pathlab_version: crate::VERSION,
        command: &study.command,
        date_utc: today_utc(),
        scene: study.scene_path.display().to_string(),
        scene_hash: study.scene.content_hash(),
        width: study.scene.render.width,
        height: study.scene.render.height,
        max_depth: study.scene.render.max_depth,
        display: study.display.to_string(),
        seeds: study.seeds,
        machine: Machine {
            cpu: cpu_model(),
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            os: std::env::consts::OS.to_string(),
            adapter: adapter.clone(),
        },
        reference: ReferenceInfo {
            description: reference.description.clone(),
            spp: reference.film.spp,
            render_seconds: reference.render_seconds,
            expected_rel_mse: reference.expected_rel_mse,
            warning: warning.clone(),
        },
        target_rel_mse: target,
        equal_samples,
        equal_time,
        convergence: conv,
        verdicts,
        runs: records,
        study_seconds,
    };
    let json = serde_json::to_string_pretty(&results).map_err(|e| StudyError::Input(e.to_string()))?;
    write_text(&dir.join("results.json"), &json)?;
    csv::write(&dir.join("convergence.csv"), records)?;
    plots::write(dir, &methods, records, &results.convergence)?;
    let grid_spp = grid::write(study, reference)?;
    let path = dir.join("report.md");
    write_text(&path, &markdown::report(study, reference, &results, verdicts, smallest, target, grid_spp))?;
    Ok(path)
}
