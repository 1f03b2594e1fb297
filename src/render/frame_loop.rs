//! The frame loop: each frame is one compute pass of the path tracer that adds `k` samples per
//! pixel into the GPU accumulator (one dispatch per band of rows, see `Band`). Several frames
//! are in flight; the host only writes the frames' uniforms and submits, and waits on the
//! device only when the queue is full, at the end, or to read back. `k` is adapted so that one dispatch takes about `TARGET_DISPATCH`.

use std::collections::VecDeque;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::gpu::{
    loop_iterations_per_sample, wait_for_submission, AccumPixel, FrameParams, Gpu, GpuError, PathTracerPipelines, PipelineKey, SceneBuffers,
};
use crate::method::Method;
use crate::scene::Scene;
use crate::shaders;

use super::Film;

/// Aim for dispatches of about this long: far below any driver watchdog, short enough for a
/// responsive Ctrl-C and progress bar, long enough to amortise submission overhead.
const TARGET_DISPATCH: Duration = Duration::from_millis(150);
/// Frames submitted but not yet finished, at most.
const MAX_IN_FLIGHT: usize = 3;
/// Largest number of samples per pixel in one dispatch.
const MAX_SAMPLES_PER_DISPATCH: u32 = 1 << 14;
/// llvmpipe (lavapipe) stops all loops of an invocation after 65535 back-edges in total; on CPU
/// adapters a dispatch is kept below this many. The readback checks every pixel's sample
/// count, so a driver that drops work is reported, never averaged in.
const CPU_LOOP_BUDGET: u64 = 60_000;
/// Sample indices are u32: a pixel can take at most 2^32 samples.
pub const MAX_SPP: u64 = 1 << 32;
const WORKGROUP: u32 = 8;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error(
        "one row of a {width}-pixel-wide image needs a {bytes} byte accumulator, more than this \
         adapter's largest storage binding ({limit} bytes); render a narrower image"
    )]
    TooLarge { width: u32, bytes: u64, limit: u64 },
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
    #[error("cannot resume from the saved accumulators: {0}")]
    Restore(String),
    #[error("a pass spread over several submissions is in progress: finish it (submit_partial) first")]
    PassInProgress,
    #[error("at most 2^32 samples per pixel are supported (asked for {0})")]
    TooManySamples(u64),
    #[error(
        "one sample of this scene may run ~{0} shader loop iterations, more than the 65535 llvmpipe \
         (software Vulkan) allows per invocation; reduce max_depth or the number of objects and \
         lights, or use a hardware GPU"
    )]
    LoopLimit(u64),
}

/// When to stop a render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Budget {
    /// Stop after this many samples per pixel in total.
    Samples(u64),
    /// Stop submitting frames after this much wall time.
    Time(Duration),
}

/// Reported after every frame.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// Samples per pixel finished on the device.
    pub spp_done: u64,
    pub elapsed: Duration,
}

/// The accumulators, read back.
#[derive(Debug, Clone)]
pub struct Readback {
    pub film: Film,
    /// Rays traced for the whole film so far (camera, bounce and shadow rays), counted by the
    /// kernel as it traces them.
    pub rays: u64,
}

/// What a call to `Renderer::render` did.
#[derive(Debug, Clone, Copy)]
pub struct RenderStats {
    /// Samples per pixel accumulated so far (over all calls).
    pub spp: u64,
    /// Wall time of this call.
    pub seconds: f64,
    /// Dispatches of this call.
    pub frames: u64,
    /// True when stopped early by the cancel flag.
    pub interrupted: bool,
}

/// Frames whose device time can be recorded between two `device_time` calls (two timestamp
/// queries each; wgpu allows 4096 queries per set).
const MAX_TIMED_FRAMES: u32 = 2048;

/// GPU timestamps at the start and end of every frame's compute pass.
struct Timestamps {
    set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    readback: wgpu::Buffer,
    /// Frames recorded since the last `device_time`.
    frames: u32,
}

