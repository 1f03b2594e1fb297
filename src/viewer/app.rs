//! The application: state, keyboard, and each UI frame's order of work (watch the scene, run
//! the driver, register textures, lay out the panels, then the script (`script`) and the report
//! (`report`)).

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use egui::Key;

use crate::display::DisplayTransform;
use crate::gpu::Gpu;
use crate::method::{Method, Preset};
use crate::scene::Scene;

use crate::display::View;
use super::driver::{Driver, ViewSettings};
use super::scene_watch::SceneWatch;
use super::panel::{Action, Notice, PanelState};
use super::report::Layout;
use super::script::{Script, Step};
use super::{image_view, panel, ViewerError, ViewerOptions, ViewerReport};
use crate::progress::Reporter;

pub struct ViewerApp {
    pub driver: Driver,
    pub watch: SceneWatch,
    /// Overrides re-applied to every reload (from the command line, then the panel).
    pub size: Option<(u32, u32)>,
    pub max_depth: Option<u32>,
    pub rr_depth: Option<Option<u32>>,
    pub view: View,
    pub display: DisplayTransform,
    pub paused: bool,
    pub show_help: bool,
    /// Split view: where the divider is, as a fraction of the image width.
    pub divider: f32,
    /// The method the right half starts with when the split view is turned on.
    pub compare: Method,
    /// Last failed scene reload (file:line:col: message), shown until a reload succeeds.
    pub scene_error: Option<String>,
    pub notice: Option<Notice>,
    pub save_dir: PathBuf,
    /// Width and height fields of the panel (applied with its button).
    pub pending_size: (u32, u32),
    /// `--frames` / `--screenshot`.
    script: Script,
    frames_seen: u64,
    /// Where things were in the last frame, for the report.
    layout: Layout,
    reporter: Arc<dyn Reporter + Send + Sync>,
    report: Arc<Mutex<ViewerReport>>,
    failure: Arc<Mutex<Option<ViewerError>>>,
}

