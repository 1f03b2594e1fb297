//! False-colour error images with a colour bar: per-pixel relative squared error on a log10
//! scale (magma), as `pathlab compare --error-map` and the study's image grid show it.

use std::path::Path;

use crate::display::LOG10_RANGE;
use crate::output::{write_rgb8_png, OutputError};

use super::colormap::magma_at;
use super::text::Canvas;


/// The false-colour tile of `values` (w x h, row-major) without a colour bar, RGB8.
pub fn false_colour(values: &[f64]) -> Vec<u8> {
    let (lo, hi) = LOG10_RANGE;
    values.iter().flat_map(|&v| magma_at((v.max(1e-30).log10() - lo) / (hi - lo))).collect()
}

/// The false-colour image of `values` with a labelled colour bar to its right.
pub fn error_map_canvas(values: &[f64], width: u32, height: u32, title: &str) -> Canvas {
    let bar_w = 110u32;
    let canvas_h = height.max(160) + 24;
    let mut canvas = Canvas::new(width + bar_w, canvas_h, [255, 255, 255]);
    canvas.text(4.0, 2.0, 14.0, [0, 0, 0], title);
    canvas.blit(0, 24, width, height, &false_colour(values));
    let (lo, hi) = LOG10_RANGE;
    let (bar_x, bar_top, bar_h) = (width + 10, 30u32, canvas_h - 44);
    for row in 0..bar_h {
        let t = 1.0 - row as f64 / (bar_h - 1).max(1) as f64;
        canvas.fill(bar_x, bar_top + row, 16, 1, magma_at(t));
    }
    for k in (lo as i32)..=(hi as i32) {
        let t = (k as f64 - lo) / (hi - lo);
        let y = bar_top as f32 + (1.0 - t as f32) * (bar_h - 1) as f32;
        canvas.fill(bar_x + 16, y as u32, 4, 1, [0, 0, 0]);
        canvas.text((bar_x + 23) as f32, y - 7.0, 12.0, [0, 0, 0], &format!("1e{k}"));
    }
    canvas
}

/// Writes the error map PNG (atomically).
pub fn write_error_map(path: &Path, values: &[f64], width: u32, height: u32, title: &str) -> Result<(), OutputError> {
    let c = error_map_canvas(values, width, height, title);
    write_rgb8_png(path, c.width, c.height, c.pixels)
}
