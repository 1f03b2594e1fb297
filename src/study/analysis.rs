//! From run records to answers: the equal-sample and equal-time tables (mean and spread over
//! seeds), efficiency 1 / (relMSE x seconds) and its ratio to `plain`, and the convergence fits
//! log relMSE = a + b log(spp) and a + b log(seconds) (least squares over every run; b = -1 for
//! plain Monte Carlo), with the time and spp each method needs to reach a target relMSE.

use serde::Serialize;

use crate::method::{Method, Preset};
use crate::stats::Fit;

/// The method every efficiency is compared with.
const PLAIN: Method = Preset::Plain.method();

use super::runs::{RunRecord, Table};

/// Mean and sample standard deviation over seeds.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Stat {
    pub mean: f64,
    /// Sample standard deviation (0 for a single value).
    pub spread: f64,
    pub n: usize,
}

impl Stat {
    pub fn of(values: &[f64]) -> Stat {
        let n = values.len();
        let mean = values.iter().sum::<f64>() / n.max(1) as f64;
        let spread =
            if n > 1 { (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt() } else { 0.0 };
        Stat { mean, spread, n }
    }
}

/// One row of a table: a method at one budget, over seeds.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    pub method: Method,
    pub biased: bool,
    /// The budget: spp (equal-samples) or seconds (equal-time).
    pub budget: f64,
    pub spp: Stat,
    pub seconds: Stat,
    pub psnr: Stat,
    pub ssim: Stat,
    pub flip: Stat,
    pub mse: Stat,
    pub rel_mse: Stat,
    pub pixel_samples_per_second: Stat,
    /// 1 / (mean relMSE x mean seconds).
    pub efficiency: f64,
    /// Efficiency over `plain`'s at the same budget (when `plain` is in the study).
    pub efficiency_vs_plain: Option<f64>,
    /// relMSE in each region of the study (`--regions`), over seeds.
    pub regions: Vec<RegionStat>,
}

/// One region's relMSE over seeds.
#[derive(Debug, Clone, Serialize)]
pub struct RegionStat {
    pub name: String,
    pub rel_mse: Stat,
}

/// The rows of `table`, in method order, then budget order.
pub fn rows(records: &[RunRecord], table: Table, methods: &[Method], budgets: &[f64]) -> Vec<Row> {
    let mut rows = Vec::new();
    for method in methods {
        for &budget in budgets {
            let runs: Vec<&RunRecord> = records
                .iter()
                .filter(|r| r.table == table && r.method == *method && budget_of(r) == Some(budget))
                .collect();
            if runs.is_empty() {
                continue;
            }
            let stat = |f: fn(&RunRecord) -> f64| Stat::of(&runs.iter().map(|r| f(r)).collect::<Vec<_>>());
            let rel_mse = stat(|r| r.rel_mse);
            let seconds = stat(|r| r.seconds);
            rows.push(Row {
                method: *method,
                biased: runs[0].biased,
                budget,
                spp: stat(|r| r.spp as f64),
                seconds,
                psnr: stat(|r| r.psnr),
                ssim: stat(|r| r.ssim),
                flip: stat(|r| r.flip),
                mse: stat(|r| r.mse),
                rel_mse,
                pixel_samples_per_second: stat(|r| r.pixel_samples_per_second),
                efficiency: 1.0 / (rel_mse.mean * seconds.mean).max(1e-300),
                efficiency_vs_plain: None,
                regions: runs[0]
                    .regions
                    .iter()
                    .enumerate()
                    .map(|(k, region)| RegionStat {
                        name: region.name.clone(),
                        rel_mse: Stat::of(&runs.iter().filter_map(|r| r.regions.get(k).map(|g| g.rel_mse)).collect::<Vec<_>>()),
                    })
                    .collect(),
            });
        }
    }
    let plain: Vec<(f64, f64)> = rows.iter().filter(|r| r.method == PLAIN).map(|r| (r.budget, r.efficiency)).collect();
    for row in &mut rows {
        row.efficiency_vs_plain = plain.iter().find(|(b, _)| *b == row.budget).map(|(_, e)| row.efficiency / e);
    }
    rows
}

/// A run's budget as a number: spp or seconds.
pub fn budget_of(r: &RunRecord) -> Option<f64> {
    r.budget_spp.map(|n| n as f64).or(r.budget_seconds)
}

/// A method's convergence.
#[derive(Debug, Clone, Serialize)]
pub struct Convergence {
    pub method: Method,
    pub biased: bool,
    /// relMSE against spp (equal-sample runs).
    pub vs_spp: Option<Fit>,
    /// relMSE against seconds (every run).
    pub vs_seconds: Option<Fit>,
    /// Predicted seconds and spp to reach the target relMSE.
    pub seconds_to_target: Option<f64>,
    pub spp_to_target: Option<f64>,
}

/// Fits every method's convergence and predicts when it reaches `target`.
pub fn convergence(records: &[RunRecord], methods: &[Method], target: f64) -> Vec<Convergence> {
    methods
        .iter()
        .map(|m| {
            let runs: Vec<&RunRecord> = records.iter().filter(|r| r.method == *m).collect();
            let vs_spp = Fit::log_log(
                &runs.iter().filter(|r| r.table == Table::EqualSamples).map(|r| (r.spp as f64, r.rel_mse)).collect::<Vec<_>>(),
            );
            let vs_seconds = Fit::log_log(&runs.iter().map(|r| (r.seconds, r.rel_mse)).collect::<Vec<_>>());
            Convergence {
                method: *m,
                biased: runs.first().is_some_and(|r| r.biased),
                seconds_to_target: vs_seconds.and_then(|f| f.solve(target)),
                spp_to_target: vs_spp.and_then(|f| f.solve(target)),
                vs_spp,
                vs_seconds,
            }
        })
        .collect()
}

/// The default target: the relMSE `plain` reaches at the largest spp budget (else the first
/// method's).
pub fn default_target(rows: &[Row]) -> Option<f64> {
    let largest = |m: Method| rows.iter().filter(|r| r.method == m).max_by(|a, b| a.budget.total_cmp(&b.budget)).map(|r| r.rel_mse.mean);
    largest(PLAIN).or_else(|| rows.first().and_then(|r| largest(r.method)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_is_mean_and_sample_deviation() {
        let s = Stat::of(&[1.0, 2.0, 3.0]);
        assert_eq!((s.mean, s.spread, s.n), (2.0, 1.0, 3));
    }
}
