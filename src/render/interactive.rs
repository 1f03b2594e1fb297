//! Submits that return at once, for interactive front-ends (the viewer adds a few samples per
//! UI frame): whole passes, or one pass spread over several calls by rows.

use super::{RenderError, Renderer};

impl Renderer {
    /// Adds `count` samples per pixel to at most `rows` more rows of the image and returns at
    /// once: a sample pass spread over several calls, so that a caller with a time budget per
    /// call (the viewer's UI frames) is never held up by a whole image's dispatch. The pass in
    /// progress keeps its own count; returns true when it has covered every row (then `spp`
    /// includes it). Every pixel gets the same samples as with `submit`. Returns the rows
    /// dispatched.
    pub fn submit_partial(&mut self, count: u32, rows: u32) -> Result<u32, RenderError> {
        let (next_row, count) = match self.partial {
            Some(pass) => pass,
            None => {
                self.check_room(count as u64)?;
                (0, count)
            }
        };
        let end = next_row.saturating_add(rows.max(1)).min(self.params.height);
        self.submit_rows(self.first_sample + self.spp_done, count, next_row..end);
        if end == self.params.height {
            self.partial = None;
            self.spp_done += count as u64;
        } else {
            self.partial = Some((end, count));
        }
        Ok(end - next_row)
    }

    /// True while a pass of `submit_partial` has not covered every row: pixels then hold
    /// different sample counts, and full readbacks wait.
    pub fn pass_in_progress(&self) -> bool {
        self.partial.is_some()
    }

    /// Submits `count` more samples per pixel and returns at once (interactive use: the viewer
    /// adds a few samples per UI frame). The queue runs work in order, so a display pass or
    /// readback submitted afterwards sees these samples.
    pub fn submit(&mut self, count: u32) -> Result<wgpu::SubmissionIndex, RenderError> {
        if self.partial.is_some() {
            return Err(RenderError::PassInProgress);
        }
        self.check_room(count as u64)?;
        let index = self.submit_frame(self.first_sample + self.spp_done, count);
        self.spp_done += count as u64;
        Ok(index)
    }

    /// The accumulator of each band: (first row, rows, buffer of `AccumPixel`s, row-major).
    pub fn accumulator_buffers(&self) -> impl Iterator<Item = (u32, u32, &wgpu::Buffer)> {
        self.bands.iter().map(|b| (b.y0, b.rows, &b.accum))
    }
}
