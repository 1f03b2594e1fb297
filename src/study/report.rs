//! The study's outputs: `results.json` (every number), `convergence.csv` (the points behind the
//! plots), `relmse_vs_spp.png` and `relmse_vs_seconds.png`, `grid.png`, and `report.md` tying
//! them together. All written atomically.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::figures::error_map::{false_colour, LOG10_RANGE};
use crate::figures::grid::{grid, Tile};
use crate::figures::plot::{write_log_log, Series};
use crate::gpu::{adapter_summary, Gpu};
use crate::metrics::{psnr, rel_mse_map, ssim};
use crate::output::{read_exr, write_atomically, write_rgb8_png, OutputError};

use super::analysis::{convergence, default_target, rows, Convergence, Row};
use super::runs::{image_path, RunRecord, Table};
use super::verdict::Verdict;
use super::{Reference, Study, StudyError};

/// The reference's own error is "not negligible" above this share of the smallest relMSE
/// measured against it.
pub const REFERENCE_WARNING_SHARE: f64 = 0.1;

#[derive(Serialize)]
struct ReferenceInfo {
    description: String,
    spp: u64,
    render_seconds: Option<f64>,
    expected_rel_mse: Option<f64>,
    warning: Option<String>,
}

#[derive(Serialize)]
struct Machine {
    cpu: String,
    cores: usize,
    os: String,
    adapter: String,
}

#[derive(Serialize)]
struct Results<'a> {
    pathlab_version: &'static str,
    command: &'a str,
    date_utc: String,
    scene: String,
    scene_hash: String,
    width: u32,
    height: u32,
    max_depth: u32,
    display: String,
    seeds: u32,
    machine: Machine,
    reference: ReferenceInfo,
    target_rel_mse: Option<f64>,
    equal_samples: Vec<Row>,
    equal_time: Vec<Row>,
    convergence: Vec<Convergence>,
    verdicts: &'a [Verdict],
    runs: &'a [RunRecord],
    study_seconds: f64,
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| s.lines().find(|l| l.starts_with("model name")).and_then(|l| l.split(':').nth(1)).map(|m| m.trim().to_string()))
        .unwrap_or_else(|| std::env::consts::ARCH.to_string())
}

/// Today's date (UTC) as YYYY-MM-DD, from the system clock (civil-from-days, H. Hinnant).
fn today_utc() -> String {
    let secs = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs()) as i64;
    let z = secs.div_euclid(86_400) + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + (m <= 2) as i64;
    format!("{y:04}-{m:02}-{d:02}")
}

fn write_text(path: &Path, text: &str) -> Result<(), OutputError> {
    write_atomically(path, |w| std::io::Write::write_all(w, text.as_bytes()).map_err(|e| e.to_string()))
}

fn pm(s: &super::analysis::Stat, digits: usize) -> String {
    if s.n > 1 { format!("{:.*} ± {:.*}", digits, s.mean, digits, s.spread) } else { format!("{:.*}", digits, s.mean) }
}

fn pm_sci(s: &super::analysis::Stat) -> String {
    if s.n > 1 { format!("{:.3e} ± {:.1e}", s.mean, s.spread) } else { format!("{:.3e}", s.mean) }
}

fn method_cell(name: &str, biased: bool) -> String {
    if biased { format!("{name} (biased demo)") } else { name.to_string() }
}

