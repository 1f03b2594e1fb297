//! How many samples per pixel one UI frame may add: the render driver's budget control.
//!
//! A frame costs the UI's own work plus the renderer's: dt = U + c k for k samples per pixel.
//! Neither U nor c is known (they depend on the window, the adapter, the scene and the method),
//! so every `PROBE_EVERY` frames two frames render nothing, and the second one's time is U; the
//! other frames give c = (dt - U) / k. Both are smoothed. The set point makes a frame last the
//! aim: the target, unless the UI alone takes more than (1 - `MIN_RENDER_SHARE`) of it (a
//! software rasteriser drawing a large window): then frames get longer instead of the renderer
//! starving. Below one sample per pixel, k is the share of the rows a
//! frame renders (see `Renderer::submit_partial`).

use std::time::Duration;

use crate::render::controller::SampleCount;

/// The renderer's least share of a frame (with the 45 ms default target, the UI may take up to
/// 31 ms before frames get longer).
pub const MIN_RENDER_SHARE: f64 = 0.3;
/// Every this many frames, two frames measure the UI alone.
const PROBE_EVERY: u64 = 40;
/// Smoothing of the UI time and of the time per sample.
const SMOOTHING: f64 = 0.2;

pub struct FrameBudget {
    target: f64,
    /// Image rows, and the samples per pixel of a pass spread over frames: below that many
    /// samples per pixel per frame, a frame renders whole rows of such a pass.
    rows: u32,
    pass: f64,
    fewest: f64,
    most: f64,
    /// Set point (samples per pixel per frame).
    k: f64,
    /// Frames asked for, and the samples per pixel of the one in flight.
    frames: u64,
    in_flight: f64,
    /// Smoothed UI seconds per frame and render seconds per sample per pixel.
    ui: Option<f64>,
    per_sample: Option<f64>,
}

fn smooth(avg: Option<f64>, x: f64) -> f64 {
    avg.map_or(x, |a| a + SMOOTHING * (x - a))
}

impl FrameBudget {
    /// A budget of `target` per frame for an image of `rows` rows whose partial passes take
    /// `pass` samples per pixel; k stays within [fewest, most].
    pub fn new(target: Duration, rows: u32, pass: u32, fewest: f64, most: f64) -> FrameBudget {
        FrameBudget {
            target: target.as_secs_f64(),
            rows: rows.max(1),
            pass: pass.max(1) as f64,
            fewest,
            most,
            k: fewest.min(most),
            frames: 0,
            in_flight: 0.0,
            ui: None,
            per_sample: None,
        }
    }

    /// Samples per pixel for the next frame: 0 on the frames that measure the UI alone, whole
    /// samples from `pass` on, whole rows of a pass below (k = pass x rows / image rows).
    pub fn next(&mut self) -> f64 {
        self.frames += 1;
        let phase = self.frames % PROBE_EVERY;
        // Frames 1 and 2 of each period render nothing (the first lets queued work drain).
        self.in_flight = if (phase == 1 || phase == 2) && self.frames > 2 {
            0.0
        } else {
            let rows = self.rows as f64;
            if self.k >= self.pass { self.k.round() } else { (self.k / self.pass * rows).ceil().min(rows) / rows * self.pass }
        };
        self.in_flight
    }

    /// The frame rendered `k` instead of what `next()` said (finishing a pass in progress).
    pub fn rendered_instead(&mut self, k: f64) {
        self.in_flight = k;
    }

    /// Records that the frame of the last `next()` took `dt` seconds, and moves the set point.
    pub fn record(&mut self, dt: f64) {
        let dt = dt.max(1e-4);
        let k = self.in_flight;
        if k == 0.0 {
            if self.frames % PROBE_EVERY == 2 {
                self.ui = Some(smooth(self.ui, dt));
            }
            return;
        }
        // The frame time to aim at: the target, or longer when the UI alone takes more than
        // (1 - MIN_RENDER_SHARE) of it.
        let aim = self.ui.map_or(self.target, |ui| self.target.max(ui / (1.0 - MIN_RENDER_SHARE)));
        let wanted = match self.ui {
            // dt = U + c k: c from this frame (smoothed), then the k that fills the aim.
            Some(ui) => {
                let per_sample = smooth(self.per_sample, ((dt - ui) / k).max(1e-7));
                self.per_sample = Some(per_sample);
                (aim - ui) / per_sample
            }
            // Until the UI has been measured: scale by aim / measured.
            None => k * aim / dt,
        };
        // Damped (a single frame's time is noisy): the geometric middle, at most doubling or
        // halving per frame.
        self.k = SampleCount::new(self.k, self.fewest, self.most).damped(0.5).towards(wanted);
    }

    /// The estimated UI seconds per frame and render seconds per sample per pixel.
    pub fn estimates(&self) -> Option<(f64, f64)> {
        Some((self.ui?, self.per_sample?))
    }

    /// The set point.
    pub fn samples_per_frame(&self) -> f64 {
        self.k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs frames of cost ui + per_sample * k (with +-2 ms of deterministic jitter) and returns
    /// the settled set point and the mean frame time of the last 200 frames.
    fn settle(ui: f64, per_sample: f64, target_ms: u64) -> (f64, f64) {
        let mut b = FrameBudget::new(Duration::from_millis(target_ms), 512, 1, 8.0 / 512.0, 1e4);
        let mut state = 12345u64;
        let mut total = 0.0;
        for i in 0..800 {
            let k = b.next();
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let jitter = ((state >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.004;
            let dt = ui + per_sample * k + jitter;
            if i >= 600 {
                total += dt;
            }
            b.record(dt);
        }
        (b.samples_per_frame(), total / 200.0)
    }

    #[test]
    fn fills_the_frame_when_the_ui_is_cheap() {
        // UI 20 ms, 5 ms a sample, target 45 ms: 5 samples, 45 ms frames (less the probes).
        let (k, frame) = settle(0.020, 0.005, 45);
        assert!((k - 5.0).abs() < 0.75, "k = {k}");
        assert!((frame - 0.044).abs() < 0.004, "frame {frame}");
    }

    #[test]
    fn keeps_a_share_of_a_slow_frame_for_the_renderer() {
        // UI 60 ms, more than the 45 ms target: frames of 60 / 0.7 = 86 ms, 30% rendering.
        let (k, frame) = settle(0.060, 0.005, 45);
        assert!((k - 5.14).abs() < 0.8, "k = {k}");
        assert!((frame - 0.085).abs() < 0.01, "frame {frame}");
    }

    #[test]
    fn goes_below_one_sample_per_pixel_for_expensive_samples() {
        // 200 ms a sample per pixel (a large image on a slow device), UI 10 ms: a sixth of the rows.
        let (k, frame) = settle(0.010, 0.200, 45);
        assert!((k - 0.175).abs() < 0.04, "k = {k}");
        assert!((frame - 0.045).abs() < 0.006, "frame {frame}");
    }
}
