//! The render driver: one or two methods converging on the same scene, each with its own
//! accumulator (`Slot`). Every UI frame it submits as many samples per pixel as fit the frame
//! budget to one slot (in the split view the slots take turns, so they share the device by time,
//! not by samples), runs the display pass into that slot's texture, and collects live metrics
//! and mouse-over probes from asynchronous readbacks. Nothing here waits on the device.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::display::DisplayTransform;
use crate::gpu::{Gpu, PathTracerPipelines};
use crate::method::Method;
use crate::output::{write_exr, write_rgb8_png};
use crate::render::{ImageHeader, PendingReadback, RenderError, Renderer};
use crate::film::Film;
use crate::scene::Scene;

use super::frame_budget::FrameBudget;
use super::display_pass::{read_shown_rgb8, DisplayPass, GpuReference, ShownImage};
use crate::display::View;
use super::live_metrics::{LivePoint, MetricsTask};
use super::plot::Curves;

/// Metrics take at most about this fraction of the time between two points (they run on a
/// worker thread, but on a software rasteriser that thread competes with the renderer).
const METRICS_DUTY: f64 = 0.1;
/// Longest interval between two points of a curve.
const MAX_METRICS_INTERVAL: Duration = Duration::from_secs(3);
/// Shortest interval between two points of a curve.
const MIN_METRICS_INTERVAL: Duration = Duration::from_millis(400);

/// What the user chose to see.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewSettings {
    pub view: View,
    pub display: DisplayTransform,
}

/// One method converging: its renderer, shown image and clock.
pub struct Slot {
    pub method: Method,
    pub seed: u32,
    renderer: Renderer,
    pub image: ShownImage,
    /// The egui texture showing `image` (registered by the app), and whether it must be
    /// pointed at a new `image` (after a rebuild).
    pub texture_id: Option<egui::TextureId>,
    pub texture_stale: bool,
    /// Render time this slot was given: the wall time of the frames that rendered it.
    pub seconds: f64,
    /// Its curve in the plot.
    pub curve: usize,
    /// Samples per pixel per frame, adapted to the frame budget; below 1, the share of the
    /// rows one frame renders.
    budget: FrameBudget,
    /// Samples per pixel of a pass spread over frames (several per invocation amortise the
    /// kernel's per-pixel work).
    pass: u32,
    /// The display pass must run (new samples or new view settings).
    dirty: bool,
    /// What one display pass of this image costs (measured once), and when it last ran: the
    /// image is refreshed at most so often that the pass takes `DISPLAY_SHARE` of the time.
    display_cost: Duration,
    last_display: Instant,
    readback: Option<(PendingReadback, f64)>,
    metrics: Option<MetricsTask>,
    next_metrics: Instant,
    pub latest: Option<LivePoint>,
}

impl Slot {
    pub fn spp(&self) -> u64 {
        self.renderer.spp()
    }

    /// Pixel samples per second of render time.
    pub fn samples_per_second(&self) -> f64 {
        let (w, h) = self.renderer.size();
        if self.seconds > 0.0 { self.spp() as f64 * w as f64 * h as f64 / self.seconds } else { 0.0 }
    }
}

/// A pixel's statistics under the mouse.
#[derive(Debug, Clone, Copy)]
pub struct Probe {
    pub slot: usize,
    pub x: u32,
    pub y: u32,
    pub spp: u64,
    pub mean: [f32; 3],
    /// Standard error of the mean per channel.
    pub stderr: [f32; 3],
}

/// Throughput since the driver started (after the first frames, which compile and warm up).
#[derive(Debug, Clone, Copy, Default)]
pub struct Throughput {
    pub frames: u64,
    pub seconds: f64,
    pub pixel_samples: f64,
}

pub struct Driver {
    pub gpu: Gpu,
    pipelines: PathTracerPipelines,
    display: DisplayPass,
    pub scene: Scene,
    reference: Option<(Arc<Film>, GpuReference)>,
    pub slots: Vec<Slot>,
    /// The slot that renders this frame (split view: they alternate).
    turn: usize,
    /// The slot that rendered the previous frame, and when that frame started.
    last_frame: Option<(Instant, Option<usize>)>,
    frame_target: Duration,
    pub curves: Curves,
    probe_pending: Option<(usize, u32, u32, PendingReadback)>,
    pub probe: Option<Probe>,
    last_settings: Option<ViewSettings>,
    /// Frames run, and throughput measured from the third frame on.
    pub frames: u64,
    pub throughput: Throughput,
    /// Textures of removed slots, for the app to free.
    pub released_textures: Vec<egui::TextureId>,
}