/// Rows `y0 .. y0 + rows` of the image: their accumulator, frame uniform and bind group.
struct Band {
    y0: u32,
    rows: u32,
    params_buffer: wgpu::Buffer,
    accum: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

/// Renders one scene with one method into a GPU accumulator.
pub struct Renderer<'g> {
    gpu: &'g Gpu,
    pipeline: Arc<wgpu::ComputePipeline>,
    /// The image in bands of rows, each with its own accumulator (one storage binding holds
    /// at most `max_storage_buffer_binding_size` bytes: 128 MiB on lavapipe, ~2 Mpixel).
    bands: Vec<Band>,
    params: FrameParams,
    /// Sample index of the first sample (0 unless set by `start_at_sample`).
    first_sample: u64,
    spp_done: u64,
    samples_per_dispatch: u32,
    /// Cap on samples per dispatch for this device and pipeline.
    max_samples_per_dispatch: u32,
    timestamps: Option<Timestamps>,
    /// A pass of `submit_partial` in progress: (next row, its samples per pixel).
    partial: Option<(u32, u32)>,
    _scene_buffers: SceneBuffers,
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
}

impl<'g> Renderer<'g> {
    pub fn new(
        gpu: &'g Gpu,
        pipelines: &PathTracerPipelines,
        scene: &Scene,
        method: Method,
        seed: u32,
    ) -> Result<Renderer<'g>, RenderError> {
        Renderer::with_band_bytes(gpu, pipelines, scene, method, seed, u64::MAX)
    }

    /// Like `new`, with accumulator bands of at most `band_bytes` bytes (whole rows; at least
    /// one row). `new` uses the adapter's largest storage binding.
    pub fn with_band_bytes(
        gpu: &'g Gpu,
        pipelines: &PathTracerPipelines,
        scene: &Scene,
        method: Method,
        seed: u32,
        band_bytes: u64,
    ) -> Result<Renderer<'g>, RenderError> {
        Renderer::build(gpu, pipelines, scene, PipelineKey { method, features: scene.features() }, seed, band_bytes)
    }

    /// Like `new`, with a pipeline that has every optional feature on
    /// (`SceneFeatures::all_on`): to measure what specialisation to the scene gains.
    pub fn unspecialised(
        gpu: &'g Gpu,
        pipelines: &PathTracerPipelines,
        scene: &Scene,
        method: Method,
        seed: u32,
    ) -> Result<Renderer<'g>, RenderError> {
        let key = PipelineKey { method, features: scene.features().all_on() };
        Renderer::build(gpu, pipelines, scene, key, seed, u64::MAX)
    }

    fn build(
        gpu: &'g Gpu,
        pipelines: &PathTracerPipelines,
        scene: &Scene,
        key: PipelineKey,
        seed: u32,
        band_bytes: u64,
    ) -> Result<Renderer<'g>, RenderError> {
        let device = &gpu.device;
        let (width, height) = (scene.render.width, scene.render.height);
        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        let row_bytes = width as u64 * std::mem::size_of::<AccumPixel>() as u64;
        if row_bytes > limit {
            return Err(RenderError::TooLarge { width, bytes: row_bytes, limit });
        }
        let rows_per_band = (band_bytes.min(limit) / row_bytes).clamp(1, height as u64) as u32;
        let max_samples_per_dispatch = if gpu.info.device_type == wgpu::DeviceType::Cpu {
            let per_sample = loop_iterations_per_sample(&key, scene.render.max_depth);
            if per_sample > CPU_LOOP_BUDGET {
                return Err(RenderError::LoopLimit(per_sample));
            }
            (CPU_LOOP_BUDGET / per_sample).clamp(1, MAX_SAMPLES_PER_DISPATCH as u64) as u32
        } else {
            MAX_SAMPLES_PER_DISPATCH
        };
        let (pipeline, _) = pipelines.get(device, key);
        let scene_buffers = SceneBuffers::new(device, scene);
        let mut params = FrameParams::for_scene(scene);
        params.seed = seed;
        let mut bands = Vec::new();
        for y0 in (0..height).step_by(rows_per_band as usize) {
            let rows = rows_per_band.min(height - y0);
            let params_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("frame params"),
                size: std::mem::size_of::<FrameParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            // An empty accumulator: a buffer mapped at creation reads as zeros (WebGPU spec), and
            // unmapping hands wgpu that initialised content (no lazy clear).
            let accum = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("accumulator"),
                size: rows as u64 * row_bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: true,
            });
            accum.unmap();
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("path tracer"),
                layout: &pipelines.bind_group_layout,
                entries: &[
                    entry(0, &params_buffer),
                    entry(1, &scene_buffers.spheres),
                    entry(2, &scene_buffers.planes),
                    entry(3, &scene_buffers.materials),
                    entry(5, &accum),
                    entry(shaders::HALTON_PRIMES_BINDING, &pipelines.halton_primes),
                ],
            });
            bands.push(Band { y0, rows, params_buffer, accum, bind_group });
        }
        Ok(Renderer {
            gpu,
            pipeline,
            bands,
            params,
            first_sample: 0,
            spp_done: 0,
            samples_per_dispatch: 1,
            max_samples_per_dispatch,
            timestamps: None,
            partial: None,
            _scene_buffers: scene_buffers,
        })
    }

    /// Number of accumulator bands the image is split into.
    pub fn bands(&self) -> usize {
        self.bands.len()
    }

    /// Image width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.params.width, self.params.height)
    }

    /// Samples per pixel accumulated so far.
    pub fn spp(&self) -> u64 {
        self.spp_done
    }

    /// Records GPU timestamps around every frame from now on, for `device_time`. Returns false
    /// when the adapter has no timestamp queries.
    pub fn enable_timestamps(&mut self) -> bool {
        if !self.gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY) {
            return false;
        }
        let device = &self.gpu.device;
        let bytes = 2 * MAX_TIMED_FRAMES as u64 * 8;
        self.timestamps = Some(Timestamps {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("frame timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_TIMED_FRAMES,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            frames: 0,
        });
        true
    }

    /// Device time of the frames rendered since timestamps were enabled or last read (at most
    /// the first MAX_TIMED_FRAMES of them), and how many frames that covers. Reads back: call
    /// it outside the frame loop.
    pub fn device_time(&mut self) -> Result<Option<(Duration, u32)>, RenderError> {
        let Some(ts) = self.timestamps.as_mut() else { return Ok(None) };
        let frames = ts.frames.min(MAX_TIMED_FRAMES);
        ts.frames = 0;
        if frames == 0 {
            return Ok(Some((Duration::ZERO, 0)));
        }
        let device = &self.gpu.device;
        let bytes = 2 * frames as u64 * 8;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("timestamps") });
        encoder.resolve_query_set(&ts.set, 0..2 * frames, &ts.resolve, 0);
        encoder.copy_buffer_to_buffer(&ts.resolve, 0, &ts.readback, 0, bytes);
        let index = self.gpu.queue.submit([encoder.finish()]);
        ts.readback.map_async(wgpu::MapMode::Read, ..bytes, |_| {});
        wait_for_submission(device, Some(index))?;
        wait_for_submission(device, None)?;
        let ticks: Vec<u64> = {
            let view = ts.readback.get_mapped_range(..bytes).map_err(|e| RenderError::Readback(e.to_string()))?;
            bytemuck::pod_collect_to_vec(&view)
        };
        ts.readback.unmap();
        let period_ns = self.gpu.queue.get_timestamp_period() as f64;
        let total_ns: f64 = ticks.chunks(2).map(|t| t[1].saturating_sub(t[0]) as f64 * period_ns).sum();
        Ok(Some((Duration::from_secs_f64(total_ns * 1e-9), frames)))
    }

    /// Draws sample indices from `index` on instead of 0 (before any sample is rendered): to
    /// continue a render in another process, or to test sample indices near 2^32.
    pub fn start_at_sample(&mut self, index: u64) -> Result<(), RenderError> {
        if self.spp_done > 0 || index >= MAX_SPP {
            return Err(RenderError::TooManySamples(index));
        }
        self.first_sample = index;
        Ok(())
    }

    /// Sample indices are u32: `n` more samples per pixel must stay below 2^32 in all.
    fn check_room(&self, n: u64) -> Result<(), RenderError> {
        let total = self.first_sample + self.spp_done + n;
        if total > MAX_SPP { Err(RenderError::TooManySamples(total)) } else { Ok(()) }
    }

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
        let gpu = self.gpu;
        let (device, queue) = (&gpu.device, &gpu.queue);
        let completed = Arc::new(AtomicU64::new(self.spp_done));
        // Throughput since the first completion: (time of the first completion, samples done by
        // then), and the latest (time, samples). Completion callbacks fire in batches during
        // polls, so intervals between single callbacks mean nothing; the long-run rate does.
        let timing: Arc<Mutex<Option<((Instant, u64), (Instant, u64))>>> = Arc::new(Mutex::new(None));
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

            if in_flight.len() >= MAX_IN_FLIGHT {
                let oldest = in_flight.pop_front();
                wait_for_submission(device, oldest)?;
            } else {
                let _ = device.poll(wgpu::PollType::Poll);
            }
            progress(Progress { spp_done: completed.load(Ordering::Relaxed), elapsed: start.elapsed() });

            // Next dispatch size from the measured time per sample: at most doubling per frame.
            let rate = *timing.lock().unwrap_or_else(|e| e.into_inner());
            let per_sample = rate.and_then(|((t0, n0), (t1, n1))| {
                (n1 > n0 && t1 > t0).then(|| (t1 - t0).as_secs_f64() / (n1 - n0) as f64)
            });
            let k = self.samples_per_dispatch as f64;
            let next = match per_sample {
                Some(per_sample) => TARGET_DISPATCH.as_secs_f64() / per_sample,
                None if frames >= 2 => k * 2.0,
                None => k,
            };
            self.samples_per_dispatch = next.clamp(k / 2.0, k * 2.0).clamp(1.0, self.max_samples_per_dispatch as f64) as u32;
        }
        wait_for_submission(device, None)?;
        self.spp_done = submitted;
        progress(Progress { spp_done: submitted, elapsed: start.elapsed() });
        Ok(RenderStats { spp: self.spp_done, seconds: start.elapsed().as_secs_f64(), frames, interrupted })
    }

    /// Encodes one frame (a compute pass over every band) adding `count` samples per pixel from
    /// sample index `sample_start`, and submits it without waiting.
    fn submit_frame(&mut self, sample_start: u64, count: u32) -> wgpu::SubmissionIndex {
        self.submit_rows(sample_start, count, 0..self.params.height)
    }

    /// Like `submit_frame` for image rows `rows` only (dispatched band by band).
    fn submit_rows(&mut self, sample_start: u64, count: u32, rows: std::ops::Range<u32>) -> wgpu::SubmissionIndex {
        let gpu = self.gpu;
        let (device, queue) = (&gpu.device, &gpu.queue);
        let groups_x = self.params.width.div_ceil(WORKGROUP);
        self.params.sample_start = sample_start as u32;
        self.params.sample_count = count;
        // The part of each band inside `rows`: (band, first image row, rows).
        let tiles: Vec<(usize, u32, u32)> = self
            .bands
            .iter()
            .enumerate()
            .filter_map(|(i, b)| {
                let (y0, y1) = (b.y0.max(rows.start), (b.y0 + b.rows).min(rows.end));
                (y1 > y0).then_some((i, y0, y1 - y0))
            })
            .collect();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        {
            let timestamp_writes = self.timestamps.as_mut().filter(|t| t.frames < MAX_TIMED_FRAMES).map(|t| {
                t.frames += 1;
                wgpu::ComputePassTimestampWrites {
                    query_set: &t.set,
                    beginning_of_pass_write_index: Some(2 * (t.frames - 1)),
                    end_of_pass_write_index: Some(2 * (t.frames - 1) + 1),
                }
            });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("path trace"), timestamp_writes });
            pass.set_pipeline(&self.pipeline);
            for &(i, _, tile_rows) in &tiles {
                pass.set_bind_group(0, &self.bands[i].bind_group, &[]);
                pass.dispatch_workgroups(groups_x, tile_rows.div_ceil(WORKGROUP), 1);
            }
        }
        for &(i, y0, tile_rows) in &tiles {
            let band = &self.bands[i];
            let params = FrameParams { tile_y: y0, tile_height: tile_rows, accum_row: y0 - band.y0, ..self.params };
            queue.write_buffer(&band.params_buffer, 0, bytemuck::bytes_of(&params));
        }
        queue.submit([encoder.finish()])
    }

    /// Adds `count` samples per pixel to at most `rows` more rows of the image and returns at
    /// once: a sample pass spread over several calls, so that a caller with a time budget per
    /// call (the viewer's UI frames) is never held up by a whole image's dispatch. The pass in
    /// progress keeps its own count; returns true when it has covered every row (then `spp`
    /// includes it). Every pixel gets the same samples as with `submit`. Returns the rows
    /// dispatched.
    pub fn submit_partial(&mut self, count: u32, rows: u32) -> Result<u32, RenderError> {
        let (next_row, count) = match self.partial {
            Some(pass) => pass,
            None => {
                self.check_room(count as u64)?;
                (0, count)
            }
        };
        let end = next_row.saturating_add(rows.max(1)).min(self.params.height);
        self.submit_rows(self.first_sample + self.spp_done, count, next_row..end);
        if end == self.params.height {
            self.partial = None;
            self.spp_done += count as u64;
        } else {
            self.partial = Some((end, count));
        }
        Ok(end - next_row)
    }

    /// True while a pass of `submit_partial` has not covered every row: pixels then hold
    /// different sample counts, and full readbacks wait.
    pub fn pass_in_progress(&self) -> bool {
        self.partial.is_some()
    }

    /// Submits `count` more samples per pixel and returns at once (interactive use: the viewer
    /// adds a few samples per UI frame). The queue runs work in order, so a display pass or
    /// readback submitted afterwards sees these samples.
    pub fn submit(&mut self, count: u32) -> Result<wgpu::SubmissionIndex, RenderError> {
        if self.partial.is_some() {
            return Err(RenderError::PassInProgress);
        }
        self.check_room(count as u64)?;
        let index = self.submit_frame(self.first_sample + self.spp_done, count);
        self.spp_done += count as u64;
        Ok(index)
    }

    /// Most samples per pixel one dispatch may take on this device (the software rasteriser's
    /// loop limit bounds it on CPU adapters).
    pub fn max_samples_per_dispatch(&self) -> u32 {
        self.max_samples_per_dispatch
    }

    /// The accumulator of each band: (first row, rows, buffer of `AccumPixel`s, row-major).
    pub fn accumulator_buffers(&self) -> impl Iterator<Item = (u32, u32, &wgpu::Buffer)> {
        self.bands.iter().map(|b| (b.y0, b.rows, &b.accum))
    }

    /// Starts copying all accumulators back without waiting: poll the device and call
    /// `PendingReadback::try_finish` in later frames. Not while a partial pass is in progress
    /// (its sample-count check would fail).
    pub fn begin_readback(&self) -> PendingReadback {
        let regions: Vec<_> = self.bands.iter().map(|b| (&b.accum, 0, b.accum.size())).collect();
        self.begin_regions(&regions)
    }

    /// Starts copying one pixel's accumulator back (for a mouse-over probe).
    pub fn begin_read_pixel(&self, x: u32, y: u32) -> Option<PendingReadback> {
        let (w, h) = self.size();
        if x >= w || y >= h {
            return None;
        }
        let size = std::mem::size_of::<AccumPixel>() as u64;
        let band = self.bands.iter().find(|b| y >= b.y0 && y < b.y0 + b.rows)?;
        let offset = ((y - band.y0) as u64 * w as u64 + x as u64) * size;
        let mut pending = self.begin_regions(&[(&band.accum, offset, size)]);
        // Mid-pass, the pixel may hold this pass's samples already: it reports its own count.
        pending.spp = None;
        Some(pending)
    }

    /// Copies `regions` (buffer, byte offset, bytes) one after another into a staging buffer
    /// and starts mapping it.
    fn begin_regions(&self, regions: &[(&wgpu::Buffer, u64, u64)]) -> PendingReadback {
        let device = &self.gpu.device;
        let size: u64 = regions.iter().map(|r| r.2).sum();
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
        let mut at = 0;
        for &(buffer, offset, bytes) in regions {
            encoder.copy_buffer_to_buffer(buffer, offset, &staging, at, bytes);
            at += bytes;
        }
        let submission = self.gpu.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        PendingReadback { staging, rx, submission, spp: Some(self.spp_done) }
    }

    /// Copies the accumulators back and turns them into mean and variance.
    pub fn film(&self) -> Result<Film, RenderError> {
        Ok(self.readback()?.film)
    }

    /// The film, and the number of rays the kernel traced for it (counted by the kernel).
    pub fn readback(&self) -> Result<Readback, RenderError> {
        let pixels = self.accumulators()?;
        let rays = pixels.iter().map(AccumPixel::rays).sum();
        Ok(Readback { film: Film::from_accumulators(self.params.width, self.params.height, self.spp_done, &pixels), rays })
    }

    /// The raw per-pixel accumulators (compensated sums, sums of squares, count, rays), row-major,
    /// after checking that every pixel holds exactly the samples submitted.
    pub fn accumulators(&self) -> Result<Vec<AccumPixel>, RenderError> {
        let mut pixels: Vec<AccumPixel> = Vec::with_capacity(self.params.width as usize * self.params.height as usize);
        for band in &self.bands {
            pixels.extend(self.read_band(band)?);
        }
        Ok(pixels)
    }


    /// Sample index of the first sample of this render.
    pub fn first_sample(&self) -> u64 {
        self.first_sample
    }

    /// Loads accumulators saved by `accumulators` (before any sample is rendered): the render
    /// continues at sample index `first_sample + spp` and ends bit-identical to one that never
    /// stopped.
    pub fn restore(&mut self, first_sample: u64, spp: u64, pixels: &[AccumPixel]) -> Result<(), RenderError> {
        let expected = self.params.width as usize * self.params.height as usize;
        if pixels.len() != expected {
            return Err(RenderError::Restore(format!("{} pixels given, the image has {expected}", pixels.len())));
        }
        if let Some((i, p)) = pixels.iter().enumerate().find(|(_, p)| p.count as u64 != spp % (1 << 32)) {
            return Err(RenderError::Restore(format!("pixel {i} holds {} samples, expected {spp}", p.count)));
        }
        if self.spp_done > 0 || first_sample + spp > MAX_SPP {
            return Err(RenderError::TooManySamples(first_sample + spp));
        }
        let row = self.params.width as usize;
        for band in &self.bands {
            let start = band.y0 as usize * row;
            let slice = &pixels[start..start + band.rows as usize * row];
            self.gpu.queue.write_buffer(&band.accum, 0, bytemuck::cast_slice(slice));
        }
        self.gpu.queue.submit([]);
        self.first_sample = first_sample;
        self.spp_done = spp;
        Ok(())
    }

    fn read_band(&self, band: &Band) -> Result<Vec<AccumPixel>, RenderError> {
        self.read_regions(&[(&band.accum, 0, band.accum.size())])
    }

    /// The accumulators of rows 0, stride, 2 stride, ... (row-major): a cheap sample of the
    /// image for error estimates during a render. Returns the pixels and the number of rows.
    pub fn accumulator_rows(&self, stride: u32) -> Result<(Vec<AccumPixel>, u32), RenderError> {
        let row_bytes = self.params.width as u64 * std::mem::size_of::<AccumPixel>() as u64;
        let mut regions = Vec::new();
        for y in (0..self.params.height).step_by(stride.max(1) as usize) {
            let band = self.bands.iter().find(|b| y >= b.y0 && y < b.y0 + b.rows).expect("bands cover the image");
            regions.push((&band.accum, (y - band.y0) as u64 * row_bytes, row_bytes));
        }
        let rows = regions.len() as u32;
        let pixels = self.read_regions(&regions)?;
        Ok((pixels, rows))
    }

    /// Copies `regions` (buffer, byte offset, bytes) back, waiting for them.
    fn read_regions(&self, regions: &[(&wgpu::Buffer, u64, u64)]) -> Result<Vec<AccumPixel>, RenderError> {
        let pending = self.begin_regions(regions);
        wait_for_submission(&self.gpu.device, Some(pending.submission.clone()))?;
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            if let Some(result) = pending.try_finish() {
                return result;
            }
            if Instant::now() >= deadline {
                return Err(RenderError::Readback("the mapped buffer never became available".into()));
            }
            wait_for_submission(&self.gpu.device, None)?;
        }
    }
}

