//! The image in bands of rows: each band has its own accumulator, frame uniform and bind group
//! (one storage binding holds at most `max_storage_buffer_binding_size` bytes), and a frame is
//! one compute pass dispatching over the bands it covers.

use crate::film::AccumPixel;
use crate::gpu::{FrameParams, PathTracerPipelines, SceneBuffers};
use crate::shaders::bindings::{self, entry};

use super::timestamps::MAX_TIMED_FRAMES;
use super::Renderer;

/// Workgroup side of the path tracer (`@workgroup_size(8, 8)` in integrator.wgsl).
const WORKGROUP: u32 = 8;

/// Rows `y0 .. y0 + rows` of the image: their accumulator, frame uniform and bind group.
pub(super) struct Band {
    pub(super) y0: u32,
    pub(super) rows: u32,
    pub(super) params_buffer: wgpu::Buffer,
    pub(super) accum: wgpu::Buffer,
    pub(super) bind_group: wgpu::BindGroup,
}

impl Band {
    /// Bands of at most `rows_per_band` rows covering a `width` x `height` image, with empty
    /// accumulators.
    pub(super) fn cover(
        device: &wgpu::Device,
        pipelines: &PathTracerPipelines,
        scene_buffers: &SceneBuffers,
        width: u32,
        height: u32,
        rows_per_band: u32,
    ) -> Vec<Band> {
        let row_bytes = width as u64 * std::mem::size_of::<AccumPixel>() as u64;
        let mut bands = Vec::new();
        for y0 in (0..height).step_by(rows_per_band as usize) {
            let rows = rows_per_band.min(height - y0);
            let params_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("frame params"),
                size: std::mem::size_of::<FrameParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            // An empty accumulator: a buffer mapped at creation reads as zeros (WebGPU spec), and
            // unmapping hands wgpu that initialised content (no lazy clear).
            let accum = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("accumulator"),
                size: rows as u64 * row_bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: true,
            });
            accum.unmap();
            // The band's own buffers, the pipelines' table, then the scene's (each at its binding).
            let mut entries =
                vec![entry(bindings::FRAME, &params_buffer), entry(bindings::ACCUM, &accum), entry(bindings::HALTON_PRIMES, &pipelines.halton_primes)];
            entries.extend(scene_buffers.entries());
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("path tracer"),
                layout: &pipelines.bind_group_layout,
                entries: &entries,
            });
            bands.push(Band { y0, rows, params_buffer, accum, bind_group });
        }
        bands
    }

    /// Whether image row `y` is in this band.
    pub(super) fn holds(&self, y: u32) -> bool {
        y >= self.y0 && y < self.y0 + self.rows
    }
}

impl Renderer {
    /// Encodes one frame (a compute pass over every band) adding `count` samples per pixel from
    /// sample index `sample_start`, and submits it without waiting.
    pub(super) fn submit_frame(&mut self, sample_start: u64, count: u32) -> wgpu::SubmissionIndex {
        self.submit_rows(sample_start, count, 0..self.params.height)
    }

    /// Like `submit_frame` for image rows `rows` only (dispatched band by band).
    pub(super) fn submit_rows(&mut self, sample_start: u64, count: u32, rows: std::ops::Range<u32>) -> wgpu::SubmissionIndex {
        let gpu = &self.gpu;
        let (device, queue) = (&gpu.device, &gpu.queue);
        let groups_x = self.params.width.div_ceil(WORKGROUP);
        self.params.sample_start = sample_start as u32;
        self.params.sample_count = count;
        // The part of each band inside `rows`: (band, first image row, rows).
        let tiles: Vec<(usize, u32, u32)> = self
            .bands
            .iter()
            .enumerate()
            .filter_map(|(i, b)| {
                let (y0, y1) = (b.y0.max(rows.start), (b.y0 + b.rows).min(rows.end));
                (y1 > y0).then_some((i, y0, y1 - y0))
            })
            .collect();
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        {
            let timestamp_writes = self.timestamps.as_mut().filter(|t| t.frames < MAX_TIMED_FRAMES).map(|t| {
                t.frames += 1;
                wgpu::ComputePassTimestampWrites {
                    query_set: &t.set,
                    beginning_of_pass_write_index: Some(2 * (t.frames - 1)),
                    end_of_pass_write_index: Some(2 * (t.frames - 1) + 1),
                }
            });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("path trace"), timestamp_writes });
            pass.set_pipeline(&self.pipeline);
            for &(i, _, tile_rows) in &tiles {
                pass.set_bind_group(0, &self.bands[i].bind_group, &[]);
                pass.dispatch_workgroups(groups_x, tile_rows.div_ceil(WORKGROUP), 1);
            }
        }
        for &(i, y0, tile_rows) in &tiles {
            let band = &self.bands[i];
            let params = FrameParams { tile_y: y0, tile_height: tile_rows, accum_row: y0 - band.y0, ..self.params };
            queue.write_buffer(&band.params_buffer, 0, bytemuck::bytes_of(&params));
        }
        queue.submit([encoder.finish()])
    }
}
