//! The error estimate without a reference (`pathlab::estimate`) is calibrated: on the study
//! scene, for every preset and every sampler, the estimated relMSE averaged over seeds agrees
//! with the true relMSE against a converged reference within a stated factor; the wrong
//! estimator for a low-discrepancy sampler (its within-pixel variance) fails that check; and
//! `render --target-rel-error` stops at the target with a true error at or below it (within the
//! same factor).

use crate::common;

use common::*;
use pathlab::render::to_target::render_randomised;
use pathlab::estimate::{estimate_films, within_pixel, Estimator};
use pathlab::method::{Method, Preset, Sampler};
use pathlab::metrics::rel_mse;
use pathlab::film::Film;

/// Estimated / true relMSE must lie in [1 / FACTOR, FACTOR] (averaged over SEEDS).
const FACTOR: f64 = 1.25;
const SEEDS: u32 = 4;
const SPP: u64 = 256;

fn scene() -> pathlab::scene::Scene {
    let mut s = study_scene();
    s.render.width = 64;
    s.render.height = 32;
    s
}

fn methods() -> Vec<(String, Method)> {
    let mut m: Vec<(String, Method)> = Preset::ALL.iter().map(|p| (p.name().to_string(), p.method())).collect();
    for sampler in [Sampler::Halton, Sampler::HaltonScrambled] {
        m.push((format!("mis+{}", sampler.name()), Method { sampler, ..Preset::Mis.method() }));
    }
    m
}

fn reference(scene: &pathlab::scene::Scene) -> Film {
    render(scene, Preset::Best.method(), 1 << 16, 999)
}

#[test]
fn estimated_rel_mse_agrees_with_the_true_one() {
    let scene = scene();
    let reference = reference(&scene);
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for (name, method) in methods() {
        let estimator = Estimator::for_sampler(method.sampler);
        let (mut est, mut truth, mut naive) = (0.0, 0.0, 0.0);
        for seed in 1..=SEEDS {
            let films = render_randomised(gpu(), pipelines(), &scene, method, seed * 7919, SPP, estimator).unwrap();
            let (film, e) = estimate_films(estimator, &films, None);
            est += e.rel_mse;
            truth += rel_mse(&film, &reference);
            naive += within_pixel(&film, None).rel_mse;
        }
        let ratio = est / truth;
        report.push(format!(
            "{name:<22} {:<42} true relMSE {:.3e}  estimate/true {ratio:.3}  within-pixel/true {:.3}",
            estimator.describe(),
            truth / SEEDS as f64,
            naive / truth
        ));
        if !(1.0 / FACTOR..=FACTOR).contains(&ratio) {
            failures.push(format!("{name}: estimate/true = {ratio:.3}"));
        }
        // The wrong estimator for a low-discrepancy sampler is caught by the same check.
        if name == "best" && (1.0 / FACTOR..=FACTOR).contains(&(naive / truth)) {
            failures.push(format!("best: the within-pixel estimate ({:.3}) was not caught", naive / truth));
        }
    }
    println!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{failures:?}\n{}", report.join("\n"));
}

/// `render --target-rel-error E`: stops with the estimate at or below E, the true relMSE within
/// the calibration factor of E, the header recording target and estimate. (How far below E it
/// lands depends on the check interval, a wall time: not asserted.)
#[test]
fn render_to_a_target_rel_error_stops_there() {
    let scene = scene();
    let reference = reference(&scene);
    let dir = tempfile::tempdir().unwrap();
    for (method, target) in [("mis", 5e-5), ("best", 2e-5)] {
        let out = dir.path().join(format!("{method}.exr"));
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_pathlab"))
            .arg("render")
            .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/study.toml"))
            .args(["--width", "64", "--height", "32", "--method", method, "--target-rel-error", &target.to_string(), "--quiet", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{stderr}");
        let (film, metadata) = pathlab::output::read_exr(&out).unwrap();
        let meta = |k: &str| metadata.iter().find(|(key, _)| key == k).map(|(_, v)| v.clone()).unwrap_or_else(|| panic!("{k}"));
        let estimate: f64 = meta("estimated_rel_mse").parse().unwrap();
        let truth = rel_mse(&film, &reference);
        println!("{method}: target {target:.1e}, {} spp, estimate {estimate:.3e}, true {truth:.3e} ({stderr})", film.spp);
        assert_eq!(meta("target_reached"), "true");
        assert_eq!(meta("target_rel_mse").parse::<f64>().unwrap(), target);
        assert!(estimate <= target, "{method}: estimate {estimate:.3e} for target {target:.1e}");
        assert!(truth <= target * FACTOR, "{method}: true relMSE {truth:.3e} above target {target:.1e} x {FACTOR}");
    }
}