/// A copy of accumulators on its way back from the device (see `Renderer::begin_readback`).
pub struct PendingReadback {
    staging: wgpu::Buffer,
    rx: std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
    submission: wgpu::SubmissionIndex,
    /// Samples per pixel submitted before the copy: every pixel read holds exactly these
    /// (`None` for a single-pixel probe, which reports the pixel's own count).
    pub spp: Option<u64>,
}

impl PendingReadback {
    /// The pixels once the copy is mapped, `None` while it is not (the caller polls the
    /// device). The sample count of every pixel is checked against `spp`.
    pub fn try_finish(&self) -> Option<Result<Vec<AccumPixel>, RenderError>> {
        let mapped = match self.rx.try_recv() {
            Ok(r) => r,
            Err(std::sync::mpsc::TryRecvError::Empty) => return None,
            Err(e) => return Some(Err(RenderError::Readback(e.to_string()))),
        };
        Some(mapped.map_err(|e| RenderError::Readback(e.to_string())).and_then(|()| {
            let pixels: Vec<AccumPixel> = {
                let view = self.staging.get_mapped_range(..).map_err(|e| RenderError::Readback(e.to_string()))?;
                bytemuck::pod_collect_to_vec(&view)
            };
            self.staging.unmap();
            if let Some(spp) = self.spp {
                check_counts(&pixels, spp)?;
            }
            Ok(pixels)
        }))
    }
}

/// Every pixel must hold exactly the samples submitted: a driver that drops work is
/// reported, never averaged in.
fn check_counts(pixels: &[AccumPixel], spp: u64) -> Result<(), RenderError> {
    match pixels.iter().enumerate().find(|(_, p)| p.count as u64 != spp % (1 << 32)) {
        Some((i, p)) => Err(RenderError::Readback(format!(
            "pixel {i} accumulated {} samples, expected {spp}: the device dropped work",
            p.count
        ))),
        None => Ok(()),
    }
}
