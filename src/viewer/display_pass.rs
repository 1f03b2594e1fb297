//! The display pass: a compute kernel (`shaders/display.wgsl`) that turns a renderer's
//! accumulators into the texture the window shows (through a packed buffer and a copy): the mean through the display transform, or a
//! false-colour error view. It runs on the device after the frame's samples, so the image never
//! travels through the CPU.

use crate::display::{DisplayTransform, Transfer, View};
use crate::shaders::bindings::{self, entry};
use crate::render::Renderer;
use crate::film::Film;
use crate::shaders;

/// The format egui draws user textures from: display-encoded values in plain RGBA8.
pub const SHOWN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const WORKGROUP: u32 = 8;
/// Rows of a buffer-to-texture copy start at multiples of 256 bytes: 64 RGBA8 texels.
const TEXELS_PER_ROW_ALIGNMENT: u32 = wgpu::COPY_BYTES_PER_ROW_ALIGNMENT / 4;

/// `DisplayParams` in display.wgsl (layout checked by `tests/shader_layouts.rs`).
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct DisplayParams {
    pub width: u32,
    pub y0: u32,
    pub rows: u32,
    pub view: u32,
    pub exposure_scale: f32,
    pub transfer: u32,
    pub inv_gamma: f32,
    pub log_lo: f32,
    pub log_hi: f32,
    pub row_stride: u32,
    pub _pad: [u32; 2],
}

/// The display kernel, its bind group layout, the colour map and a stand-in reference.
pub struct DisplayPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
    colour_map: wgpu::Buffer,
    no_reference: wgpu::Buffer,
}

/// A reference image on the device (linear RGB, padded to vec4).
pub struct GpuReference {
    pub width: u32,
    pub height: u32,
    buffer: wgpu::Buffer,
}

impl GpuReference {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, film: &Film) -> GpuReference {
        let texels: Vec<[f32; 4]> = film.mean.iter().map(|m| [m[0], m[1], m[2], 0.0]).collect();
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("reference"),
            size: (texels.len().max(1) * 16) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&buffer, 0, bytemuck::cast_slice(&texels));
        GpuReference { width: film.width, height: film.height, buffer }
    }
}

/// One shown image: its texture, the packed RGBA8 buffer the kernel writes (rows of `stride`
/// texels, as a buffer-to-texture copy wants them) and the bind groups that read one renderer's
/// bands into it.
pub struct ShownImage {
    pub width: u32,
    pub height: u32,
    pub texture: wgpu::Texture,
    pub view: wgpu::TextureView,
    packed: wgpu::Buffer,
    stride: u32,
    /// Per band: first row, rows, its parameters and bind group.
    bands: Vec<(u32, u32, wgpu::Buffer, wgpu::BindGroup)>,
}

