//! The scripted run of `--frames N [--screenshot out.png]`: after N frames, the next frame's
//! framebuffer is captured (egui's screenshot of the real window, not a re-render), saved, and
//! the window closes. Used by the tests and to make the README's screenshot.

use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use egui::ColorImage;

use super::ViewerError;

/// What the script wants after a frame.
pub enum Step {
    /// Keep showing frames.
    Continue,
    /// Close the window; the screenshot saved, if one was asked for.
    Close(Option<PathBuf>),
    /// The screenshot could not be saved.
    Failed(ViewerError),
}

pub struct Script {
    frames: Option<u64>,
    screenshot_path: Option<PathBuf>,
    screenshot: Arc<Mutex<Option<Arc<ColorImage>>>>,
    requested: bool,
}

impl Script {
    pub fn new(frames: Option<u64>, screenshot_path: Option<PathBuf>) -> Script {
        Script { frames, screenshot_path, screenshot: Arc::new(Mutex::new(None)), requested: false }
    }

    /// True when the window runs a fixed number of frames (it then renders even when paused).
    pub fn is_scripted(&self) -> bool {
        self.frames.is_some()
    }

    /// Called after each frame with the number of frames shown so far.
    pub fn after_frame(&mut self, ctx: &egui::Context, frames_seen: u64) -> Step {
        let Some(limit) = self.frames else { return Step::Continue };
        if frames_seen < limit {
            return Step::Continue;
        }
        let Some(path) = &self.screenshot_path else { return Step::Close(None) };
        if !self.requested {
            self.requested = true;
            let slot = self.screenshot.clone();
            ctx.request_screenshot(move |image| {
                *slot.lock().unwrap_or_else(|e| e.into_inner()) = Some(image);
            });
            return Step::Continue;
        }
        let Some(image) = self.screenshot.lock().unwrap_or_else(|e| e.into_inner()).take() else { return Step::Continue };
        let rgb: Vec<u8> = image.pixels.iter().flat_map(|c| [c.r(), c.g(), c.b()]).collect();
        let [w, h] = image.size;
        match crate::output::write_rgb8_png(path, w as u32, h as u32, rgb) {
            Ok(()) => Step::Close(Some(path.clone())),
            Err(e) => Step::Failed(ViewerError::Screenshot(e.to_string())),
        }
    }
}