/// The display pass may take at most this share of the time: on a software rasteriser a large
/// image is refreshed less often than the UI (1024x512 on lavapipe: a 32 ms pass, ~4 times a
/// second), on a GPU every frame.
const DISPLAY_SHARE: f64 = 0.15;

/// Samples per pixel of a pass spread over frames.
const PARTIAL_PASS_SAMPLES: u32 = 8;

/// Most samples per pixel one frame may add.
const MAX_SAMPLES_PER_FRAME: f64 = 65536.0;

/// Frames left out of the throughput (pipeline compilation, first texture uploads).
const WARM_UP_FRAMES: u64 = 2;

impl Driver {
    pub fn new(gpu: Gpu, scene: Scene, methods: &[Method], seed: u32, reference: Option<Film>, frame_target: Duration) -> Result<Driver, RenderError> {
        let pipelines = PathTracerPipelines::new(&gpu);
        let display = DisplayPass::new(&gpu.device, &gpu.queue);
        let reference = reference.map(|film| {
            let on_device = GpuReference::new(&gpu.device, &gpu.queue, &film);
            (Arc::new(film), on_device)
        });
        let mut driver = Driver {
            gpu,
            pipelines,
            display,
            scene,
            reference,
            slots: Vec::new(),
            turn: 0,
            last_frame: None,
            frame_target,
            curves: Curves::default(),
            probe_pending: None,
            probe: None,
            last_settings: None,
            frames: 0,
            throughput: Throughput::default(),
            released_textures: Vec::new(),
        };
        for (i, &method) in methods.iter().enumerate() {
            let slot = driver.new_slot(method, seed.wrapping_add(i as u32))?;
            driver.slots.push(slot);
        }
        Ok(driver)
    }

    pub fn reference(&self) -> Option<&Film> {
        self.reference.as_ref().map(|(f, _)| f.as_ref())
    }

    /// True when the reference has the image's size (error views and true metrics work).
    pub fn reference_matches(&self) -> bool {
        self.reference().is_some_and(|r| (r.width, r.height) == (self.scene.render.width, self.scene.render.height))
    }

    fn new_slot(&mut self, method: Method, seed: u32) -> Result<Slot, RenderError> {
        let renderer = Renderer::new(&self.gpu, &self.pipelines, &self.scene, method, seed)?;
        let pass = PARTIAL_PASS_SAMPLES.min(renderer.max_samples_per_dispatch()).max(1);
        let rows = self.scene.render.height;
        let image = self.display.shown_image(&self.gpu.device, &renderer, self.reference.as_ref().map(|(_, r)| r));
        // One display pass, timed (it also compiles the display pipeline on first use).
        self.gpu.wait_idle()?;
        let start = Instant::now();
        self.display.run(&self.gpu.device, &self.gpu.queue, &image, View::Radiance, DisplayTransform::default());
        self.gpu.wait_idle()?;
        let display_cost = start.elapsed();
        let curve = self.curves.start(&method.name());
        Ok(Slot {
            method,
            seed,
            renderer,
            image,
            texture_id: None,
            texture_stale: true,
            seconds: 0.0,
            curve,
            budget: FrameBudget::new(self.frame_target, rows, pass, pass as f64 * (8.0 / rows as f64).min(1.0), MAX_SAMPLES_PER_FRAME),
            pass,
            dirty: true,
            display_cost,
            last_display: Instant::now(),
            readback: None,
            metrics: None,
            next_metrics: Instant::now(),
            latest: None,
        })
    }

    /// Restarts slot `i` with `method` (the pipeline comes from the cache when seen before).
    /// On error the slot keeps converging as it was.
    pub fn set_method(&mut self, i: usize, method: Method) -> Result<(), RenderError> {
        let mut slot = self.new_slot(method, self.slots[i].seed)?;
        slot.texture_id = self.slots[i].texture_id;
        self.slots[i] = slot;
        self.probe = None;
        Ok(())
    }

