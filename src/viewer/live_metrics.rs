//! Live error metrics of a converging image, computed off the UI thread from an asynchronous
//! readback of the accumulators: with a reference, relMSE (linear radiance) and PSNR and SSIM
//! (display images), through the same `metrics` functions as `pathlab compare`; without one,
//! the relMSE and PSNR estimated from the per-pixel sample variance (`estimate::within_pixel`).

use std::sync::mpsc::{channel, Receiver, TryRecvError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::display::DisplayTransform;
use crate::film::AccumPixel;
use crate::metrics::{linear::rel_mse, psnr::psnr, ssim::ssim};
use crate::film::Film;

/// One point of a convergence curve.
#[derive(Debug, Clone, Copy)]
pub struct LivePoint {
    /// Render time the method had when its accumulators were read.
    pub seconds: f64,
    pub spp: u64,
    pub rel_mse: f64,
    /// True when `rel_mse` and `psnr` are estimated from the sample variance (no reference).
    pub estimated: bool,
    /// PSNR (dB) of the display image.
    pub psnr: f64,
    /// SSIM of the display image (with a reference only).
    pub ssim: Option<f64>,
}

/// Metrics being computed on a worker thread.
pub struct MetricsTask {
    rx: Receiver<LivePoint>,
    started: Instant,
}

/// What the task took, to pace the next one.
pub struct Finished {
    pub point: LivePoint,
    pub cost: Duration,
}

impl MetricsTask {
    /// Starts computing the metrics of `pixels` (a full readback holding `spp` samples per
    /// pixel, taken at `seconds` of render time) against `reference` when it has the size.
    pub fn spawn(
        pixels: Vec<AccumPixel>,
        (width, height): (u32, u32),
        spp: u64,
        seconds: f64,
        reference: Option<Arc<Film>>,
        display: DisplayTransform,
    ) -> MetricsTask {
        let (tx, rx) = channel();
        std::thread::spawn(move || {
            let film = Film::from_accumulators(width, height, spp, &pixels);
            let _ = tx.send(compute(&film, reference.as_deref(), display, seconds));
        });
        MetricsTask { rx, started: Instant::now() }
    }

    /// The result when it is ready (`None` while computing, or if the worker died).
    pub fn try_finish(&self) -> Option<Finished> {
        match self.rx.try_recv() {
            Ok(point) => Some(Finished { point, cost: self.started.elapsed() }),
            Err(TryRecvError::Empty | TryRecvError::Disconnected) => None,
        }
    }
}

/// The metrics of `film` (against `reference` when the sizes agree).
pub fn compute(film: &Film, reference: Option<&Film>, display: DisplayTransform, seconds: f64) -> LivePoint {
    match reference.filter(|r| crate::metrics::check_sizes(film, r).is_ok()) {
        Some(reference) => {
            let (t, r) = (display.film(film), display.film(reference));
            LivePoint {
                seconds,
                spp: film.spp,
                rel_mse: rel_mse(film, reference),
                estimated: false,
                psnr: psnr(&r, &t),
                ssim: Some(ssim(&r, &t)),
            }
        }
        None => {
            let e = crate::estimate::within_pixel(film, Some(&display));
            LivePoint { seconds, spp: film.spp, rel_mse: e.rel_mse, estimated: true, psnr: e.psnr.unwrap_or(f64::NAN), ssim: None }
        }
    }
}
