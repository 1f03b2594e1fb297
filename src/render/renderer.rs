//! The renderer: one scene with one method accumulating samples per pixel in GPU buffers.
//! What it does is split by concern: `band` (the image in bands of rows and the dispatches over
//! them), `batch` (rendering to a budget), `interactive` (submits that return at once, for the
//! viewer), `readback` (accumulators back to the host), `timestamps` (GPU time of frames).

use std::sync::Arc;
use std::time::Duration;

use crate::estimate::ErrorEstimate;
use crate::film::AccumPixel;
use crate::gpu::{loop_iterations_per_sample, max_triangles, FrameParams, Gpu, GpuError, PackedTriangles, PathTracerPipelines, PipelineKey, SceneBuffers, SceneFeatures};
use crate::method::Method;
use crate::scene::Scene;

use super::band::Band;
use super::timestamps::Timestamps;

/// Largest number of samples per pixel in one dispatch.
const MAX_SAMPLES_PER_DISPATCH: u32 = 1 << 14;
/// llvmpipe (lavapipe) stops all loops of an invocation after 65535 back-edges in total; on CPU
/// adapters a dispatch is kept below this many. The readback checks every pixel's sample
/// count, so a driver that drops work is reported, never averaged in.
const CPU_LOOP_BUDGET: u64 = 60_000;
/// Sample indices are u32: a pixel can take at most 2^32 samples.
pub const MAX_SPP: u64 = 1 << 32;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error(transparent)]
    Technique(#[from] crate::scene::TechniqueError),
    #[error(
        "one row of a {width}-pixel-wide image needs a {bytes} byte accumulator, more than this \
         adapter's largest storage binding ({limit} bytes); render a narrower image"
    )]
    TooLarge { width: u32, bytes: u64, limit: u64 },
    #[error(
        "method {method} cannot see {light}: a point, spot or directional light is found only by \
         next event estimation, which {method} does not do (lights=none); choose a method with \
         light sampling (nee, mis)"
    )]
    UnseenDeltaLight { method: String, light: String },
    #[error(
        "{method} samples the environment map by its compensated distribution, which leaves the \
         directions no brighter than the map's mean to BSDF sampling under MIS: use it with mis \
         or mis-balance (e.g. mis+env+env-compensated)"
    )]
    IncompleteEnvSampling { method: String },
    #[error("reading the image back from the GPU failed: {0}")]
    Readback(String),
    #[error("cannot resume from the saved accumulators: {0}")]
    Restore(String),
    #[error("a pass spread over several submissions is in progress: finish it (submit_partial) first")]
    PassInProgress,
    #[error("{0}")]
    Unsupported(&'static str),
    #[error("at most 2^32 samples per pixel are supported (asked for {0})")]
    TooManySamples(u64),
    #[error(
        "one sample of this scene may run ~{iterations} shader loop iterations, more than the 65535 llvmpipe \
         (software Vulkan) allows per invocation; reduce max_depth or the number of objects and \
         lights, or use a hardware GPU{}",
        tracking_hint(*max_null_collisions)
    )]
    LoopLimit { iterations: u64, max_null_collisions: u32 },
    #[error(
        "the scene has {count} triangles, more than this adapter holds ({limit}: its largest storage \
         binding is {binding} bytes, 48 bytes per triangle, and its 2D textures are at most \
         {texture_rows} texels high, {} x {texture_rows} / 4 triangles)",
        crate::shaders::bindings::TEXEL_TABLE_WIDTH
    )]
    TooManyTriangles { count: u64, limit: u64, binding: u64, texture_rows: u64 },
    #[error(
        "the scene's textures need {bytes} bytes on the GPU, more than this adapter's largest \
         storage binding ({limit} bytes); the largest: {largest} (`pathlab check` lists them)"
    )]
    TexturesTooLarge { bytes: u64, limit: u64, largest: String },
}

