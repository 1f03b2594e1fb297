//! The accumulators back on the host: whole films (waiting), sampled rows for error estimates
//! during a render, and copies that finish later (`PendingReadback`, for the viewer's frames).
//! Every pixel's sample count is checked: a driver that drops work is reported, never averaged in.

use std::time::{Duration, Instant};

use crate::film::{AccumPixel, Film};
use crate::gpu::wait_for_submission;

use super::band::Band;
use super::{RenderError, Renderer};

/// The accumulators, read back.
#[derive(Debug, Clone)]
pub struct Readback {
    pub film: Film,
    /// Rays traced for the whole film so far (camera, bounce and shadow rays), counted by the
    /// kernel as it traces them.
    pub rays: u64,
    /// Samples in which a researcher's technique faulted (each contributed 0).
    pub faults: u64,
}

impl Renderer {
    /// Starts copying all accumulators back without waiting: poll the device and call
    /// `PendingReadback::try_finish` in later frames. Not while a partial pass is in progress
    /// (its sample-count check would fail).
    pub fn begin_readback(&self) -> PendingReadback {
        let regions: Vec<_> = self.bands.iter().map(|b| (&b.accum, 0, b.accum.size())).collect();
        self.begin_regions(&regions)
    }

    /// Starts copying one pixel's accumulator back (for a mouse-over probe).
    pub fn begin_read_pixel(&self, x: u32, y: u32) -> Option<PendingReadback> {
        let (w, h) = self.size();
        if x >= w || y >= h {
            return None;
        }
        let size = std::mem::size_of::<AccumPixel>() as u64;
        let band = self.bands.iter().find(|b| b.holds(y))?;
        let offset = ((y - band.y0) as u64 * w as u64 + x as u64) * size;
        let mut pending = self.begin_regions(&[(&band.accum, offset, size)]);
        // Mid-pass, the pixel may hold this pass's samples already: it reports its own count.
        pending.spp = None;
        Some(pending)
    }

    /// Copies `regions` (buffer, byte offset, bytes) one after another into a staging buffer
    /// and starts mapping it.
    fn begin_regions(&self, regions: &[(&wgpu::Buffer, u64, u64)]) -> PendingReadback {
        let device = &self.gpu.device;
        let size: u64 = regions.iter().map(|r| r.2).sum();
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("readback") });
        let mut at = 0;
        for &(buffer, offset, bytes) in regions {
            encoder.copy_buffer_to_buffer(buffer, offset, &staging, at, bytes);
            at += bytes;
        }
        let submission = self.gpu.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |r| {
            let _ = tx.send(r);
        });
        PendingReadback { staging, rx, submission, spp: Some(self.spp_done) }
    }

    /// Copies the accumulators back and turns them into mean and variance.
    pub fn film(&self) -> Result<Film, RenderError> {
        Ok(self.readback()?.film)
    }

    /// The film, and the number of rays the kernel traced for it (counted by the kernel).
    pub fn readback(&self) -> Result<Readback, RenderError> {
        let pixels = self.accumulators()?;
        let rays = pixels.iter().map(AccumPixel::rays).sum();
        let faults = pixels.iter().map(|p| p.faults as u64).sum();
        Ok(Readback { film: Film::from_accumulators(self.params.width, self.params.height, self.spp_done, &pixels), rays, faults })
    }

    /// The raw per-pixel accumulators (compensated sums, sums of squares, count, rays), row-major,
    /// after checking that every pixel holds exactly the samples submitted.
    pub fn accumulators(&self) -> Result<Vec<AccumPixel>, RenderError> {
        let mut pixels: Vec<AccumPixel> = Vec::with_capacity(self.params.width as usize * self.params.height as usize);
        for band in &self.bands {
            pixels.extend(self.read_band(band)?);
        }
        Ok(pixels)
    }

    fn read_band(&self, band: &Band) -> Result<Vec<AccumPixel>, RenderError> {
        self.read_regions(&[(&band.accum, 0, band.accum.size())])
    }

    /// The accumulators of rows 0, stride, 2 stride, ... (row-major): a cheap sample of the
    /// image for error estimates during a render. Returns the pixels and the number of rows.
    pub fn accumulator_rows(&self, stride: u32) -> Result<(Vec<AccumPixel>, u32), RenderError> {
        let row_bytes = self.params.width as u64 * std::mem::size_of::<AccumPixel>() as u64;
        let mut regions = Vec::new();
        for y in (0..self.params.height).step_by(stride.max(1) as usize) {
            let band = self.bands.iter().find(|b| b.holds(y)).expect("bands cover the image");
            regions.push((&band.accum, (y - band.y0) as u64 * row_bytes, row_bytes));
        }
        let rows = regions.len() as u32;
        let pixels = self.read_regions(&regions)?;
        Ok((pixels, rows))
    }

    /// Copies `regions` (buffer, byte offset, bytes) back, waiting for them.
    fn read_regions(&self, regions: &[(&wgpu::Buffer, u64, u64)]) -> Result<Vec<AccumPixel>, RenderError> {
        let pending = self.begin_regions(regions);
        wait_for_submission(&self.gpu.device, Some(pending.submission.clone()))?;
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            if let Some(result) = pending.try_finish() {
                return result;
            }
            if Instant::now() >= deadline {
                return Err(RenderError::Readback("the mapped buffer never became available".into()));
            }
            wait_for_submission(&self.gpu.device, None)?;
        }
    }
}

/// A copy of accumulators on its way back from the device (see `Renderer::begin_readback`).
pub struct PendingReadback {
    staging: wgpu::Buffer,
    rx: std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>,
    submission: wgpu::SubmissionIndex,
    /// Samples per pixel submitted before the copy: every pixel read holds exactly these
    /// (`None` for a single-pixel probe, which reports the pixel's own count).
    pub spp: Option<u64>,
}

impl PendingReadback {
    /// The pixels once the copy is mapped, `None` while it is not (the caller polls the
    /// device). The sample count of every pixel is checked against `spp`.
    pub fn try_finish(&self) -> Option<Result<Vec<AccumPixel>, RenderError>> {
        let mapped = match self.rx.try_recv() {
            Ok(r) => r,
            Err(std::sync::mpsc::TryRecvError::Empty) => return None,
            Err(e) => return Some(Err(RenderError::Readback(e.to_string()))),
        };
        Some(mapped.map_err(|e| RenderError::Readback(e.to_string())).and_then(|()| {
            let pixels: Vec<AccumPixel> = {
                let view = self.staging.get_mapped_range(..).map_err(|e| RenderError::Readback(e.to_string()))?;
                bytemuck::pod_collect_to_vec(&view)
            };
            self.staging.unmap();
            if let Some(spp) = self.spp {
                check_counts(&pixels, spp)?;
            }
            Ok(pixels)
        }))
    }
}

/// Every pixel must hold exactly the samples submitted: a driver that drops work is
/// reported, never averaged in.
fn check_counts(pixels: &[AccumPixel], spp: u64) -> Result<(), RenderError> {
    match AccumPixel::first_miscounted(pixels, spp) {
        Some(i) => Err(RenderError::Readback(format!(
            "pixel {i} accumulated {} samples, expected {spp}: the device dropped work (on a software \
             Vulkan driver: a ray's BVH traversal ran past the loop limit of 65535 iterations per \
             invocation; see README, \"Limits\")",
            pixels[i].count
        ))),
        None => Ok(()),
    }
}