impl ViewerApp {
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        options: ViewerOptions,
        report: Arc<Mutex<ViewerReport>>,
        failure: Arc<Mutex<Option<ViewerError>>>,
    ) -> Result<ViewerApp, ViewerError> {
        let rs = cc.wgpu_render_state.as_ref().ok_or_else(|| ViewerError::Start("eframe did not start its wgpu renderer".into()))?;
        // The path tracer runs on the window's device (shared handles: every renderer owns a clone).
        let gpu = Gpu {
            device: rs.device.clone(),
            queue: rs.queue.clone(),
            info: rs.adapter.get_info(),
            limits: rs.device.limits(),
            features: rs.device.features(),
        };
        let adapter_name = gpu.info.name.clone();
        let mut methods = vec![options.method];
        methods.extend(options.compare);
        let scene_path = options.scene.path.clone();
        // Stamped before anything is announced: a change made once the window says it is up
        // is always seen as a change.
        let watch = SceneWatch::new(&scene_path, &options.defines);
        let pending_size = (options.scene.render.width, options.scene.render.height);
        let driver = Driver::new(gpu, options.scene, &methods, options.seed, options.reference, options.frame_budget)
            .map_err(|e| ViewerError::Start(e.to_string()))?;
        let compare = options.compare.unwrap_or(if options.method == Preset::Plain.method() { Preset::Mis.method() } else { Preset::Plain.method() });
        options.reporter.note(&format!(
            "pathlab view: {} ({}x{}), {} on {}",
            scene_path.display(),
            pending_size.0,
            pending_size.1,
            methods.iter().map(Method::name).collect::<Vec<_>>().join(" | "),
            adapter_name
        ));
        Ok(ViewerApp {
            driver,
            watch,
            size: options.size,
            max_depth: options.max_depth,
            rr_depth: options.rr_depth,
            view: options.view,
            display: options.display,
            paused: options.paused,
            show_help: false,
            divider: 0.5,
            compare,
            scene_error: None,
            notice: None,
            save_dir: options.save_dir,
            pending_size,
            script: Script::new(options.frames, options.screenshot),
            frames_seen: 0,
            layout: Layout::default(),
            reporter: options.reporter,
            report,
            failure,
        })
    }

    pub fn notify(&mut self, text: impl Into<String>, error: bool) {
        let text = text.into();
        self.reporter.note(&format!("pathlab view: {text}"));
        self.notice = Some(Notice { text, error, since: Instant::now() });
    }

    /// The scene with this window's overrides applied.
    fn with_overrides(&self, mut scene: Scene) -> Scene {
        // The researchers' techniques given on the command line stay loaded across reloads.
        if scene.techniques.is_empty() {
            scene.techniques = self.driver.scene.techniques.clone();
        }
        if let Some((w, h)) = self.size {
            scene.render.width = w;
            scene.render.height = h;
        }
        if let Some(d) = self.max_depth {
            scene.render.max_depth = d;
        }
        if let Some(rr) = self.rr_depth {
            scene.render.rr_depth = rr;
        }
        scene
    }

    /// Rebuilds with the current scene and overrides (after a change of size or depth).
    pub fn apply_overrides(&mut self) {
        let scene = self.with_overrides(self.driver.scene.clone());
        if let Err(e) = self.driver.set_scene(scene) {
            self.notify(format!("cannot render with these settings: {e}"), true);
        }
        self.pending_size = (self.driver.scene.render.width, self.driver.scene.render.height);
    }

    pub fn set_method(&mut self, slot: usize, method: Method) {
        if slot < self.driver.slots.len() && self.driver.slots[slot].method != method {
            if let Err(e) = self.driver.set_method(slot, method) {
                self.notify(format!("cannot use {}: {e}", method.name()), true);
            }
        }
    }

    pub fn set_split(&mut self, on: bool) {
        let second = on.then_some(self.compare);
        if let Err(e) = self.driver.set_split(second) {
            self.notify(format!("cannot start the second method: {e}"), true);
        }
    }

    pub fn reset(&mut self) {
        if let Err(e) = self.driver.reset() {
            self.notify(format!("reset failed: {e}"), true);
        }
    }

    pub fn save(&mut self) {
        match self.driver.save(&self.save_dir, self.view) {
            Ok(files) => {
                let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
                self.notify(format!("saved {}", names.join(", ")), false);
            }
            Err(e) => self.notify(format!("saving failed: {e}"), true),
        }
    }

    /// The views that make sense now (error views need a reference of the image's size).
    pub fn available_views(&self) -> Vec<View> {
        View::ALL.into_iter().filter(|v| !v.needs_reference() || self.driver.reference_matches()).collect()
    }

    /// Carries out what the user did in the panel.
    fn apply(&mut self, action: Action) {
        match action {
            Action::TogglePause => self.paused = !self.paused,
            Action::Reset => self.reset(),
            Action::Save => self.save(),
            Action::Split(on) => self.set_split(on),
            Action::Method(slot, method) => {
                self.set_method(slot, method);
                if slot == 1 {
                    self.compare = method;
                }
            }
            Action::MaxDepth(d) => {
                self.max_depth = Some(d);
                self.apply_overrides();
            }
            Action::Size(size) => {
                let before = (self.driver.scene.render.width, self.driver.scene.render.height);
                self.size = Some(size);
                self.apply_overrides();
                let after = (self.driver.scene.render.width, self.driver.scene.render.height);
                if let Some(reframing) = crate::scene::Reframing::of(before, after, self.driver.scene.camera.projection) {
                    self.notify(reframing.to_string(), false);
                }
            }
            Action::PendingSize(size) => self.pending_size = size,
            Action::View(v) => self.view = v,
            Action::Display(d) => self.display = d,
        }
    }

    fn keyboard(&mut self, ctx: &egui::Context) {
        // Keys belong to a text field while one is being edited.
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let pressed = |key: Key| ctx.input_mut(|i| i.consume_key(egui::Modifiers::NONE, key));
        if pressed(Key::Space) {
            self.paused = !self.paused;
        }
        if pressed(Key::R) {
            self.reset();
        }
        if pressed(Key::S) {
            self.save();
        }
        if pressed(Key::V) {
            let views = self.available_views();
            let i = views.iter().position(|v| *v == self.view).map_or(0, |i| (i + 1) % views.len());
            self.view = views[i];
        }
        if pressed(Key::H) || pressed(Key::F1) {
            self.show_help = !self.show_help;
        }
        if pressed(Key::Escape) {
            self.show_help = false;
        }
        const DIGITS: [Key; 7] = [Key::Num1, Key::Num2, Key::Num3, Key::Num4, Key::Num5, Key::Num6, Key::Num7];
        for (key, preset) in DIGITS.into_iter().zip(Preset::ALL) {
            if pressed(key) {
                self.set_method(0, preset.method());
            }
        }
    }

    /// A reload of the scene file, if it changed.
    fn watch_scene(&mut self) {
        if let Some(result) = self.watch.poll() {
            match result {
                Ok(scene) => {
                    let scene = self.with_overrides(scene);
                    match self.driver.set_scene(scene) {
                        Ok(()) => {
                            self.scene_error = None;
                            self.notify(format!("reloaded {}", self.watch.path().display()), false);
                        }
                        Err(e) => {
                            self.scene_error = Some(e.to_string());
                            self.reporter.note(&format!("pathlab view: reloading the scene failed: {e}"));
                        }
                    }
                }
                Err(e) => {
                    let text = e.to_string();
                    self.reporter.note(&format!("pathlab view: reloading the scene failed (the last good image stays):\n{text}"));
                    self.scene_error = Some(text);
                }
            }
        }
    }

    /// Points each slot's egui texture at its current shown image.
    fn register_textures(&mut self, frame: &eframe::Frame) {
        let Some(rs) = frame.wgpu_render_state() else { return };
        let mut renderer = rs.renderer.write();
        for id in self.driver.released_textures.drain(..) {
            renderer.free_texture(&id);
        }
        for slot in &mut self.driver.slots {
            if !slot.texture_stale {
                continue;
            }
            match slot.texture_id {
                Some(id) => renderer.update_egui_texture_from_wgpu_texture(&rs.device, &slot.image.view, wgpu::FilterMode::Nearest, id),
                None => slot.texture_id = Some(renderer.register_native_texture(&rs.device, &slot.image.view, wgpu::FilterMode::Nearest)),
            }
            slot.texture_stale = false;
        }
    }

    fn close(&mut self, ctx: &egui::Context, screenshot: Option<PathBuf>) {
        self.write_report(screenshot);
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    /// Fills the shared report (read after the window closes) from the last frame's state.
    fn write_report(&self, screenshot: Option<PathBuf>) {
        let mut report = self.report.lock().unwrap_or_else(|e| e.into_inner());
        let screenshot = screenshot.or_else(|| report.screenshot.clone());
        *report = super::report::report(&self.driver, &self.layout, self.frames_seen, self.view.name(), self.scene_error.clone(), screenshot);
    }
}

