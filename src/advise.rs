//! `pathlab advise`: which method reaches a target error first, and how long it takes.
//!
//! Each method runs a short pilot (a `RenderJob` whose error plan has no target) that records its
//! estimated error (no reference needed, see `estimate`) as it renders. The error of a Monte
//! Carlo render falls as a power of the samples, error = a N^b: b = -1 exactly for independent
//! samples (the variance of their mean is sigma^2 / N); for randomised QMC the slope of a
//! least-squares fit of log error against log spp over the pilot's second half (early on,
//! dispatches are still growing), held within [`QMC_SLOPE_LIMIT`, -1]. Drawn through the pilot's last check,
//! it gives the spp the target needs, and the pilot's steady throughput (second half) the time.
//! The range spans that and the pilot's own fitted slope (held within `SLOPE_RANGE`): wide where
//! the pilot's estimates are still noisy.

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use serde::Serialize;

use crate::display::DisplayTransform;
use crate::estimate::target::Target;
use crate::estimate::{ErrorEstimate, Estimator};
use crate::gpu::{Gpu, PathTracerPipelines};
use crate::method::{Method, Preset};
use crate::render::{warm_up, Budget, CheckpointError, ErrorPlan, RenderJob};
use crate::scene::Scene;
use crate::stats::Fit;

/// The pilot's checks before this share of its time are not fitted.
const SKIP_SHARE: f64 = 0.5;
/// Slopes the prediction uses, whatever the pilot's fit: path-tracing integrands are
/// discontinuous, so randomised QMC converges at best about as N^-1.5 (Owen scrambling's rate
/// for non-smooth integrands is well below its smooth N^-3); a steeper pilot slope is noise, and
/// one shallower than -0.5 means the error has not started to fall.
pub const SLOPE_RANGE: (f64, f64) = (-1.5, -0.5);
/// The steepest slope a randomised-QMC prediction uses: the study scene's measured slopes
/// against spp were -1.14 (Halton) and -1.27 (Owen-scrambled Sobol', `best`); a pilot's few
/// noisy randomisations can claim much more (-1.8 for Halton).
pub const QMC_SLOPE_LIMIT: f64 = -1.3;
/// Checks per pilot.
const PILOT_CHECKS: f64 = 12.0;

/// One method's pilot and prediction.
#[derive(Debug, Clone, Serialize)]
pub struct Advice {
    pub method: Method,
    pub estimator: String,
    /// Pilot: seconds rendered, spp reached, pixel samples per second.
    pub pilot_seconds: f64,
    pub pilot_spp: u64,
    pub pixel_samples_per_second: f64,
    /// The error measure at the pilot's end (relMSE, or the display MSE for a PSNR target).
    pub pilot_error: f64,
    /// Fitted slope of log error against log seconds.
    pub slope: Option<f64>,
    /// Predicted seconds to the target, and its range; `None` when the pilot cannot tell
    /// (error not falling, or the target beyond 100x the pilot's time).
    pub predicted_seconds: Option<f64>,
    pub range: Option<(f64, f64)>,
    pub predicted_spp: Option<f64>,
    /// plain's predicted seconds / this method's (when plain was piloted).
    pub speedup_vs_plain: Option<f64>,
}

/// The error measure a target is met on: relMSE, or the display MSE (10^(-PSNR/10)).
pub fn error_of(target: Target, e: &ErrorEstimate) -> f64 {
    match target {
        Target::RelMse(_) => e.rel_mse,
        Target::Psnr(_) => e.psnr.map_or(f64::INFINITY, |p| 10f64.powf(-p / 10.0)),
    }
}

/// The target as an error measure.
pub fn target_error(target: Target) -> f64 {
    match target {
        Target::RelMse(e) => e,
        Target::Psnr(db) => 10f64.powf(-db / 10.0),
    }
}

