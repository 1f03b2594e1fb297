//! `pathlab view`: a window (eframe/egui on the same wgpu device as the path tracer) where an
//! image converges progressively, methods switch live, two methods converge side by side at
//! equal time, and the error is plotted against time.
//!
//! - `app`: the application state, keyboard, and what happens each frame;
//! - `panel`: the side panel's layout (method, render, display, metrics, save);
//! - `image_view`: the image area (fit, split divider, mouse-over pixel probe, error banner);
//! - `driver`: the render driver (equal-time sharing, asynchronous readbacks);
//! - `frame_budget`: how many samples per pixel a frame may add (UI cost vs sample cost);
//! - `display_pass`: accumulators to the shown texture on the device (`shaders/display.wgsl`);
//! - `live_metrics`: PSNR, SSIM, relMSE (or their estimates) off the UI thread;
//! - `plot`: relMSE against seconds, log-log, one curve per method run;
//! - `scene_watch`: reloading the scene file when it changes;
//! - `script`: `--frames N --screenshot`; `report`: what `--log-stats` prints.

mod app;
pub mod display_pass;
pub mod driver;
pub mod frame_budget;
mod image_view;
pub mod live_metrics;
mod panel;
pub mod plot;
pub mod report;
pub mod scene_watch;
mod script;

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use std::time::Duration;


use crate::display::DisplayTransform;
use crate::method::Method;
use crate::film::Film;
use crate::scene::Scene;

pub use crate::display::View;

/// Everything `pathlab view` was asked for.
#[derive(Clone)]
pub struct ViewerOptions {
    /// The scene as loaded (overrides applied) and the overrides, re-applied on every reload.
    pub scene: Scene,
    pub size: Option<(u32, u32)>,
    pub max_depth: Option<u32>,
    /// `--define`s of a Mitsuba scene, re-applied on every reload.
    pub defines: Vec<(String, String)>,
    /// `Some(rr)`: Russian roulette as `rr` (`render.rr_depth`) whatever the scene says.
    pub rr_depth: Option<Option<u32>>,
    pub method: Method,
    /// Start in the split view with this method on the right.
    pub compare: Option<Method>,
    pub seed: u32,
    /// A reference image of the scene's size (error views and true metrics).
    pub reference: Option<Film>,
    pub display: DisplayTransform,
    pub view: View,
    /// Inner size of the window in points.
    pub window: (u32, u32),
    /// Exit after this many UI frames (with `screenshot`, save the window's pixels first).
    pub frames: Option<u64>,
    pub screenshot: Option<PathBuf>,
    /// Where `S` saves.
    pub save_dir: PathBuf,
    /// Frame time the renderer's share is adapted to.
    pub frame_budget: Duration,
    /// Open paused.
    pub paused: bool,
    /// Adapter name filter (as `--adapter` / PATHLAB_ADAPTER).
    pub adapter: Option<String>,
    /// Where the window's notices go (saves, reloads, errors of actions).
    pub reporter: Arc<dyn crate::progress::Reporter + Send + Sync>,
}

pub use report::{SlotReport, ViewerReport};

#[derive(Debug, thiserror::Error)]
pub enum ViewerError {
    #[error(
        "no display: neither DISPLAY nor WAYLAND_DISPLAY is set, so no window can open.\n\
         Render without a window instead:  pathlab render SCENE.toml\n\
         (or run the viewer under a virtual display: xvfb-run pathlab view SCENE.toml)"
    )]
    NoDisplay,
    #[error(
        "cannot open a window: {0}\n\
         Is the X server (DISPLAY) reachable? Without a display, use `pathlab render SCENE.toml`."
    )]
    Window(String),
    #[error("the viewer could not start: {0}")]
    Start(String),
    #[error("cannot save the screenshot: {0}")]
    Screenshot(String),
}