    /// Restarts every slot (a new curve each).
    pub fn reset(&mut self) -> Result<(), RenderError> {
        let methods: Vec<(Method, u32)> = self.slots.iter().map(|s| (s.method, s.seed)).collect();
        let mut slots = Vec::new();
        for (i, (method, seed)) in methods.into_iter().enumerate() {
            let mut slot = self.new_slot(method, seed)?;
            slot.texture_id = self.slots[i].texture_id;
            slots.push(slot);
        }
        self.slots = slots;
        self.probe = None;
        self.probe_pending = None;
        Ok(())
    }

    /// Replaces the scene (a reload, or a new size or depth) and restarts every slot; on error
    /// the previous scene stays.
    pub fn set_scene(&mut self, scene: Scene) -> Result<(), RenderError> {
        let previous = std::mem::replace(&mut self.scene, scene);
        if let Err(e) = self.reset() {
            self.scene = previous;
            return Err(e);
        }
        Ok(())
    }

    /// Shows one method, or two side by side (the second starts as `second`).
    pub fn set_split(&mut self, second: Option<Method>) -> Result<(), RenderError> {
        match second {
            Some(method) if self.slots.len() == 1 => {
                let seed = self.slots[0].seed.wrapping_add(1);
                let slot = self.new_slot(method, seed)?;
                self.slots.push(slot);
            }
            None => {
                for slot in self.slots.drain(1..) {
                    self.released_textures.extend(slot.texture_id);
                }
            }
            _ => {}
        }
        self.turn = 0;
        Ok(())
    }

    /// One UI frame's work: account the time of the previous frame, submit samples to the
    /// slot whose turn it is, run the display pass where needed, collect finished readbacks.
    pub fn frame(&mut self, settings: ViewSettings, paused: bool) -> Result<(), RenderError> {
        let now = Instant::now();
        if let Some((start, rendered)) = self.last_frame {
            let dt = (now - start).as_secs_f64();
            if let Some(i) = rendered.filter(|&i| i < self.slots.len()) {
                let slot = &mut self.slots[i];
                slot.seconds += dt;
                slot.budget.record(dt);
            }
            if self.frames > WARM_UP_FRAMES {
                self.throughput.seconds += dt;
                self.throughput.frames += 1;
            }
        }
        let mut rendered = None;
        if !paused && !self.slots.is_empty() {
            let i = self.turn % self.slots.len();
            self.turn = (i + 1) % self.slots.len();
            let slot = &mut self.slots[i];
            let (w, h) = slot.renderer.size();
            let k = slot.budget.next();
            let mut pixel_samples = 0.0;
            if k == 0.0 {
                // A frame that measures the UI alone.
            } else if k < slot.pass as f64 || slot.renderer.pass_in_progress() {
                // Less than a pass fits the frame: a share of the rows of a pass spread over
                // frames, or the rest of a pass in progress.
                let pass = slot.pass as f64;
                let rows = if k < pass { (k / pass * h as f64).round() as u32 } else { h };
                let done = slot.renderer.submit_partial(slot.pass, rows)?;
                slot.budget.rendered_instead(done as f64 / h as f64 * pass);
                pixel_samples += done as f64 * w as f64 * pass;
            } else {
                // Whole passes, in dispatches the device allows (lavapipe's loop limit).
                let mut left = k.round() as u32;
                let per_dispatch = slot.renderer.max_samples_per_dispatch().max(1);
                while left > 0 {
                    let n = left.min(per_dispatch);
                    slot.renderer.submit(n)?;
                    left -= n;
                }
                pixel_samples += k.round() * w as f64 * h as f64;
            }
            slot.dirty |= k > 0.0;
            rendered = Some(i);
            if self.frames >= WARM_UP_FRAMES {
                self.throughput.pixel_samples += pixel_samples;
            }
        }
        self.frames += 1;
        self.last_frame = Some((now, rendered));

        let settings_changed = self.last_settings != Some(settings);
        self.last_settings = Some(settings);
        for slot in &mut self.slots {
            let due = now.duration_since(slot.last_display) >= slot.display_cost.div_f64(DISPLAY_SHARE);
            if settings_changed || (slot.dirty && due) {
                self.display.run(&self.gpu.device, &self.gpu.queue, &slot.image, settings.view, settings.display);
                slot.dirty = false;
                slot.last_display = now;
            }
        }
        self.collect(settings.display);
        Ok(())
    }

