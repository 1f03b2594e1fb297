//! GPU timestamps at the start and end of every frame's compute pass, for `pathlab bench`'s
//! device time and host overhead.

use std::time::Duration;

use crate::gpu::wait_for_submission;

use super::{RenderError, Renderer};

/// Frames whose device time can be recorded between two `device_time` calls (two timestamp
/// queries each; wgpu allows 4096 queries per set).
pub(super) const MAX_TIMED_FRAMES: u32 = 2048;

/// GPU timestamps at the start and end of every frame's compute pass.
pub(super) struct Timestamps {
    pub(super) set: wgpu::QuerySet,
    pub(super) resolve: wgpu::Buffer,
    pub(super) readback: wgpu::Buffer,
    /// Frames recorded since the last `device_time`.
    pub(super) frames: u32,
}

impl Renderer {
    /// Records GPU timestamps around every frame from now on, for `device_time`. Returns false
    /// when the adapter has no timestamp queries.
    pub fn enable_timestamps(&mut self) -> bool {
        if !self.gpu.features.contains(wgpu::Features::TIMESTAMP_QUERY) {
            return false;
        }
        let device = &self.gpu.device;
        let bytes = 2 * MAX_TIMED_FRAMES as u64 * 8;
        self.timestamps = Some(Timestamps {
            set: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("frame timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2 * MAX_TIMED_FRAMES,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp resolve"),
                size: bytes,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamp readback"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            frames: 0,
        });
        true
    }

    /// Device time of the frames rendered since timestamps were enabled or last read (at most
    /// the first MAX_TIMED_FRAMES of them), and how many frames that covers. Reads back: call
    /// it outside the frame loop.
    pub fn device_time(&mut self) -> Result<Option<(Duration, u32)>, RenderError> {
        let Some(ts) = self.timestamps.as_mut() else { return Ok(None) };
        let frames = ts.frames.min(MAX_TIMED_FRAMES);
        ts.frames = 0;
        if frames == 0 {
            return Ok(Some((Duration::ZERO, 0)));
        }
        let device = &self.gpu.device;
        let bytes = 2 * frames as u64 * 8;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("timestamps") });
        encoder.resolve_query_set(&ts.set, 0..2 * frames, &ts.resolve, 0);
        encoder.copy_buffer_to_buffer(&ts.resolve, 0, &ts.readback, 0, bytes);
        let index = self.gpu.queue.submit([encoder.finish()]);
        ts.readback.map_async(wgpu::MapMode::Read, ..bytes, |_| {});
        wait_for_submission(device, Some(index))?;
        wait_for_submission(device, None)?;
        let ticks: Vec<u64> = {
            let view = ts.readback.get_mapped_range(..bytes).map_err(|e| RenderError::Readback(e.to_string()))?;
            bytemuck::pod_collect_to_vec(&view)
        };
        ts.readback.unmap();
        let period_ns = self.gpu.queue.get_timestamp_period() as f64;
        let total_ns: f64 = ticks.chunks(2).map(|t| t[1].saturating_sub(t[0]) as f64 * period_ns).sum();
        Ok(Some((Duration::from_secs_f64(total_ns * 1e-9), frames)))
    }
}
