//! Rendering to a budget: each frame is one compute pass that adds `k` samples per pixel to
//! the accumulators (one dispatch per band). Several frames are in flight; the host only writes
//! the frames' uniforms and submits, and waits on the device only when the queue is full, at the
//! end, or to read back. `k` follows the measured rate so that a dispatch takes about
//! `TARGET_DISPATCH` (`TARGET_DISPATCH_CPU` on CPU adapters; `controller::SampleCount`).

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::gpu::wait_for_submission;

use super::controller::SampleCount;
use super::{Budget, Progress, RenderError, RenderStats, Renderer, MAX_SPP};

/// Aim for dispatches of about this long: far below any driver watchdog, short enough for a
/// responsive Ctrl-C and progress bar, long enough to amortise submission overhead.
const TARGET_DISPATCH: Duration = Duration::from_millis(150);
/// Frames submitted but not yet finished, at most.
const MAX_IN_FLIGHT: usize = 3;
/// On CPU adapters, longer dispatches and fewer in flight (Ctrl-C then waits up to 0.8 s, where
/// a GPU's 3 x 150 ms is 0.45 s): lavapipe (Mesa 22.3) compiles the kernel again at every
/// dispatch, with the uniforms it inlines (`lvp_inline_uniforms`; from Mesa's shader cache where
/// it has them), which shorter dispatches pay more often. `pathlab bench SCENE --methods mis
/// --seconds 4` at 150 / 300 / 600 ms, M samples/s: Veach's scene (512x256) 3.39 / 4.03 / 4.29,
/// the study scene (1024x512) 28.1 / 30.4 / 31.5, the Cornell box (256x256) 4.88 / 4.85 / 4.89.
const TARGET_DISPATCH_CPU: Duration = Duration::from_millis(400);
const MAX_IN_FLIGHT_CPU: usize = 2;

/// The dispatch length aimed for on `gpu`, and the frames in flight at most.
pub(super) fn dispatch_aim(gpu: &crate::gpu::Gpu) -> (Duration, usize) {
    if gpu.info.device_type == wgpu::DeviceType::Cpu {
        (TARGET_DISPATCH_CPU, MAX_IN_FLIGHT_CPU)
    } else {
        (TARGET_DISPATCH, MAX_IN_FLIGHT)
    }
}

/// Aimed-for wall time of one round of a render to a target error (`to_target`), all its
/// `randomisations` together, on GPUs.
const ROUND: Duration = Duration::from_millis(250);

/// The wall time aimed for by one round of `randomisations` renders to a target error: on GPUs
/// `ROUND` in all; on CPU adapters at least one dispatch of `dispatch_aim` each, since lavapipe
/// prepares the kernel again at every dispatch (above). With 250 ms rounds of `best`'s 4
/// randomisations, `pathlab advise assets/scenes/veach_mis.xml --size 256x128` spent 53% of its
/// samples in the driver and piloted `best` at 0.91 M samples/s where `bench` runs it at 3.7.
pub(super) fn round_aim(gpu: &crate::gpu::Gpu, randomisations: u32) -> Duration {
    if gpu.info.device_type == wgpu::DeviceType::Cpu {
        ROUND.max(TARGET_DISPATCH_CPU * randomisations)
    } else {
        ROUND
    }
}

impl Renderer {
    /// Adds samples until `budget` is met or `cancel` is set, then waits for the device.
    pub fn render(&mut self, budget: Budget, cancel: &AtomicBool, progress: impl FnMut(Progress)) -> Result<RenderStats, RenderError> {
        self.render_until(budget, None, cancel, progress)
    }

    /// Like `render`, also stopping (not interrupted) once `deadline` has passed: for
    /// checkpoints at regular intervals.
    pub fn render_until(
        &mut self,
        budget: Budget,
        deadline: Option<Instant>,
        cancel: &AtomicBool,
        mut progress: impl FnMut(Progress),
    ) -> Result<RenderStats, RenderError> {
        if let Budget::Samples(n) = budget {
            self.check_room(n)?;
        }
        let start = Instant::now();
        let target_spp = match budget {
            Budget::Samples(n) => self.spp_done + n,
            Budget::Time(_) => MAX_SPP - self.first_sample,
        };
        let (device, queue) = (self.gpu.device.clone(), self.gpu.queue.clone());
        let completed = Arc::new(AtomicU64::new(self.spp_done));
        // Throughput since the first completion: (time of the first completion, samples done by
        // then), and the latest (time, samples). Completion callbacks fire in batches during
        // polls, so intervals between single callbacks mean nothing; the long-run rate does.
        let timing: Arc<Mutex<Option<((Instant, u64), (Instant, u64))>>> = Arc::new(Mutex::new(None));
        let (target_dispatch, max_in_flight) = dispatch_aim(&self.gpu);
        let mut in_flight: VecDeque<wgpu::SubmissionIndex> = VecDeque::new();
        let mut submitted = self.spp_done;
        let mut frames = 0;
        let mut interrupted = false;
        loop {
            if cancel.load(Ordering::Relaxed) {
                interrupted = true;
                break;
            }
            if submitted >= target_spp {
                break;
            }
            if let Budget::Time(limit) = budget {
                if start.elapsed() >= limit {
                    break;
                }
            }
            if deadline.is_some_and(|d| Instant::now() >= d) {
                break;
            }
            let count = (self.samples_per_dispatch as u64).min(target_spp - submitted) as u32;
            let index = self.submit_frame(self.first_sample + submitted, count);
            let (done, clock) = (completed.clone(), timing.clone());
            queue.on_submitted_work_done(move || {
                let done_now = done.fetch_add(count as u64, Ordering::Relaxed) + count as u64;
                let now = Instant::now();
                let mut t = clock.lock().unwrap_or_else(|e| e.into_inner());
                let first = t.map_or((now, done_now), |(first, _)| first);
                *t = Some((first, (now, done_now)));
            });
            in_flight.push_back(index);
            submitted += count as u64;
            frames += 1;

            if in_flight.len() >= max_in_flight {
                let oldest = in_flight.pop_front();
                wait_for_submission(&device, oldest)?;
            } else {
                let _ = device.poll(wgpu::PollType::Poll);
            }
            progress(Progress { spp_done: completed.load(Ordering::Relaxed), elapsed: start.elapsed(), estimate: None, eta: None });

            // Next dispatch size from the measured time per sample (doubling until measured).
            let rate = *timing.lock().unwrap_or_else(|e| e.into_inner());
            let per_sample = rate.and_then(|((t0, n0), (t1, n1))| {
                (n1 > n0 && t1 > t0).then(|| (t1 - t0).as_secs_f64() / (n1 - n0) as f64)
            });
            let mut size = SampleCount::new(self.samples_per_dispatch as f64, 1.0, self.max_samples_per_dispatch as f64);
            match per_sample {
                Some(per_sample) => size.fill(target_dispatch.as_secs_f64(), per_sample),
                None if frames >= 2 => size.grow(),
                None => size.get(),
            };
            self.samples_per_dispatch = size.get() as u32;
        }
        wait_for_submission(&device, None)?;
        self.spp_done = submitted;
        progress(Progress { spp_done: submitted, elapsed: start.elapsed(), estimate: None, eta: None });
        Ok(RenderStats { spp: self.spp_done, seconds: start.elapsed().as_secs_f64(), frames, interrupted })
    }
}