    /// Advances readbacks and metric tasks without blocking.
    fn collect(&mut self, display: DisplayTransform) {
        let _ = self.gpu.device.poll(wgpu::PollType::Poll);
        let reference = self.reference_matches().then(|| self.reference.as_ref().map(|(f, _)| f.clone())).flatten();
        let now = Instant::now();
        for slot in &mut self.slots {
            if let Some(task) = &slot.metrics {
                if let Some(done) = task.try_finish() {
                    self.curves.push(slot.curve, done.point);
                    slot.latest = Some(done.point);
                    slot.metrics = None;
                    slot.next_metrics = now + done.cost.div_f64(METRICS_DUTY).clamp(MIN_METRICS_INTERVAL, MAX_METRICS_INTERVAL);
                }
            }
            if let Some((pending, seconds)) = &slot.readback {
                match pending.try_finish() {
                    Some(Ok(pixels)) => {
                        let spp = pending.spp.unwrap_or_default();
                        slot.metrics = Some(MetricsTask::spawn(pixels, slot.renderer.size(), spp, *seconds, reference.clone(), display));
                        slot.readback = None;
                    }
                    Some(Err(_)) => slot.readback = None,
                    None => {}
                }
            } else if slot.metrics.is_none() && now >= slot.next_metrics && slot.spp() >= 2 && !slot.renderer.pass_in_progress() {
                slot.readback = Some((slot.renderer.begin_readback(), slot.seconds));
            }
        }
        if let Some((i, x, y, pending)) = &self.probe_pending {
            if let Some(result) = pending.try_finish() {
                if let Some(p) = result.ok().filter(|p| p.len() == 1) {
                    let spp = p[0].count as u64;
                    let film = Film::from_accumulators(1, 1, spp, &p);
                    self.probe = Some(Probe {
                        slot: *i,
                        x: *x,
                        y: *y,
                        spp,
                        mean: film.mean[0],
                        stderr: film.variance[0].map(f32::sqrt),
                    });
                }
                self.probe_pending = None;
            }
        }
    }

    /// Asks for the statistics of pixel (x, y) of slot `i` (answered in a later frame).
    pub fn request_probe(&mut self, i: usize, x: u32, y: u32) {
        if self.probe_pending.is_none() {
            if let Some(pending) = self.slots.get(i).and_then(|s| s.renderer.begin_read_pixel(x, y)) {
                self.probe_pending = Some((i, x, y, pending));
            }
        }
    }

    /// Saves every slot: an EXR of the mean and variance (spp, method, seed, ... in the
    /// header, as `pathlab render` writes) and a PNG of what is shown. Blocks for the readbacks.
    pub fn save(&mut self, dir: &Path, view: View) -> Result<Vec<PathBuf>, String> {
        // A pass spread over frames is finished first: every pixel then has the same count.
        for slot in &mut self.slots {
            if slot.renderer.pass_in_progress() {
                let h = slot.renderer.size().1;
                slot.renderer.submit_partial(1, h).map_err(|e| e.to_string())?;
            }
        }
        let stem = self.scene.path.file_stem().and_then(|s| s.to_str()).unwrap_or("view").to_string();
        let mut written = Vec::new();
        for slot in &self.slots {
            let readback = slot.renderer.readback().map_err(|e| e.to_string())?;
            let spp = slot.spp();
            let name = format!("{stem}-{}-{spp}spp", slot.method.name().replace('/', "-"));
            let header = ImageHeader {
                method: slot.method,
                seed: slot.seed,
                max_depth: self.scene.render.max_depth,
                rr_depth: self.scene.render.rr_depth,
                spp,
                rays: readback.rays,
                render_seconds: slot.seconds,
                scene_hash: self.scene.content_hash(),
                scene: Some(self.scene.path.clone()),
                display: Some(self.scene.display),
                adapter: Some(self.gpu.info.name.clone()),
                techniques: crate::scene::technique::stamp(&slot.method, &self.scene.techniques),
                technique_faults: Some(readback.faults),
            };
            let metadata = header.metadata(&[("source", "pathlab view".into())]);
            let exr = dir.join(format!("{name}.exr"));
            write_exr(&exr, &readback.film, &metadata, true).map_err(|e| e.to_string())?;
            written.push(exr);
            let shown = read_shown_rgb8(&self.gpu.device, &self.gpu.queue, &slot.image)?;
            let png = match view {
                View::Radiance => dir.join(format!("{name}.png")),
                other => dir.join(format!("{name}-{}.png", other.name())),
            };
            write_rgb8_png(&png, slot.image.width, slot.image.height, shown).map_err(|e| e.to_string())?;
            written.push(png);
        }
        Ok(written)
    }
}