/// What a loop-limit refusal adds where heterogeneous media are tracked: their share.
fn tracking_hint(max_null_collisions: u32) -> String {
    if max_null_collisions == 0 {
        return String::new();
    }
    format!(
        "; delta and ratio tracking in the heterogeneous media may meet up to {max_null_collisions} null collisions along each path segment and shadow ray: a lower `scale` (their majorant) or smaller boxes lower that"
    )
}

impl RenderError {
    /// Refuses a method that cannot see one of the scene's lights (a delta light without next
    /// event estimation): no GPU needed, so commands call it before any GPU work.
    /// Also refuses compensated environment sampling without MIS, whose estimate would miss
    /// the directions its pdf leaves out.
    pub fn check_sees_lights(scene: &Scene, method: &Method) -> Result<(), RenderError> {
        if let Some(light) = scene.delta_light_unseen_by(method) {
            return Err(RenderError::UnseenDeltaLight { method: method.name(), light });
        }
        if scene.environment_map.is_some() && method.env_pdf_is_incomplete() {
            return Err(RenderError::IncompleteEnvSampling { method: method.name() });
        }
        Ok(())
    }
}

/// When to stop a render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Budget {
    /// Stop after this many samples per pixel in total.
    Samples(u64),
    /// Stop submitting frames after this much wall time.
    Time(Duration),
}

/// Reported after every frame.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    /// Samples per pixel finished on the device.
    pub spp_done: u64,
    pub elapsed: Duration,
    /// Rendering to a target error: the latest estimate, once there is one.
    pub estimate: Option<ErrorEstimate>,
    /// Rendering to a target error: the predicted time until it is met (error ~ 1/spp).
    pub eta: Option<Duration>,
}

/// What a call to `Renderer::render` did.
#[derive(Debug, Clone, Copy)]
pub struct RenderStats {
    /// Samples per pixel accumulated so far (over all calls).
    pub spp: u64,
    /// Wall time of this call.
    pub seconds: f64,
    /// Dispatches of this call.
    pub frames: u64,
    /// True when stopped early by the cancel flag.
    pub interrupted: bool,
}

/// Frames whose device time can be recorded between two `device_time` calls (two timestamp

/// Renders one scene with one method into a GPU accumulator. Owns its device handle.
pub struct Renderer {
    pub(super) gpu: Gpu,
    pub(super) pipeline: Arc<wgpu::ComputePipeline>,
    /// The image in bands of rows, each with its own accumulator (one storage binding holds
    /// at most `max_storage_buffer_binding_size` bytes: 128 MiB on lavapipe, ~2 Mpixel).
    pub(super) bands: Vec<Band>,
    pub(super) params: FrameParams,
    /// Sample index of the first sample (0 unless set by `start_at_sample`).
    pub(super) first_sample: u64,
    pub(super) spp_done: u64,
    /// Samples per dispatch of the batch loop, adapted to the measured rate.
    pub(super) samples_per_dispatch: u32,
    /// Cap on samples per dispatch for this device and pipeline.
    pub(super) max_samples_per_dispatch: u32,
    pub(super) timestamps: Option<Timestamps>,
    /// A pass of `submit_partial` in progress: (next row, its samples per pixel).
    pub(super) partial: Option<(u32, u32)>,
    _scene_buffers: SceneBuffers,
}

impl Renderer {
    pub fn new(gpu: &Gpu, pipelines: &PathTracerPipelines, scene: &Scene, method: Method, seed: u32) -> Result<Renderer, RenderError> {
        Renderer::with_band_bytes(gpu, pipelines, scene, method, seed, u64::MAX)
    }

    /// Like `new`, with accumulator bands of at most `band_bytes` bytes (whole rows; at least
    /// one row). `new` uses the adapter's largest storage binding.
    pub fn with_band_bytes(
        gpu: &Gpu,
        pipelines: &PathTracerPipelines,
        scene: &Scene,
        method: Method,
        seed: u32,
        band_bytes: u64,
    ) -> Result<Renderer, RenderError> {
        Renderer::build(gpu, pipelines, scene, PipelineKey::new(method, SceneFeatures::of(scene), scene.default_light_select()), seed, band_bytes)
    }

