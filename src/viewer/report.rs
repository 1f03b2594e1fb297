//! What the window reached, for `--log-stats` (one JSON line when it closes): per method spp,
//! render seconds, samples per second and metrics; frames per second; where the image, divider
//! and plot were in the window's pixels; the last scene error.

use std::path::PathBuf;

use serde::Serialize;

use super::driver::Driver;

/// What a method reached.
#[derive(Debug, Clone, Serialize)]
pub struct SlotReport {
    pub method: String,
    pub spp: u64,
    pub render_seconds: f64,
    /// Pixel samples per second of the render time this method was given.
    pub samples_per_second: f64,
    pub rel_mse: Option<f64>,
    pub psnr: Option<f64>,
    pub ssim: Option<f64>,
    /// True when rel_mse and psnr are estimates from the sample variance (no reference).
    pub estimated: bool,
}

/// The window's final state. Rectangles are in physical pixels of the window: x0, y0, x1, y1.
#[derive(Debug, Clone, Serialize, Default)]
pub struct ViewerReport {
    pub adapter: String,
    pub frames: u64,
    /// UI frames per second, and pixel samples per second of all methods together, both over
    /// the frames after the first two (which compile pipelines and upload fonts).
    pub frames_per_second: f64,
    pub samples_per_second: f64,
    pub width: u32,
    pub height: u32,
    pub slots: Vec<SlotReport>,
    pub window: [u32; 2],
    pub image_rect: [f32; 4],
    /// The split view's divider (x in physical pixels), when split.
    pub divider_x: Option<f32>,
    pub plot_rect: Option<[f32; 4]>,
    pub view: String,
    /// The error of the last failed scene reload, if it has not been fixed since.
    pub scene_error: Option<String>,
    pub screenshot: Option<PathBuf>,
}

/// Where things were in the last frame, in points.
#[derive(Debug, Clone, Copy)]
pub struct Layout {
    pub pixels_per_point: f32,
    pub screen: egui::Rect,
    pub image_rect: egui::Rect,
    pub divider_x: Option<f32>,
    pub plot_rect: Option<egui::Rect>,
}

impl Default for Layout {
    fn default() -> Layout {
        Layout { pixels_per_point: 1.0, screen: egui::Rect::NOTHING, image_rect: egui::Rect::NOTHING, divider_x: None, plot_rect: None }
    }
}

/// The report of `driver` after `frames` frames laid out as `layout`.
pub fn report(
    driver: &Driver,
    layout: &Layout,
    frames: u64,
    view: &str,
    scene_error: Option<String>,
    screenshot: Option<PathBuf>,
) -> ViewerReport {
    let ppp = layout.pixels_per_point;
    let px = |r: egui::Rect| [r.min.x * ppp, r.min.y * ppp, r.max.x * ppp, r.max.y * ppp];
    let screen = layout.screen;
    let t = driver.throughput;
    ViewerReport {
            adapter: driver.gpu.info.name.clone(),
            frames,
            frames_per_second: if t.seconds > 0.0 { t.frames as f64 / t.seconds } else { 0.0 },
            samples_per_second: if t.seconds > 0.0 { t.pixel_samples / t.seconds } else { 0.0 },
            width: driver.scene.render.width,
            height: driver.scene.render.height,
            slots: driver
                .slots
                .iter()
                .map(|s| SlotReport {
                    method: s.method.name(),
                    spp: s.spp(),
                    render_seconds: s.seconds,
                    samples_per_second: s.samples_per_second(),
                    rel_mse: s.latest.map(|p| p.rel_mse),
                    psnr: s.latest.map(|p| p.psnr),
                    ssim: s.latest.and_then(|p| p.ssim),
                    estimated: s.latest.is_none_or(|p| p.estimated),
                })
                .collect(),
            window: [(screen.width() * ppp).round() as u32, (screen.height() * ppp).round() as u32],
            image_rect: px(layout.image_rect),
            divider_x: layout.divider_x.map(|x| x * ppp),
            plot_rect: layout.plot_rect.map(px),
            view: view.to_string(),
            scene_error,
            screenshot,
        }
}