/// Pilots every method for `pilot` seconds and predicts the time to `target`; sorted by the
/// predicted time, fastest first (methods without a prediction last).
pub fn advise(
    gpu: &Gpu,
    pipelines: &PathTracerPipelines,
    scene: &Scene,
    methods: &[Method],
    target: Target,
    display: &DisplayTransform,
    pilot: Duration,
    cancel: &AtomicBool,
) -> Result<Vec<Advice>, CheckpointError> {
    let pixels = scene.render.width as f64 * scene.render.height as f64;
    let goal = target_error(target);
    let mut advice = Vec::new();
    for method in methods {
        warm_up(gpu, pipelines, scene, *method)?;
        // About 12 checks per pilot (their time is not counted as rendering time).
        let every = pilot.div_f64(PILOT_CHECKS);
        let mut job = RenderJob::new(scene.clone(), scene.path.clone(), *method, 1, Budget::Time(pilot));
        job.error = Some(ErrorPlan { target: None, every: Some(every), display: *display, check_pixels: None });
        let outcome = job.run(gpu, pipelines, cancel, |_| {})?;
        let run = outcome.error.as_ref().expect("a job with an error plan tracks its error");
        let seconds = outcome.stats.seconds - run.check_seconds;
        // The pilot's second half: dispatches have grown to their steady size.
        let late: Vec<&(f64, u64, ErrorEstimate)> = run.history.iter().filter(|(t, _, _)| *t >= SKIP_SHARE * seconds).collect();
        let fit = Fit::log_log(&late.iter().map(|(_, n, e)| (*n as f64, error_of(target, e))).collect::<Vec<_>>());
        let last = error_of(target, &run.estimate);
        let spp = outcome.film.spp as f64;
        // Steady throughput over the second half (spp per second), else over the whole pilot.
        let steady = match (late.first(), late.last()) {
            (Some(a), Some(b)) if b.0 > a.0 && b.1 > a.1 => (b.1 - a.1) as f64 / (b.0 - a.0),
            _ => spp / seconds.max(1e-9),
        };
        let estimator = Estimator::for_sampler(method.sampler);
        // error = last (n / spp)^b through the last check: spp needed for the goal at slope b.
        let spp_for = |b: f64| (last.is_finite() && last > 0.0).then(|| spp * (goal / last).powf(1.0 / b));
        let slope = match estimator {
            // The variance of a mean of independent samples is exactly sigma^2 / N.
            Estimator::WithinPixel => -1.0,
            // Randomised QMC: the pilot's slope, held within what path tracing allows.
            Estimator::Randomisations(_) => fit.map_or(-1.0, |f| f.slope.clamp(QMC_SLOPE_LIMIT, -1.0)),
        };
        let predicted_spp = spp_for(slope);
        // Seconds for n spp: within the pilot at its average throughput, beyond it at the steady one.
        let time_for = |n: f64| if n <= spp { seconds * n / spp.max(1.0) } else { seconds + (n - spp) / steady };
        let predicted = predicted_spp.map(time_for);
        let alternative = fit.and_then(|f| spp_for(f.slope.clamp(SLOPE_RANGE.0, SLOPE_RANGE.1))).map(time_for);
        let range = predicted.map(|p| {
            let a = alternative.unwrap_or(p);
            (p.min(a), p.max(a))
        });
        advice.push(Advice {
            method: *method,
            estimator: estimator.describe(),
            pilot_seconds: seconds,
            pilot_spp: outcome.film.spp,
            pixel_samples_per_second: steady * pixels,
            pilot_error: last,
            slope: fit.map(|f| f.slope),
            predicted_seconds: predicted,
            range,
            predicted_spp,
            speedup_vs_plain: None,
        });
        if outcome.stats.interrupted {
            break;
        }
    }
    let plain = advice.iter().find(|a| a.method == Preset::Plain.method()).and_then(|a| a.predicted_seconds);
    for a in &mut advice {
        a.speedup_vs_plain = plain.zip(a.predicted_seconds).map(|(p, t)| p / t);
    }
    advice.sort_by(|a, b| match (a.predicted_seconds, b.predicted_seconds) {
        (Some(x), Some(y)) => x.total_cmp(&y),
        (Some(_), None) => std::cmp::Ordering::Less,
        (None, Some(_)) => std::cmp::Ordering::Greater,
        (None, None) => std::cmp::Ordering::Equal,
    });
    Ok(advice)
}
