//! `convergence.csv`: one row per run, the points behind the plots.

use std::fmt::Write as _;
use std::path::Path;

use crate::output::OutputError;

use super::super::runs::RunRecord;
use super::write_text;

pub fn write(path: &Path, records: &[RunRecord]) -> Result<(), OutputError> {
    let mut csv = String::from("table,method,biased,seed,budget,spp,seconds,rel_mse,mse,psnr,ssim,flip\n");
    for r in records {
        let budget = r.budget_spp.map(|n| n as f64).or(r.budget_seconds).unwrap_or(0.0);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{:.6},{:.6e},{:.6e},{:.4},{:.5},{:.5}",
            r.table.name(),
            r.method.name(),
            r.biased,
            r.seed,
            budget,
            r.spp,
            r.seconds,
            r.rel_mse,
            r.mse,
            r.psnr,
            r.ssim,
            r.flip
        );
    }
    write_text(path, &csv)

}