/// Writes every output; returns the report's path.
pub fn write(
    study: &Study,
    reference: &Reference,
    records: &[RunRecord],
    verdicts: &[Verdict],
    gpu: &Gpu,
    study_seconds: f64,
) -> Result<PathBuf, StudyError> {
    let dir = &study.out;
    let methods: Vec<String> = study.methods.iter().map(|m| m.name.clone()).collect();
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
        eprintln!("warning: {w}");
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

    // The points behind the plots.
    let mut csv = String::from("table,method,biased,seed,budget,spp,seconds,rel_mse,mse,psnr,ssim,flip\n");
    for r in records {
        let budget = r.budget_spp.map(|n| n as f64).or(r.budget_seconds).unwrap_or(0.0);
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{:.6},{:.6e},{:.6e},{:.4},{:.5},{:.5}",
            r.table.name(),
            r.method,
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
    write_text(&dir.join("convergence.csv"), &csv)?;

    let series = |x: fn(&RunRecord) -> f64, only: Option<Table>, fit: fn(&Convergence) -> Option<super::analysis::Fit>| -> Vec<Series> {
        methods
            .iter()
            .zip(&results.convergence)
            .map(|(m, c)| Series {
                name: m.clone(),
                points: records.iter().filter(|r| &r.method == m && only.is_none_or(|t| r.table == t)).map(|r| (x(r), r.rel_mse)).collect(),
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
    )?;

    let grid_spp = write_grid(study, reference)?;

    // report.md
    let mut md = String::new();
    let w = &mut md;
    let _ = writeln!(w, "# pathlab study: {}\n", study.scene_path.display());
    let _ = writeln!(w, "```\n{}\n```\n", study.command);
    let _ = writeln!(
        w,
        "- {}x{}, max_depth {}, {} seeds per cell; display transform for PSNR/SSIM/FLIP: **{}**",
        results.width, results.height, results.max_depth, study.seeds, results.display
    );
    let _ = writeln!(w, "- machine: {} ({} cores, {}); adapter: {}", results.machine.cpu, results.machine.cores, results.machine.os, adapter);
    let _ = writeln!(w, "- pathlab {}, {}; the study took {:.1} s", crate::VERSION, results.date_utc, study_seconds);
    let _ = writeln!(w, "- relMSE = mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01), on linear radiance\n");
    let _ = writeln!(w, "## Reference\n");
    let _ = writeln!(w, "{}", reference.description);
    if let Some(s) = reference.render_seconds {
        let _ = writeln!(w, "; rendered in {s:.1} s");
    }
    if let Some(e) = reference.expected_rel_mse {
        let _ = writeln!(
            w,
            "\nIts own expected relMSE (from its per-pixel variance): {e:.3e}, against a smallest measured relMSE of {smallest:.3e} ({:.2}%).",
            100.0 * e / smallest
        );
    }
    if let Some(warn) = &warning {
        let _ = writeln!(w, "\n**Warning:** {warn}.");
    }
    let _ = writeln!(w, "\n## Equal samples\n");
    let _ = writeln!(w, "| method | spp | PSNR (dB) | SSIM | FLIP | relMSE | MSE | seconds | M samples/s |");
    let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|");
    for r in &results.equal_samples {
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            method_cell(&r.method, r.biased),
            r.budget,
            pm(&r.psnr, 2),
            pm(&r.ssim, 3),
            pm(&r.flip, 3),
            pm_sci(&r.rel_mse),
            pm_sci(&r.mse),
            pm(&r.seconds, 3),
            r.pixel_samples_per_second.mean / 1e6
        );
    }
    let _ = writeln!(w, "\n## Equal time\n");
    let _ = writeln!(w, "Efficiency = 1 / (relMSE x seconds); the last column is its ratio to `plain` at the same budget.\n");
    let _ = writeln!(w, "| method | seconds | spp reached | PSNR (dB) | SSIM | FLIP | relMSE | efficiency | vs plain |");
    let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|");
    for r in &results.equal_time {
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} | {} | {:.3e} | {} |",
            method_cell(&r.method, r.biased),
            r.budget,
            pm(&r.spp, 0),
            pm(&r.psnr, 2),
            pm(&r.ssim, 3),
            pm(&r.flip, 3),
            pm_sci(&r.rel_mse),
            r.efficiency,
            r.efficiency_vs_plain.map_or("-".to_string(), |e| format!("{e:.2}x"))
        );
    }
    let _ = writeln!(w, "\n## Convergence\n");
    let _ = writeln!(
        w,
        "Least-squares fits of log relMSE against log spp and log seconds over every run (slope -1 is plain Monte Carlo's rate). \
         Target relMSE: {} ({}).\n",
        target.map_or("-".into(), |t| format!("{t:.3e}")),
        if study.target.is_some() { "--target" } else { "what `plain` reaches at the largest spp" }
    );
    let _ = writeln!(w, "| method | slope vs spp | slope vs seconds | R² (seconds) | seconds to target | spp to target |");
    let _ = writeln!(w, "|---|---|---|---|---|---|");
    for c in &results.convergence {
        let f = |x: Option<f64>, d: usize| x.map_or("-".to_string(), |v| format!("{v:.*}", d));
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} |",
            method_cell(&c.method, c.biased),
            f(c.vs_spp.map(|f| f.slope), 3),
            f(c.vs_seconds.map(|f| f.slope), 3),
            f(c.vs_seconds.map(|f| f.r2), 3),
            f(c.seconds_to_target, 3),
            f(c.spp_to_target, 0)
        );
    }
    let _ = writeln!(w, "\n![relMSE against spp](relmse_vs_spp.png)\n\n![relMSE against seconds](relmse_vs_seconds.png)\n");
    let _ = writeln!(w, "## Bias verdicts\n");
    let _ = writeln!(
        w,
        "At {} spp x {} seeds against the reference; a whole study wrongly flags an unbiased method with probability below {} \
         (image-mean bias z-test and per-pixel or per-block z-test, Šidák-corrected over methods).\n",
        study.spp.iter().max().unwrap_or(&0),
        study.seeds,
        super::verdict::STUDY_ALPHA
    );
    let _ = writeln!(w, "| method | verdict |");
    let _ = writeln!(w, "|---|---|");
    for v in verdicts {
        let _ = writeln!(w, "| {} | {} |", method_cell(&v.method, v.biased_demonstration), v.text);
    }
    let _ = writeln!(
        w,
        "\n## Image grid\n\nSeed 1 at every spp, the reference, and the relative squared error at {grid_spp} spp (magma, log scale 1e{} to 1e{}).\n\n![grid](grid.png)\n",
        LOG10_RANGE.0, LOG10_RANGE.1
    );
    let _ = writeln!(
        w,
        "## Files\n\n`results.json` (every number; run records join `pathlab bench --json` on scene, method, width, height, max_depth), \
         `convergence.csv`, `runs/*.json`, `images/*.exr`, `reference.exr`."
    );
    let path = dir.join("report.md");
    write_text(&path, &md)?;
    Ok(path)
}

