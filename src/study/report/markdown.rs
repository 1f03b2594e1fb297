//! `report.md`: the tables, fits, verdicts and figures of one study, in Markdown.

use std::fmt::Write as _;

use crate::display::LOG10_RANGE;

use super::super::analysis::{Row, Stat};
use super::super::verdict::Verdict;
use super::super::{Reference, Study};
use super::Results;

fn pm(s: &Stat, digits: usize) -> String {
    if s.n > 1 { format!("{:.*} ± {:.*}", digits, s.mean, digits, s.spread) } else { format!("{:.*}", digits, s.mean) }
}

fn pm_sci(s: &Stat) -> String {
    if s.n > 1 { format!("{:.3e} ± {:.1e}", s.mean, s.spread) } else { format!("{:.3e}", s.mean) }
}

fn method_cell(name: &str, biased: bool) -> String {
    if biased { format!("{name} (biased demo)") } else { name.to_string() }
}

/// The report's text.
pub fn report(
    study: &Study,
    reference: &Reference,
    results: &Results,
    verdicts: &[Verdict],
    smallest: f64,
    target: Option<f64>,
    grid_spp: u64,
) -> String {
    let mut md = String::new();
    let w = &mut md;
    let _ = writeln!(w, "# pathlab study: {}\n", study.scene_path.display());
    let _ = writeln!(w, "```\n{}\n```\n", study.command);
    let _ = writeln!(
        w,
        "- {}x{}, max_depth {}, {} seeds per cell; display transform for PSNR/SSIM/FLIP: **{}**",
        results.width, results.height, results.max_depth, study.seeds, results.display
    );
    let _ = writeln!(w, "- machine: {} ({} cores, {}); adapter: {}", results.machine.cpu, results.machine.cores, results.machine.os, results.machine.adapter);
    let _ = writeln!(w, "- pathlab {}, {}; the study took {:.1} s", crate::VERSION, results.date_utc, results.study_seconds);
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
    if let Some(warn) = &results.reference.warning {
        let _ = writeln!(w, "\n**Warning:** {warn}.");
    }
    let _ = writeln!(w, "\n## Equal samples\n");
    let _ = writeln!(w, "| method | spp | PSNR (dB) | SSIM | FLIP | relMSE | MSE | seconds | M samples/s |");
    let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|");
    for r in &results.equal_samples {
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            method_cell(&r.method.name(), r.biased),
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
            method_cell(&r.method.name(), r.biased),
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
    region_table(w, &results.equal_time);
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
            method_cell(&c.method.name(), c.biased),
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
        super::super::verdict::STUDY_ALPHA
    );
    let _ = writeln!(w, "| method | verdict |");
    let _ = writeln!(w, "|---|---|");
    for v in verdicts {
        let _ = writeln!(w, "| {} | {} |", method_cell(&v.method.name(), v.biased_demonstration), v.text);
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
    md
}


/// The region table: every region's relMSE at the largest time budget for each method, and
/// which strategy wins there. Methods are grouped by how they use light sampling: BSDF
/// sampling only (`none`), light sampling only (`nee`, whose BSDF-sampled rays count no
/// emitter), and both (`mis`, `mis-balance`); each group is represented by its best method in
/// the region. The factor is the loser's relMSE over the winner's; "MIS vs better" is the best
/// MIS method's relMSE over the better single strategy's (below 1: MIS beats both).
fn region_table(w: &mut String, equal_time: &[Row]) {
    use crate::method::LightSampling as L;
    let Some(budget) = equal_time.iter().filter(|r| !r.regions.is_empty()).map(|r| r.budget).max_by(f64::total_cmp) else { return };
    let rows: Vec<&Row> = equal_time.iter().filter(|r| r.budget == budget && !r.biased).collect();
    let Some(first) = rows.first() else { return };
    let _ = writeln!(w, "\n## Regions (equal time, {budget} s)\n");
    let _ = writeln!(
        w,
        "relMSE in each region (mean over seeds), at the largest time budget. The last three columns compare the best method \
         of each kind of light sampling in the region: BSDF sampling only (lights `none`), light sampling only (`nee`), \
         and both (`mis`, `mis-balance`). The factor is the losing single strategy's relMSE over the winner's; MIS / better \
         is the best MIS method's relMSE over the better single strategy's (below 1: MIS beats both).\n"
    );
    let header: Vec<String> = rows.iter().map(|r| format!("`{}`", r.method.name())).collect();
    let _ = writeln!(w, "| region | {} | single-strategy winner | factor | MIS / better |", header.join(" | "));
    let _ = writeln!(w, "|---|{}---|---|---|", "---|".repeat(rows.len()));
    for (k, region) in first.regions.iter().enumerate() {
        let value = |r: &Row| r.regions.get(k).map_or(f64::NAN, |g| g.rel_mse.mean);
        let best_of = |kinds: &[L]| {
            rows.iter().filter(|r| kinds.contains(&r.method.lights)).map(|r| (value(r), r.method.name())).filter(|(v, _)| v.is_finite()).min_by(|a, b| a.0.total_cmp(&b.0))
        };
        let cells: Vec<String> = rows.iter().map(|r| format!("{:.3e}", value(r))).collect();
        let (bsdf, light, mis) = (best_of(&[L::None]), best_of(&[L::Nee]), best_of(&[L::Mis, L::MisBalance]));
        let (winner, factor, better) = match (&bsdf, &light) {
            (Some(b), Some(l)) if b.0 <= l.0 => (format!("BSDF sampling (`{}`)", b.1), format!("{:.1}x", l.0 / b.0), Some(b.0)),
            (Some(b), Some(l)) => (format!("light sampling (`{}`)", l.1), format!("{:.1}x", b.0 / l.0), Some(l.0)),
            (Some(b), None) => (format!("`{}` (no light-only method)", b.1), "-".into(), Some(b.0)),
            (None, Some(l)) => (format!("`{}` (no BSDF-only method)", l.1), "-".into(), Some(l.0)),
            (None, None) => ("-".into(), "-".into(), None),
        };
        let mis_vs = match (mis, better) {
            (Some(m), Some(b)) => format!("{:.2} (`{}`)", m.0 / b, m.1),
            _ => "-".into(),
        };
        let _ = writeln!(w, "| {} | {} | {winner} | {factor} | {mis_vs} |", region.name, cells.join(" | "));
    }
}