    /// Like `new`, with a pipeline that has every optional feature on
    /// (`SceneFeatures::all_on`): to measure what specialisation to the scene gains.
    pub fn unspecialised(gpu: &Gpu, pipelines: &PathTracerPipelines, scene: &Scene, method: Method, seed: u32) -> Result<Renderer, RenderError> {
        let key = PipelineKey::new(method, SceneFeatures::of(scene).all_on(), scene.default_light_select());
        Renderer::build(gpu, pipelines, scene, key, seed, u64::MAX)
    }

    fn build(gpu: &Gpu, pipelines: &PathTracerPipelines, scene: &Scene, mut key: PipelineKey, seed: u32, band_bytes: u64) -> Result<Renderer, RenderError> {
        RenderError::check_sees_lights(scene, &key.method)?;
        let device = &gpu.device;
        let binding = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        let count = scene.num_triangles() as u64;
        let texture_rows = gpu.limits.max_texture_dimension_2d as u64;
        // Each attribute slot's table takes as many bytes per triangle as the normals'.
        let limit = max_triangles(binding / scene.mesh_attribute_names().len().max(1) as u64, texture_rows);
        if count > limit {
            return Err(RenderError::TooManyTriangles { count, limit, binding, texture_rows });
        }
        let textures: Vec<&crate::scene::Texture> = scene.materials.iter().flat_map(|m| m.textures()).collect();
        let texture_bytes: u64 = textures.iter().map(|t| t.gpu_bytes()).sum();
        if texture_bytes > binding {
            let largest = textures.iter().max_by_key(|t| t.gpu_bytes()).map_or(String::new(), |t| t.describe());
            return Err(RenderError::TexturesTooLarge { bytes: texture_bytes, limit: binding, largest });
        }
        let packed = PackedTriangles::new(scene, key.samples_environment());
        key.deep_bvh = packed.bvh.depth > crate::gpu::ONE_WORD_TRAIL_DEPTH;
        let (width, height) = (scene.render.width, scene.render.height);
        let limit = gpu.limits.max_storage_buffer_binding_size.min(gpu.limits.max_buffer_size);
        let row_bytes = width as u64 * std::mem::size_of::<AccumPixel>() as u64;
        if row_bytes > limit {
            return Err(RenderError::TooLarge { width, bytes: row_bytes, limit });
        }
        let rows_per_band = (band_bytes.min(limit) / row_bytes).clamp(1, height as u64) as u32;
        let max_samples_per_dispatch = if gpu.info.device_type == wgpu::DeviceType::Cpu {
            let leaves = packed.bvh.nodes.iter().filter(|n| n.count > 0).count() as u64;
            let techniques = crate::shaders::TechniqueFiles::of(&key.method, &scene.techniques)?;
            let bound_of = |key: &PipelineKey| {
                loop_iterations_per_sample(key, scene.render.max_depth, packed.bvh.nodes.len() as u64, leaves)
                    .with_shape_loops(scene, key)
                    .with_techniques(key, techniques, scene.render.max_depth)
            };
            let mut bound = bound_of(&key);
            if key.features.num_bspline_segments > 0 && bound.per_sample() > CPU_LOOP_BUDGET {
                // The B-spline segments' looped searches would not fit: unrolled ones have no
                // back-edges (and run at half the speed).
                key.bspline_unrolled = true;
                bound = bound_of(&key);
            }
            if bound.fixed > CPU_LOOP_BUDGET {
                return Err(RenderError::LoopLimit { iterations: bound.fixed, max_null_collisions: key.features.max_null_collisions });
            }
            if bound.per_sample() <= CPU_LOOP_BUDGET {
                // The worst case fits: as many samples per dispatch as fit whole.
                (CPU_LOOP_BUDGET / bound.per_sample()).clamp(1, MAX_SAMPLES_PER_DISPATCH as u64) as u32
            } else {
                // A worst-case traversal would not fit (large meshes): one sample per dispatch,
                // and the kernel counts its traversal steps, dropping a sample that would pass
                // the budget left after everything else (never seen in practice: a ray visits
                // a few hundred nodes, not all of them), which the readback then reports.
                // Three quarters of what is left: the kernel's count of a traversal is within
                // 1.45x of llvmpipe's own (measured on a worst case, tests/bvh.rs).
                key.traversal_budget = ((CPU_LOOP_BUDGET - bound.fixed) * 3 / 4) as u32;
                1
            }
        } else {
            MAX_SAMPLES_PER_DISPATCH
        };
        let techniques = crate::shaders::TechniqueFiles::of(&key.method, &scene.techniques)?;
        let (pipeline, _) = pipelines.get(device, key, techniques);
        let scene_buffers = SceneBuffers::new(device, &gpu.queue, scene, &packed);
        let mut params = FrameParams::for_scene(scene);
        params.seed = seed;
        let bands = Band::cover(device, pipelines, &scene_buffers, width, height, rows_per_band);
        Ok(Renderer {
            gpu: gpu.clone(),
            pipeline,
            bands,
            params,
            first_sample: 0,
            spp_done: 0,
            samples_per_dispatch: 1,
            max_samples_per_dispatch,
            timestamps: None,
            partial: None,
            _scene_buffers: scene_buffers,
        })
    }

