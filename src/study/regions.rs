//! Named pixel rectangles of the study's image (`study --regions FILE`): each run's relMSE is
//! also measured in every region, for the region table of the report (which strategy wins
//! where, as in Veach's figure 9.2). The file is TOML:
//!
//! ```toml
//! size = [128, 72]            # the image size the rectangles are written for
//! [[region]]
//! name = "smooth plate, small light"
//! x = 40                      # left column, top row, width and height in pixels
//! y = 30
//! width = 6
//! height = 3
//! ```
//!
//! At another study size the rectangles are scaled (edges rounded to pixels, at least one
//! pixel each way), so one file serves a quick study and a full one.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::StudyError;
use crate::film::Film;

/// One rectangle, in pixels of the study's image.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Region {
    pub name: String,
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RegionsFile {
    size: [u32; 2],
    #[serde(rename = "region")]
    regions: Vec<Region>,
}

/// Reads `path` and scales its rectangles to `width` x `height`. Refused, naming the file (and
/// the line, for TOML errors) and the region: no regions, an empty or repeated name, an empty
/// rectangle, one reaching outside `size`.
pub fn load(path: &Path, width: u32, height: u32) -> Result<Vec<Region>, StudyError> {
    let bad = |m: String| StudyError::Input(format!("{}: {m}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| bad(format!("cannot read the regions file: {e}")))?;
    let file: RegionsFile = toml::from_str(&text).map_err(|e| {
        let line = e.span().map_or(0, |s| text[..s.start.min(text.len())].matches('\n').count() + 1);
        bad(format!("line {line}: {}", e.message().trim()))
    })?;
    let [sw, sh] = file.size;
    if sw == 0 || sh == 0 {
        return Err(bad(format!("size = [{sw}, {sh}]: both must be at least 1")));
    }
    if file.regions.is_empty() {
        return Err(bad("no [[region]]".into()));
    }
    let mut out: Vec<Region> = Vec::new();
    for (i, r) in file.regions.iter().enumerate() {
        let what = format!("region {} (`{}`)", i + 1, r.name);
        if r.name.trim().is_empty() {
            return Err(bad(format!("region {}: the name is empty", i + 1)));
        }
        if out.iter().any(|o| o.name == r.name) {
            return Err(bad(format!("{what}: the name is used twice")));
        }
        if r.width == 0 || r.height == 0 {
            return Err(bad(format!("{what}: width and height must be at least 1")));
        }
        if r.x as u64 + r.width as u64 > sw as u64 || r.y as u64 + r.height as u64 > sh as u64 {
            return Err(bad(format!("{what}: x {}..{}, y {}..{} reaches outside the {sw}x{sh} image", r.x, r.x + r.width, r.y, r.y + r.height)));
        }
        // Edges scaled to the study's size and rounded, at least one pixel each way.
        let scale = |v: u32, from: u32, to: u32| ((v as f64 * to as f64 / from as f64).round() as u32).min(to);
        let (x0, y0) = (scale(r.x, sw, width).min(width - 1), scale(r.y, sh, height).min(height - 1));
        let x1 = scale(r.x + r.width, sw, width).max(x0 + 1);
        let y1 = scale(r.y + r.height, sh, height).max(y0 + 1);
        out.push(Region { name: r.name.clone(), x: x0, y: y0, width: x1 - x0, height: y1 - y0 });
    }
    Ok(out)
}

/// relMSE of `test` against `reference` over one region (the metric of `metrics::linear`).
pub fn rel_mse(test: &Film, reference: &Film, region: &Region) -> f64 {
    let mut sum = 0.0;
    for y in region.y..region.y + region.height {
        for x in region.x..region.x + region.width {
            let i = (y * test.width + x) as usize;
            for c in 0..3 {
                sum += crate::metrics::linear::rel_sq(test.mean[i][c] as f64, reference.mean[i][c] as f64);
            }
        }
    }
    sum / (3 * region.width * region.height) as f64
}

/// A region's relMSE in one run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RegionError {
    pub name: String,
    pub rel_mse: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(text: &str) -> tempfile::NamedTempFile {
        let f = tempfile::NamedTempFile::new().unwrap();
        std::fs::write(f.path(), text).unwrap();
        f
    }

    #[test]
    fn regions_are_scaled_to_the_study_size() {
        let f = write("size = [128, 72]\n[[region]]\nname = \"a\"\nx = 10\ny = 20\nwidth = 7\nheight = 3\n[[region]]\nname = \"b\"\nx = 127\ny = 71\nwidth = 1\nheight = 1\n");
        let r = load(f.path(), 128, 72).unwrap();
        assert_eq!(r[0], Region { name: "a".into(), x: 10, y: 20, width: 7, height: 3 });
        let r = load(f.path(), 256, 144).unwrap();
        assert_eq!((r[0].x, r[0].y, r[0].width, r[0].height), (20, 40, 14, 6));
        // Half size: rounded, and never empty or outside.
        let r = load(f.path(), 64, 36).unwrap();
        assert_eq!((r[0].x, r[0].y, r[0].width, r[0].height), (5, 10, 4, 2));
        assert_eq!((r[1].x, r[1].y, r[1].width, r[1].height), (63, 35, 1, 1));
    }

    #[test]
    fn bad_regions_files_are_refused_by_name() {
        for (text, message) in [
            ("size = [8, 8]\n", "missing field"),
            ("size = [8, 8]\nregion = []\n", "no [[region]]"),
            ("size = [8, 8]\n[[region]]\nname = \"a\"\nx = 4\ny = 0\nwidth = 5\nheight = 1\n", "reaches outside"),
            ("size = [8, 8]\n[[region]]\nname = \"a\"\nx = 0\ny = 0\nwidth = 0\nheight = 1\n", "at least 1"),
            ("size = [8, 8]\n[[region]]\nname = \"a\"\nx = 0\ny = 0\nwidth = 1\nheight = 1\n[[region]]\nname = \"a\"\nx = 1\ny = 0\nwidth = 1\nheight = 1\n", "used twice"),
            ("size = [8, 8]\n[[region]]\nname = \"a\"\nx = -1\ny = 0\nwidth = 1\nheight = 1\n", "line 4"),
        ] {
            let f = write(text);
            let e = load(f.path(), 8, 8).unwrap_err().to_string();
            assert!(e.contains(message) && e.contains(&f.path().display().to_string()), "{text}: {e}");
        }
    }
}
