//! From run records to answers: the equal-sample and equal-time tables (mean and spread over
//! seeds), efficiency 1 / (relMSE x seconds) and its ratio to `plain`, and the convergence fits
//! log relMSE = a + b log(spp) and a + b log(seconds) (least squares over every run; b = -1 for
//! plain Monte Carlo), with the time and spp each method needs to reach a target relMSE.

use serde::Serialize;

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
    pub method: String,
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
}

/// The rows of `table`, in method order, then budget order.
pub fn rows(records: &[RunRecord], table: Table, methods: &[String], budgets: &[f64]) -> Vec<Row> {
    let mut rows = Vec::new();
    for method in methods {
        for &budget in budgets {
            let runs: Vec<&RunRecord> = records
                .iter()
                .filter(|r| r.table == table && &r.method == method && budget_of(r) == Some(budget))
                .collect();
            if runs.is_empty() {
                continue;
            }
            let stat = |f: fn(&RunRecord) -> f64| Stat::of(&runs.iter().map(|r| f(r)).collect::<Vec<_>>());
            let rel_mse = stat(|r| r.rel_mse);
            let seconds = stat(|r| r.seconds);
            rows.push(Row {
                method: method.clone(),
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
            });
        }
    }
    let plain: Vec<(f64, f64)> = rows.iter().filter(|r| r.method == "plain").map(|r| (r.budget, r.efficiency)).collect();
    for row in &mut rows {
        row.efficiency_vs_plain = plain.iter().find(|(b, _)| *b == row.budget).map(|(_, e)| row.efficiency / e);
    }
    rows
}

/// A run's budget as a number: spp or seconds.
pub fn budget_of(r: &RunRecord) -> Option<f64> {
    r.budget_spp.map(|n| n as f64).or(r.budget_seconds)
}

/// log relMSE = intercept + slope log x (natural logs), least squares.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Fit {
    pub slope: f64,
    pub intercept: f64,
    /// Coefficient of determination.
    pub r2: f64,
    pub points: usize,
    /// Largest x fitted.
    pub x_max: f64,
}

/// `Fit::solve` extrapolates at most this factor beyond the largest x measured.
pub const MAX_EXTRAPOLATION: f64 = 100.0;

impl Fit {
    /// Least squares through (ln x, ln y) of the positive points; `None` with fewer than two
    /// distinct x.
    pub fn log_log(points: &[(f64, f64)]) -> Option<Fit> {
        let pts: Vec<(f64, f64)> = points.iter().filter(|(x, y)| *x > 0.0 && *y > 0.0).map(|(x, y)| (x.ln(), y.ln())).collect();
        let n = pts.len() as f64;
        let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
        let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
        let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
        let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
        let syy: f64 = pts.iter().map(|p| (p.1 - my).powi(2)).sum();
        if pts.len() < 2 || sxx <= 1e-12 {
            return None;
        }
        let slope = sxy / sxx;
        let r2 = if syy > 0.0 { (sxy * sxy) / (sxx * syy) } else { 1.0 };
        let x_max = pts.iter().map(|p| p.0).fold(f64::MIN, f64::max).exp();
        Some(Fit { slope, intercept: my - slope * mx, r2, points: pts.len(), x_max })
    }

    /// The fitted relMSE at x.
    pub fn at(&self, x: f64) -> f64 {
        (self.intercept + self.slope * x.ln()).exp()
    }

    /// The x at which the fit reaches `target`: only for decreasing fits, and only up to
    /// `MAX_EXTRAPOLATION` times the largest x measured (beyond, the fit says nothing).
    pub fn solve(&self, target: f64) -> Option<f64> {
        if !(self.slope < 0.0 && target > 0.0) {
            return None;
        }
        let x = ((target.ln() - self.intercept) / self.slope).exp();
        (x <= MAX_EXTRAPOLATION * self.x_max).then_some(x)
    }
}

/// A method's convergence.
#[derive(Debug, Clone, Serialize)]
pub struct Convergence {
    pub method: String,
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
pub fn convergence(records: &[RunRecord], methods: &[String], target: f64) -> Vec<Convergence> {
    methods
        .iter()
        .map(|m| {
            let runs: Vec<&RunRecord> = records.iter().filter(|r| &r.method == m).collect();
            let vs_spp = Fit::log_log(
                &runs.iter().filter(|r| r.table == Table::EqualSamples).map(|r| (r.spp as f64, r.rel_mse)).collect::<Vec<_>>(),
            );
            let vs_seconds = Fit::log_log(&runs.iter().map(|r| (r.seconds, r.rel_mse)).collect::<Vec<_>>());
            Convergence {
                method: m.clone(),
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
    let largest = |m: &str| rows.iter().filter(|r| r.method == m).max_by(|a, b| a.budget.total_cmp(&b.budget)).map(|r| r.rel_mse.mean);
    largest("plain").or_else(|| rows.first().and_then(|r| largest(&r.method)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_log_fit_recovers_a_power_law() {
        let pts: Vec<(f64, f64)> = [1.0, 4.0, 16.0, 64.0].iter().map(|&x| (x, 2.0 * f64::powf(x, -1.0))).collect();
        let f = Fit::log_log(&pts).unwrap();
        assert!((f.slope + 1.0).abs() < 1e-12 && (f.intercept - 2f64.ln()).abs() < 1e-12 && (f.r2 - 1.0).abs() < 1e-12);
        assert!((f.solve(0.02).unwrap() - 100.0).abs() < 1e-9);
        // Beyond 100x the largest x measured (64), no prediction.
        assert!(f.solve(2.0 / 6399.0).is_some() && f.solve(2.0 / 6500.0).is_none());
        assert!((f.at(8.0) - 0.25).abs() < 1e-12);
        assert!(Fit::log_log(&[(1.0, 1.0)]).is_none());
    }

    #[test]
    fn stat_is_mean_and_sample_deviation() {
        let s = Stat::of(&[1.0, 2.0, 3.0]);
        assert_eq!((s.mean, s.spread, s.n), (2.0, 1.0, 3));
    }
}