    /// Number of accumulator bands the image is split into.
    pub fn bands(&self) -> usize {
        self.bands.len()
    }

    /// Image width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.params.width, self.params.height)
    }

    /// Samples per pixel accumulated so far.
    pub fn spp(&self) -> u64 {
        self.spp_done
    }

    /// Sample index of the first sample of this render.
    pub fn first_sample(&self) -> u64 {
        self.first_sample
    }

    /// Most samples per pixel one dispatch may take on this device (the software rasteriser's
    /// loop limit bounds it on CPU adapters).
    pub fn max_samples_per_dispatch(&self) -> u32 {
        self.max_samples_per_dispatch
    }

    /// Draws sample indices from `index` on instead of 0 (before any sample is rendered): to
    /// continue a render in another process, or to test sample indices near 2^32.
    pub fn start_at_sample(&mut self, index: u64) -> Result<(), RenderError> {
        if self.spp_done > 0 || index >= MAX_SPP {
            return Err(RenderError::TooManySamples(index));
        }
        self.first_sample = index;
        Ok(())
    }

    /// Sample indices are u32: `n` more samples per pixel must stay below 2^32 in all.
    pub(super) fn check_room(&self, n: u64) -> Result<(), RenderError> {
        let total = self.first_sample + self.spp_done + n;
        if total > MAX_SPP { Err(RenderError::TooManySamples(total)) } else { Ok(()) }
    }

    /// Loads accumulators saved by `accumulators` (before any sample is rendered): the render
    /// continues at sample index `first_sample + spp` and ends bit-identical to one that never
    /// stopped.
    pub fn restore(&mut self, first_sample: u64, spp: u64, pixels: &[AccumPixel]) -> Result<(), RenderError> {
        let expected = self.params.width as usize * self.params.height as usize;
        if pixels.len() != expected {
            return Err(RenderError::Restore(format!("{} pixels given, the image has {expected}", pixels.len())));
        }
        if let Some(i) = AccumPixel::first_miscounted(pixels, spp) {
            return Err(RenderError::Restore(format!("pixel {i} holds {} samples, expected {spp}", pixels[i].count)));
        }
        if self.spp_done > 0 || first_sample + spp > MAX_SPP {
            return Err(RenderError::TooManySamples(first_sample + spp));
        }
        let row = self.params.width as usize;
        for band in &self.bands {
            let start = band.y0 as usize * row;
            let slice = &pixels[start..start + band.rows as usize * row];
            self.gpu.queue.write_buffer(&band.accum, 0, bytemuck::cast_slice(slice));
        }
        self.gpu.queue.submit([]);
        self.first_sample = first_sample;
        self.spp_done = spp;
        Ok(())
    }

}