impl DisplayPass {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue) -> DisplayPass {
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("display pass"),
            source: wgpu::ShaderSource::Wgsl(shaders::display_source().into()),
        });

        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("display pass"),
            entries: &bindings::layout_entries(&bindings::DISPLAY),
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("display pass"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("display pass"),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(shaders::DISPLAY_ENTRY),
            compilation_options: Default::default(),
            cache: None,
        });
        // Magma as linear [0, 1] display values (the same table as the figures' error maps).
        let magma: Vec<[f32; 4]> = (0..256)
            .map(|i| {
                let [r, g, b] = crate::figures::colormap::magma_at(i as f64 / 255.0);
                [r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0, 1.0]
            })
            .collect();
        let colour_map = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("magma"),
            size: 256 * 16,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        queue.write_buffer(&colour_map, 0, bytemuck::cast_slice(&magma));
        let no_reference = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("no reference"),
            size: 16,
            usage: wgpu::BufferUsages::STORAGE,
            mapped_at_creation: false,
        });
        DisplayPass { pipeline, layout, colour_map, no_reference }
    }

    /// A texture of the renderer's size and the bind groups that fill it from its bands
    /// (and read `reference` when it has the same size).
    pub fn shown_image(&self, device: &wgpu::Device, renderer: &Renderer, reference: Option<&GpuReference>) -> ShownImage {
        let (width, height) = renderer.size();
        let texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shown image"),
            size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: SHOWN_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
        let stride = width.div_ceil(TEXELS_PER_ROW_ALIGNMENT) * TEXELS_PER_ROW_ALIGNMENT;
        let packed = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shown image (packed)"),
            size: stride as u64 * height as u64 * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let reference = reference.filter(|r| (r.width, r.height) == (width, height)).map_or(&self.no_reference, |r| &r.buffer);
        let bands = renderer
            .accumulator_buffers()
            .map(|(y0, rows, accum)| {
                let params = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("display params"),
                    size: std::mem::size_of::<DisplayParams>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("display pass"),
                    layout: &self.layout,
                    entries: &[
                        entry(bindings::DISPLAY_PARAMS, &params),
                        entry(bindings::DISPLAY_BAND, accum),
                        entry(bindings::DISPLAY_REFERENCE, reference),
                        entry(bindings::DISPLAY_COLOUR_MAP, &self.colour_map),
                        entry(bindings::DISPLAY_SHOWN, &packed),
                    ],
                });
                (y0, rows, params, bind_group)
            })
            .collect();
        ShownImage { width, height, texture, view, packed, stride, bands }
    }

    /// Fills `image` from its renderer's accumulators: `view` through `display`.
    pub fn run(&self, device: &wgpu::Device, queue: &wgpu::Queue, image: &ShownImage, view: View, display: DisplayTransform) {
        let inv_gamma = match display.transfer {
            Transfer::Srgb => 1.0,
            Transfer::Gamma(g) => 1.0 / g,
        };
        let transfer = display.transfer.code();
        let (log_lo, log_hi) = view.log10_range();
        for &(y0, rows, ref params, _) in &image.bands {
            let p = DisplayParams {
                width: image.width,
                y0,
                rows,
                view: view.constant(),
                exposure_scale: display.exposure.exp2(),
                transfer,
                inv_gamma,
                log_lo,
                log_hi,
                row_stride: image.stride,
                _pad: [0; 2],
            };
            queue.write_buffer(params, 0, bytemuck::bytes_of(&p));
        }
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("display pass") });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("display pass"), timestamp_writes: None });
            pass.set_pipeline(&self.pipeline);
            for (_, rows, _, bind_group) in &image.bands {
                pass.set_bind_group(0, bind_group, &[]);
                pass.dispatch_workgroups(image.width.div_ceil(WORKGROUP), rows.div_ceil(WORKGROUP), 1);
            }
        }
        encoder.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer: &image.packed,
                layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(image.stride * 4), rows_per_image: None },
            },
            image.texture.as_image_copy(),
            wgpu::Extent3d { width: image.width, height: image.height, depth_or_array_layers: 1 },
        );
        queue.submit([encoder.finish()]);
    }
}

/// Reads the shown texture back as RGB8 (for saving what is shown as PNG). Blocks.
pub fn read_shown_rgb8(device: &wgpu::Device, queue: &wgpu::Queue, image: &ShownImage) -> Result<Vec<u8>, String> {
    let row = image.width * 4;
    let padded = row.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("shown image readback"),
        size: padded as u64 * image.height as u64,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("shown image readback") });
    encoder.copy_texture_to_buffer(
        image.texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &staging,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: None },
        },
        wgpu::Extent3d { width: image.width, height: image.height, depth_or_array_layers: 1 },
    );
    let index = queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    staging.map_async(wgpu::MapMode::Read, .., move |r| {
        let _ = tx.send(r);
    });
    crate::gpu::wait_for_submission(device, Some(index)).map_err(|e| e.to_string())?;
    rx.recv_timeout(std::time::Duration::from_secs(60)).map_err(|e| e.to_string())?.map_err(|e| e.to_string())?;
    let bytes = {
        let view = staging.get_mapped_range(..).map_err(|e| e.to_string())?;
        let mut rgb = Vec::with_capacity(image.width as usize * image.height as usize * 3);
        for y in 0..image.height as usize {
            let line = &view[y * padded as usize..y * padded as usize + row as usize];
            rgb.extend(line.chunks(4).flat_map(|p| [p[0], p[1], p[2]]));
        }
        rgb
    };
    staging.unmap();
    Ok(bytes)
}
