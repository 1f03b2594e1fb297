//! The histogram image of a chi-square test: observed counts beside expected ones over the
//! (phi, s = 1 - cos theta) grid, on one magma scale, and their difference in units of the
//! expected count's standard deviation (red where more samples fell than the pdf says, blue
//! where fewer), so a wrong normalisation or a missing region shows at a glance.

use std::path::Path;

use crate::chi2::Chi2Outcome;
use crate::figures::colormap::magma_at;
use crate::figures::text::Canvas;
use crate::output::{write_rgb8_png, OutputError};

/// Pixels per cell, across (phi) and down (s).
const CELL_W: u32 = 3;
const CELL_H: u32 = 2;
const MARGIN: u32 = 12;
const TITLE: u32 = 44;

/// Writes the histogram of `outcome`, titled `title`, as a PNG.
pub fn write_histogram(outcome: &Chi2Outcome, title: &str, path: &Path) -> Result<(), OutputError> {
    let (phi_bins, s_bins) = outcome.bins;
    let (w, h) = (phi_bins as u32 * CELL_W, s_bins as u32 * CELL_H);
    let width = 3 * w + 4 * MARGIN;
    let height = h + TITLE + 2 * MARGIN;
    let mut canvas = Canvas::new(width, height, [255, 255, 255]);
    canvas.text(MARGIN as f32, 4.0, 14.0, [0, 0, 0], title);
    let mass_line = format!("pdf mass {:.5}, p = {:.3e}; rows: s = 1 - cos theta from 0 (top) to 2", outcome.mass, outcome.p_value);
    canvas.text(MARGIN as f32, 22.0, 12.0, [60, 60, 60], &mass_line);
    let cells = phi_bins * s_bins;
    let peak = outcome.observed[..cells].iter().map(|&o| o as f64).chain(outcome.expected[..cells].iter().copied()).fold(0.0f64, f64::max).max(1.0);
    let panels: [(&str, Box<dyn Fn(usize) -> [u8; 3]>); 3] = [
        ("observed", Box::new(|c| magma_at((outcome.observed[c] as f64 / peak).sqrt()))),
        ("expected", Box::new(|c| magma_at((outcome.expected[c] / peak).sqrt()))),
        (
            "(observed - expected) / sqrt(expected), +-5",
            Box::new(|c| {
                let (o, e) = (outcome.observed[c] as f64, outcome.expected[c]);
                let z = if e > 0.0 { (o - e) / e.sqrt() } else if o > 0.0 { 5.0 } else { 0.0 };
                let t = (z / 5.0).clamp(-1.0, 1.0);
                let fade = |x: f64| (255.0 * (1.0 - x.abs())) as u8;
                if t >= 0.0 { [255, fade(t), fade(t)] } else { [fade(t), fade(t), 255] }
            }),
        ),
    ];
    for (k, (label, colour)) in panels.iter().enumerate() {
        let x0 = MARGIN + k as u32 * (w + MARGIN);
        let mut rgb = vec![0u8; (w * h * 3) as usize];
        for j in 0..s_bins {
            for i in 0..phi_bins {
                let c = colour(j * phi_bins + i);
                for dy in 0..CELL_H {
                    for dx in 0..CELL_W {
                        let at = (((j as u32 * CELL_H + dy) * w + i as u32 * CELL_W + dx) * 3) as usize;
                        rgb[at..at + 3].copy_from_slice(&c);
                    }
                }
            }
        }
        canvas.blit(x0, TITLE + MARGIN, w, h, &rgb);
        canvas.text(x0 as f32, (TITLE - 6) as f32 - 2.0, 11.0, [0, 0, 0], label);
    }
    write_rgb8_png(path, canvas.width, canvas.height, canvas.pixels)
}
