//! Rendering until the estimated error reaches a target (`render --target-rel-error E` or
//! `--target-psnr DB`), with a sample count or a time as the upper bound; without a target, a
//! pilot that records its estimates (`advise`).
//!
//! The render advances in rounds (every randomisation gets the same samples per round, about a
//! quarter of a second in all on GPUs, a dispatch's length each on CPU adapters: `batch::round_aim`;
//! sized by `controller::SampleCount`); the estimate needs a
//! readback of every accumulator, so it is checked only once `CHECK_COST_FACTOR` times its own
//! measured cost has passed since the last check (at least `MIN_CHECK_INTERVAL`): checking
//! costs at most about 2% of the render.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::display::DisplayTransform;
use crate::estimate::target::Target;
use crate::estimate::{estimate_films, ErrorEstimate, Estimator};
use crate::film::Film;
use crate::gpu::{Gpu, PathTracerPipelines};
use crate::method::Method;
use crate::scene::Scene;

use super::controller::SampleCount;
use super::{Budget, Progress, RenderError, Renderer, MAX_SPP};

/// A check waits at least this many times its own cost: checking stays under ~2% of the time.
pub const CHECK_COST_FACTOR: f64 = 50.0;
/// Checks during the render estimate from evenly spaced rows holding about this many pixels
/// (an unbiased sample of the image's mean error, at a fraction of a full readback); the final
/// estimate uses every pixel.
pub const CHECK_PIXELS: u32 = 32_768;
pub const MIN_CHECK_INTERVAL: Duration = Duration::from_millis(250);

/// The result.
#[derive(Debug, Clone)]
pub struct TargetOutcome {
    pub film: Film,
    pub rays: u64,
    /// Samples in which a researcher's technique faulted (each contributed 0).
    pub faults: u64,
    pub seconds: f64,
    pub estimate: ErrorEstimate,
    pub estimator: Estimator,
    pub reached: bool,
    pub interrupted: bool,
    /// Estimates made along the way, and the wall time they took.
    pub checks: u32,
    pub check_seconds: f64,
    /// Every check: (seconds of rendering so far, spp, estimate).
    pub history: Vec<(f64, u64, ErrorEstimate)>,
}

/// Seed of randomisation `r` (r = 0 keeps `seed`).
pub fn randomisation_seed(seed: u32, r: u32) -> u32 {
    seed.wrapping_add(r.wrapping_mul(0x9E37_79B9))
}