impl eframe::App for ViewerApp {
    fn on_exit(&mut self) {
        // A window closed by the user (the --frames path has reported already; this keeps its
        // screenshot path).
        self.write_report(None);
    }

    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        if self.driver.gpu.info.device_type == wgpu::DeviceType::Cpu {
            // A software rasteriser pays per triangle: anti-aliasing feathers triple the
            // triangles of every shape (measured on lavapipe at 1280x800: 24.8 -> 31.0 frames
            // per second with the renderer paused). Text stays anti-aliased (font atlas). Set
            // every frame: set once at creation, it did not hold.
            ctx.tessellation_options_mut(|o| o.feathering = false);
        }
        self.layout.pixels_per_point = ctx.pixels_per_point();
        self.layout.screen = ctx.content_rect();
        self.keyboard(&ctx);
        self.watch_scene();
        if !self.available_views().contains(&self.view) {
            self.view = View::Radiance;
        }
        let settings = ViewSettings { view: self.view, display: self.display };
        if let Err(e) = self.driver.frame(settings, self.paused) {
            self.paused = true;
            self.notify(format!("rendering stopped: {e}"), true);
        }
        self.register_textures(frame);

        let state = PanelState {
            driver: &self.driver,
            paused: self.paused,
            view: self.view,
            views: self.available_views(),
            display: self.display,
            pending_size: self.pending_size,
            notice: self.notice.as_ref(),
        };
        let actions = egui::Panel::left("controls").resizable(false).exact_size(300.0).frame(bare(8.0)).show(ui, |ui| panel::show(&state, ui)).inner;
        for action in actions {
            self.apply(action);
        }
        let plot = egui::Panel::bottom("plot").resizable(true).default_size(230.0).frame(bare(4.0)).show(ui, |ui| super::plot::show(ui, &self.driver.curves));
        self.layout.plot_rect = Some(plot.inner);
        let shown = egui::CentralPanel::default()
            .frame(bare(0.0))
            .show(ui, |ui| image_view::show(&self.driver, self.divider, self.scene_error.as_deref(), ui))
            .inner;
        self.layout.image_rect = shown.image_rect;
        self.divider = shown.divider;
        self.layout.divider_x = shown.divider_x;
        if let Some((slot, x, y)) = shown.probe {
            self.driver.request_probe(slot, x, y);
        }
        if self.show_help {
            help_overlay(&ctx);
        }

        self.frames_seen += 1;
        match self.script.after_frame(&ctx, self.frames_seen) {
            Step::Continue => {}
            Step::Close(screenshot) => self.close(&ctx, screenshot),
            Step::Failed(e) => {
                *self.failure.lock().unwrap_or_else(|e| e.into_inner()) = Some(e);
                ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            }
        }
        if self.paused && !self.script.is_scripted() {
            ctx.request_repaint_after(std::time::Duration::from_millis(100));
        } else {
            ctx.request_repaint();
        }
    }
}

/// A panel frame without a fill: the window's clear colour is the background, so a software
/// rasteriser (lavapipe) is not asked to shade every pixel of the window once more per panel.
fn bare(margin: f32) -> egui::Frame {
    egui::Frame::NONE.inner_margin(margin)
}

/// The keys, over the image.
fn help_overlay(ctx: &egui::Context) {
    egui::Window::new("Keys").collapsible(false).resizable(false).anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0]).show(ctx, |ui| {
        egui::Grid::new("keys").num_columns(2).striped(true).show(ui, |ui| {
            let presets: Vec<String> = Preset::ALL.iter().enumerate().map(|(i, p)| format!("{} {}", i + 1, p.name())).collect();
            for (key, what) in [
                ("Space", "pause / resume"),
                ("R", "reset (a new curve per method)"),
                ("S", "save EXR (mean, variance, spp, method, seed) and PNG of what is shown"),
                ("V", "cycle views: radiance, relative std. error, errors vs reference"),
                ("1-7", presets.join(", ").as_str()),
                ("H / F1", "this help (Esc closes)"),
                ("mouse", "hover: pixel mean, std. error, spp; drag the divider in the split view"),
            ] {
                ui.strong(key);
                ui.label(what);
                ui.end_row();
            }
        });
    });
}