/// True when a display server is named in the environment (always on non-Unix systems).
fn display_available() -> bool {
    if cfg!(all(unix, not(target_os = "macos"))) {
        let set = |k: &str| std::env::var_os(k).is_some_and(|v| !v.is_empty());
        set("DISPLAY") || set("WAYLAND_DISPLAY")
    } else {
        true
    }
}

/// The wgpu setup of the window: the same backends as the headless commands (Vulkan, Metal,
/// DX12), the adapter's full limits (the path tracer's accumulators want large storage
/// bindings) and timestamp queries when there are any.
fn wgpu_setup(adapter_filter: Option<String>) -> eframe::egui_wgpu::WgpuSetup {
    use eframe::egui_wgpu::{WgpuSetup, WgpuSetupCreateNew};
    let mut setup = WgpuSetupCreateNew::without_display_handle();
    setup.instance_descriptor.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    setup.device_descriptor = Arc::new(|adapter: &wgpu::Adapter| wgpu::DeviceDescriptor {
        label: Some("pathlab view"),
        required_features: adapter.features() & wgpu::Features::TIMESTAMP_QUERY,
        required_limits: adapter.limits(),
        ..Default::default()
    });
    let filter = adapter_filter.or_else(|| std::env::var(crate::gpu::ADAPTER_ENV).ok()).filter(|s| !s.is_empty());
    if let Some(filter) = filter {
        let needle = filter.to_lowercase();
        setup.native_adapter_selector = Some(Arc::new(move |adapters: &[wgpu::Adapter], surface: Option<&wgpu::Surface<'_>>| {
            adapters
                .iter()
                .filter(|a| surface.is_none_or(|s| a.is_surface_supported(s)))
                .find(|a| a.get_info().name.to_lowercase().contains(&needle))
                .cloned()
                .ok_or_else(|| format!("no adapter that can draw to the window has a name containing \"{filter}\""))
        }));
    }
    WgpuSetup::CreateNew(setup)
}

/// Opens the window and runs until it is closed (or `frames` have been shown).
pub fn run(options: ViewerOptions) -> Result<ViewerReport, ViewerError> {
    if !display_available() {
        return Err(ViewerError::NoDisplay);
    }
    let title = format!("pathlab view — {}", options.scene.path.display());
    let (w, h) = options.window;
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_inner_size([w as f32, h as f32]).with_title(title),
        renderer: eframe::Renderer::Wgpu,
        // Exact pixels: the image is the display pass's output, not dithered.
        dithering: false,
        wgpu_options: eframe::egui_wgpu::WgpuConfiguration {
            wgpu_setup: wgpu_setup(options.adapter.clone()),
            // One frame queued at most: a frame's time is its own work (the budget control
            // measures it), and input is answered by the next frame.
            surface: eframe::egui_wgpu::SurfaceConfig::LOW_LATENCY,
            ..Default::default()
        },
        ..Default::default()
    };
    let report: Arc<Mutex<ViewerReport>> = Arc::new(Mutex::new(ViewerReport::default()));
    let failure: Arc<Mutex<Option<ViewerError>>> = Arc::new(Mutex::new(None));
    let (report_out, failure_out) = (report.clone(), failure.clone());
    let result = eframe::run_native(
        "pathlab view",
        native,
        Box::new(move |cc| {
            let app = app::ViewerApp::new(cc, options, report_out, failure_out).map_err(|e| e.to_string())?;
            Ok(Box::new(app))
        }),
    );
    if let Some(e) = failure.lock().unwrap_or_else(|e| e.into_inner()).take() {
        return Err(e);
    }
    match result {
        Ok(()) => Ok(report.lock().unwrap_or_else(|e| e.into_inner()).clone()),
        Err(eframe::Error::AppCreation(e)) => Err(ViewerError::Start(e.to_string())),
        Err(e @ (eframe::Error::Winit(_) | eframe::Error::WinitEventLoop(_))) => Err(ViewerError::Window(e.to_string())),
        Err(e) => Err(ViewerError::Start(e.to_string())),
    }
}
