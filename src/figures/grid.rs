//! The study's image grid, like the study's own figure: one row per method, one column per
//! samples-per-pixel budget and the reference, each tile labelled; the last column holds the
//! false-colour error map of the row's method (see `error_map`).

use super::text::Canvas;

/// One tile: an RGB8 image and up to two lines of label beneath it.
#[derive(Debug, Clone)]
pub struct Tile {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
    pub label: Vec<String>,
}

/// Tiles wider than this are shrunk by an integer box filter.
pub const MAX_TILE_WIDTH: u32 = 256;

impl Tile {
    /// Shrinks by the smallest integer factor that brings the width to `MAX_TILE_WIDTH` or less.
    pub fn fitted(self) -> Tile {
        let f = self.width.div_ceil(MAX_TILE_WIDTH).max(1);
        if f == 1 {
            return self;
        }
        let (w, h) = (self.width / f, self.height / f);
        let mut rgb = vec![0u8; (w * h * 3) as usize];
        for y in 0..h {
            for x in 0..w {
                for c in 0..3 {
                    let mut sum = 0u32;
                    for dy in 0..f {
                        for dx in 0..f {
                            sum += self.rgb[(((y * f + dy) * self.width + x * f + dx) * 3 + c) as usize] as u32;
                        }
                    }
                    rgb[((y * w + x) * 3 + c) as usize] = (sum / (f * f)) as u8;
                }
            }
        }
        Tile { width: w, height: h, rgb, label: self.label }
    }
}

const LEFT: u32 = 130;
const HEADER: u32 = 26;
const GAP: u32 = 6;
const LABEL_LINE: u32 = 14;

/// Lays out `rows` (label, one or more lines; tiles) under `headers`; every tile is fitted to the same size.
pub fn grid(title: &str, headers: &[String], rows: Vec<(String, Vec<Option<Tile>>)>) -> Canvas {
    let rows: Vec<(String, Vec<Option<Tile>>)> =
        rows.into_iter().map(|(l, tiles)| (l, tiles.into_iter().map(|t| t.map(Tile::fitted)).collect())).collect();
    let (tw, th) = rows
        .iter()
        .flat_map(|(_, t)| t.iter().flatten())
        .map(|t| (t.width, t.height))
        .next()
        .unwrap_or((MAX_TILE_WIDTH, MAX_TILE_WIDTH / 2));
    let cols = headers.len() as u32;
    let cell_w = tw + GAP;
    let cell_h = th + 2 * LABEL_LINE + GAP + 4;
    let width = LEFT + cols * cell_w;
    let height = HEADER * 2 + rows.len() as u32 * cell_h;
    let mut canvas = Canvas::new(width, height, [255, 255, 255]);
    canvas.text(8.0, 4.0, 16.0, [0, 0, 0], title);
    for (i, h) in headers.iter().enumerate() {
        canvas.text((LEFT + i as u32 * cell_w) as f32, (HEADER + 4) as f32, 14.0, [0, 0, 0], h);
    }
    for (r, (label, tiles)) in rows.iter().enumerate() {
        let y = HEADER * 2 + r as u32 * cell_h;
        for (k, line) in label.lines().enumerate() {
            canvas.text(8.0, (y + th / 2) as f32 - 8.0 + 16.0 * k as f32, 14.0, [0, 0, 0], line);
        }
        for (c, tile) in tiles.iter().enumerate() {
            let x = LEFT + c as u32 * cell_w;
            match tile {
                Some(t) => {
                    canvas.blit(x, y, t.width.min(tw), t.height.min(th), &t.rgb);
                    for (k, line) in t.label.iter().take(2).enumerate() {
                        canvas.text(x as f32, (y + th + 2 + k as u32 * LABEL_LINE) as f32, 11.0, [40, 40, 40], line);
                    }
                }
                None => canvas.fill(x, y, tw, th, [230, 230, 230]),
            }
        }
    }
    canvas
}
