//! Text on images, in the font shipped in `assets/fonts/` (DejaVu Sans, embedded in the
//! binary), so figures render the same on every machine.

use ab_glyph::{Font, FontRef, PxScale, ScaleFont};

/// DejaVu Sans (Bitstream Vera licence, `assets/fonts/LICENSE-DejaVu.txt`).
pub static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

fn font() -> FontRef<'static> {
    FontRef::try_from_slice(FONT_BYTES).expect("the embedded font parses")
}

/// An RGB8 canvas, row-major.
#[derive(Debug, Clone)]
pub struct Canvas {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<u8>,
}

impl Canvas {
    pub fn new(width: u32, height: u32, background: [u8; 3]) -> Canvas {
        Canvas { width, height, pixels: background.repeat((width * height) as usize) }
    }

    /// Copies an RGB8 image with its top-left corner at (x, y), clipped to the canvas.
    pub fn blit(&mut self, x: u32, y: u32, width: u32, height: u32, rgb: &[u8]) {
        for row in 0..height.min(self.height.saturating_sub(y)) {
            for col in 0..width.min(self.width.saturating_sub(x)) {
                let src = ((row * width + col) * 3) as usize;
                let dst = (((y + row) * self.width + x + col) * 3) as usize;
                self.pixels[dst..dst + 3].copy_from_slice(&rgb[src..src + 3]);
            }
        }
    }

    /// Fills a rectangle.
    pub fn fill(&mut self, x: u32, y: u32, width: u32, height: u32, colour: [u8; 3]) {
        let rgb = colour.repeat((width * height) as usize);
        self.blit(x, y, width, height, &rgb);
    }

    /// Draws `text` with its top-left corner at (x, y), `size` pixels high, alpha-blended.
    pub fn text(&mut self, x: f32, y: f32, size: f32, colour: [u8; 3], text: &str) {
        let font = font();
        let scaled = font.as_scaled(PxScale::from(size));
        let mut caret = x;
        let mut previous = None;
        for ch in text.chars() {
            let id = scaled.glyph_id(ch);
            if let Some(p) = previous {
                caret += scaled.kern(p, id);
            }
            let glyph = id.with_scale_and_position(size, ab_glyph::point(caret, y + scaled.ascent()));
            caret += scaled.h_advance(id);
            previous = Some(id);
            let Some(outline) = font.outline_glyph(glyph) else { continue };
            let bounds = outline.px_bounds();
            outline.draw(|gx, gy, coverage| {
                let px = bounds.min.x as i64 + gx as i64;
                let py = bounds.min.y as i64 + gy as i64;
                if px < 0 || py < 0 || px >= self.width as i64 || py >= self.height as i64 {
                    return;
                }
                let i = ((py as u32 * self.width + px as u32) * 3) as usize;
                for c in 0..3 {
                    let bg = self.pixels[i + c] as f32;
                    self.pixels[i + c] = (bg + (colour[c] as f32 - bg) * coverage.clamp(0.0, 1.0)).round() as u8;
                }
            });
        }
    }

    /// Width in pixels of `text` at `size`.
    pub fn text_width(size: f32, text: &str) -> f32 {
        let font = font();
        let scaled = font.as_scaled(PxScale::from(size));
        text.chars().map(|c| scaled.h_advance(scaled.glyph_id(c))).sum()
    }
}