/// The image grid; returns the spp of its error-map column.
fn write_grid(study: &Study, reference: &Reference) -> Result<u64, StudyError> {
    let dir = &study.out;
    let mut spps = study.spp.clone();
    spps.sort_unstable();
    spps.dedup();
    // The error-map column shows the budget nearest the study's 10 spp.
    let error_spp = *spps.iter().min_by_key(|&&n| (n as i64 - 10).unsigned_abs()).unwrap_or(&1);
    let display = study.display;
    let ref_display = display.film(&reference.film);
    let mut headers: Vec<String> = spps.iter().map(|n| format!("{n} spp")).collect();
    headers.push("reference".into());
    headers.push(format!("rel. error, {error_spp} spp"));
    let mut rows = Vec::new();
    for m in &study.methods {
        let mut tiles = Vec::new();
        let mut error_tile = None;
        for &n in &spps {
            let film = read_exr(&image_path(dir, &m.name, n, 1)).ok().map(|(f, _)| f);
            tiles.push(film.as_ref().map(|f| {
                let img = display.film(f);
                Tile {
                    width: f.width,
                    height: f.height,
                    rgb: img.to_rgb8(),
                    label: vec![format!("{} {n} spp", m.name), format!("{:.2} dB / SSIM {:.3}", psnr(&ref_display, &img), ssim(&ref_display, &img))],
                }
            }));
            if n == error_spp {
                error_tile = film.map(|f| Tile {
                    width: f.width,
                    height: f.height,
                    rgb: false_colour(&rel_mse_map(&f, &reference.film)),
                    label: vec![format!("relMSE {:.2e}", crate::metrics::rel_mse(&f, &reference.film))],
                });
            }
        }
        tiles.push(Some(Tile {
            width: reference.film.width,
            height: reference.film.height,
            rgb: ref_display.to_rgb8(),
            label: vec![format!("reference {} spp", reference.film.spp)],
        }));
        tiles.push(error_tile);
        rows.push((if m.biased { format!("{}\n(biased demo)", m.name) } else { m.name.clone() }, tiles));
    }
    let title = format!("{} ({}), display {}", study.scene_path.display(), study.scene.content_hash(), display);
    let canvas = grid(&title, &headers, rows);
    write_rgb8_png(&dir.join("grid.png"), canvas.width, canvas.height, canvas.pixels)?;
    Ok(error_spp)
}
