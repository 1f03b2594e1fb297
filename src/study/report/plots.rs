//! `relmse_vs_spp.png` and `relmse_vs_seconds.png`: every run and each method's fit, log-log.

use std::path::Path;

use crate::figures::plot::{write_log_log, Series};
use crate::method::Method;
use crate::output::OutputError;
use crate::stats::Fit;

use super::super::analysis::Convergence;
use super::super::runs::{RunRecord, Table};

pub fn write(dir: &Path, methods: &[Method], records: &[RunRecord], convergence: &[Convergence]) -> Result<(), OutputError> {
    let series = |x: fn(&RunRecord) -> f64, only: Option<Table>, fit: fn(&Convergence) -> Option<Fit>| -> Vec<Series> {
        methods
            .iter()
            .zip(convergence)
            .map(|(m, c)| Series {
                name: m.name(),
                points: records.iter().filter(|r| r.method == *m && only.is_none_or(|t| r.table == t)).map(|r| (x(r), r.rel_mse)).collect(),
                fit: fit(c).map(|f| (f.slope, f.intercept)),
            })
            .collect()
    };
    write_log_log(
        &dir.join("relmse_vs_spp.png"),
        "relMSE against samples per pixel (equal-sample runs)",
        "samples per pixel",
        "relMSE",
        &series(|r| r.spp as f64, Some(Table::EqualSamples), |c| c.vs_spp),
    )?;
    write_log_log(
        &dir.join("relmse_vs_seconds.png"),
        "relMSE against render time (every run)",
        "seconds",
        "relMSE",
        &series(|r| r.seconds, None, |c| c.vs_seconds),
    )
}