/// Renders `scene` with `method` until `target` is met (never, for `None`: a pilot that only
/// records its estimates), `max_spp` samples per pixel (all randomisations together) or
/// `max_time` is spent, or `cancel` is set. Checks come every `check_every`, or (`None`) as the
/// check cost allows (see `CHECK_COST_FACTOR`), each from about `check_pixels` pixels in evenly
/// spaced rows, and the target is confirmed on every pixel before the render stops.
#[allow(clippy::too_many_arguments)]
pub fn render_to_target(
    gpu: &Gpu,
    pipelines: &PathTracerPipelines,
    scene: &Scene,
    method: Method,
    seed: u32,
    target: Option<Target>,
    display: &DisplayTransform,
    max_spp: Option<u64>,
    max_time: Option<Duration>,
    check_every: Option<Duration>,
    check_pixels: u32,
    cancel: &AtomicBool,
    mut progress: impl FnMut(Progress),
) -> Result<TargetOutcome, RenderError> {
    let estimator = Estimator::for_sampler(method.sampler);
    let r = estimator.renders() as u64;
    let mut renderers = randomised_renderers(gpu, pipelines, scene, method, seed, estimator)?;
    let max_spp = max_spp.unwrap_or(MAX_SPP).min(MAX_SPP);
    let never = AtomicBool::new(false);
    let start = Instant::now();
    let (mut checks, mut check_seconds) = (0u32, 0.0f64);
    let mut last_check = start;
    let mut interval = check_every.unwrap_or(MIN_CHECK_INTERVAL);
    let mut latest: Option<ErrorEstimate> = None;
    let mut history = Vec::new();
    // Time spent checking is not rendering time: the history's seconds leave it out.
    let rendering = |now: Instant, check_seconds: f64| (now - start).as_secs_f64() - check_seconds;
    let mut k = 1u64;
    let mut interrupted = false;
    // The within-pixel variance needs two samples a pixel: from one it reads 0, an error of 0
    // that would meet any target (a large image's first round, when it outlasts the first check
    // interval, stopped at 1 spp "reached"). The spread of randomisations is defined from 1.
    let defined = |renderers: &[Renderer]| estimator.renders() > 1 || renderers[0].spp() >= 2;
    // The image and its whole estimate, once a check has confirmed the target on every pixel.
    let mut confirmed = None;
    let round_aim = super::batch::round_aim(gpu, r as u32);
    let read = |renderers: &[Renderer]| -> Result<(Vec<Film>, u64, u64), RenderError> {
        let mut films = Vec::new();
        let (mut rays, mut faults) = (0, 0);
        for rd in renderers {
            let b = rd.readback()?;
            rays += b.rays;
            faults += b.faults;
            films.push(b.film);
        }
        Ok((films, rays, faults))
    };
    loop {
        let done = renderers[0].spp() * r;
        if cancel.load(Ordering::Relaxed) {
            interrupted = true;
            break;
        }
        if done + r > max_spp || max_time.is_some_and(|t| start.elapsed() >= t) {
            break;
        }
        let per = k.min((max_spp - done) / r).max(1);
        let round = Instant::now();
        for rd in renderers.iter_mut() {
            rd.render(Budget::Samples(per), &never, |_| {})?;
        }
        let took = round.elapsed().as_secs_f64().max(1e-6);
        // The next round's size: a round's aim, or what is left of a time budget if less.
        let aim = max_time.map_or(round_aim, |t| round_aim.min(t.saturating_sub(start.elapsed())));
        k = SampleCount::new(per as f64, 1.0, f64::MAX).fill(aim.as_secs_f64().max(1e-3), took / per as f64) as u64;
        if last_check.elapsed() >= interval && defined(&renderers) {
            let t0 = Instant::now();
            let mut e = sampled_estimate(&renderers, estimator, display, check_pixels)?;
            // What a sampled check costs sets the interval between checks.
            let cost = t0.elapsed();
            if target.is_some_and(|t| t.reached(&e)) {
                // The sampled rows say reached: confirm on every pixel, the estimate the image
                // is reported with, so that a render never stops short of its target on the
                // rows' sampling error.
                let (films, rays, faults) = read(&renderers)?;
                let (film, whole) = estimate_films(estimator, &films, Some(display));
                e = whole;
                if target.is_some_and(|t| t.reached(&whole)) {
                    confirmed = Some((film, whole, rays, faults));
                }
            }
            history.push((rendering(t0, check_seconds), renderers[0].spp() * r, e));
            checks += 1;
            check_seconds += t0.elapsed().as_secs_f64();
            interval = check_every.unwrap_or_else(|| MIN_CHECK_INTERVAL.max(cost.mul_f64(CHECK_COST_FACTOR)));
            last_check = Instant::now();
            latest = Some(e);
            if confirmed.is_some() {
                break;
            }
            // No more than the samples the target still needs if the error falls as 1 / spp
            // (randomised QMC falls faster): a round of the full aim would overshoot the target
            // by up to a round, and CPU adapters' rounds are long.
            if let Some(f) = target.map(|t| t.remaining_factor(&e)).filter(|f| f.is_finite() && *f > 1.0) {
                k = k.min(((renderers[0].spp() as f64 * (f - 1.0)).ceil() as u64).max(1));
            }
        }
        let elapsed = start.elapsed();
        let eta = latest.zip(target).map(|(e, t)| elapsed.mul_f64((t.remaining_factor(&e) - 1.0).clamp(0.0, 1e6)));
        progress(Progress { spp_done: renderers[0].spp() * r, elapsed, estimate: latest, eta });
    }
    let seconds = start.elapsed().as_secs_f64();
    let (film, estimate, rays, faults) = match confirmed {
        Some(done) => done,
        None => {
            let (films, rays, faults) = read(&renderers)?;
            let (film, estimate) = estimate_films(estimator, &films, Some(display));
            (film, estimate, rays, faults)
        }
    };
    Ok(TargetOutcome {
        film,
        rays,
        faults,
        seconds,
        reached: defined(&renderers) && target.is_some_and(|t| t.reached(&estimate)),
        estimate,
        estimator,
        interrupted,
        checks,
        check_seconds,
        history,
    })
}

/// The estimate from evenly spaced rows of every randomisation, about `pixels` in all.
fn sampled_estimate(renderers: &[Renderer], estimator: Estimator, display: &DisplayTransform, pixels: u32) -> Result<ErrorEstimate, RenderError> {
    let (width, height) = renderers[0].size();
    let rows_wanted = (pixels / width.max(1)).clamp(1, height);
    let stride = height.div_ceil(rows_wanted);
    let mut films = Vec::new();
    for rd in renderers {
        let (pixels, rows) = rd.accumulator_rows(stride)?;
        films.push(Film::from_accumulators(width, rows, rd.spp(), &pixels));
    }
    Ok(estimate_films(estimator, &films, Some(display)).1)
}

/// Renders `spp` samples per pixel split over the randomisations `estimator` needs (spp / R
/// each, seeds `randomisation_seed(seed, r)`), and returns their films.
pub fn render_randomised(
    gpu: &Gpu,
    pipelines: &PathTracerPipelines,
    scene: &Scene,
    method: Method,
    seed: u32,
    spp: u64,
    estimator: Estimator,
) -> Result<Vec<Film>, RenderError> {
    let per = (spp / estimator.renders() as u64).max(1);
    let never = AtomicBool::new(false);
    randomised_renderers(gpu, pipelines, scene, method, seed, estimator)?
        .into_iter()
        .map(|mut rd| {
            rd.render(Budget::Samples(per), &never, |_| {})?;
            Ok(rd.readback()?.film)
        })
        .collect()
}

/// One renderer per randomisation `estimator` needs, seeded `randomisation_seed(seed, r)`.
fn randomised_renderers(
    gpu: &Gpu,
    pipelines: &PathTracerPipelines,
    scene: &Scene,
    method: Method,
    seed: u32,
    estimator: Estimator,
) -> Result<Vec<Renderer>, RenderError> {
    (0..estimator.renders()).map(|i| Renderer::new(gpu, pipelines, scene, method, randomisation_seed(seed, i))).collect()
}
