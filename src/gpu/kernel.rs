//! A minimal harness that runs one WGSL compute entry point over host-provided buffers and
//! reads one buffer back: used by tests to run the library's own WGSL functions (samplers,
//! warps, BSDFs) in small kernels, and by tools that need a single GPU computation.

use wgpu::util::DeviceExt;

use crate::shaders::bindings::{self, layout_entry, Kind};
use super::{wait_for_submission, Gpu, GpuError};

/// One dispatch of `entry` in `source`.
pub struct KernelRun<'a> {
    pub source: &'a str,
    pub entry: &'a str,
    /// `override` constants.
    pub constants: &'a [(&'a str, f64)],
    /// Read-only storage buffers: (binding, bytes).
    pub inputs: Vec<(u32, Vec<u8>)>,
    /// Uniform buffers: (binding, bytes).
    pub uniforms: Vec<(u32, Vec<u8>)>,
    /// Texel tables (`bindings::Kind::TexelTable`): (binding, bytes, a multiple of 16).
    pub texel_tables: Vec<(u32, Vec<u8>)>,
    /// The read-write storage buffer that comes back: (binding, size in bytes).
    pub output: (u32, u64),
    /// Workgroups along x.
    pub workgroups: u32,
}

impl KernelRun<'_> {
    /// Compiles, dispatches and returns the output buffer's bytes.
    pub fn run(&self, gpu: &Gpu) -> Result<Vec<u8>, GpuError> {
        let device = &gpu.device;
        // The BSDF library's one binding, its data, as zeros where the kernel gives none (a
        // kernel that reaches no kind reading data, or a source without the library). The same
        // for the environment map and the mesh attributes (16 bytes: one vec4).
        let mut inputs = self.inputs.clone();
        for binding in [bindings::BSDF_DATA, bindings::ENVIRONMENT_MAP, bindings::MESH_ATTRIBUTES] {
            let data = binding.number;
            let taken = inputs.iter().chain(&self.uniforms).any(|(b, _)| *b == data) || self.output.0 == data;
            if !taken && self.source.contains(&format!("BINDING_{}) var", binding.name)) {
                inputs.push((data, vec![0; 16]));
            }
        }
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(self.entry),
            source: wgpu::ShaderSource::Wgsl(self.source.into()),
        });
        let mut layout_entries: Vec<_> = inputs.iter().map(|(b, _)| layout_entry(*b, Kind::Storage { read_only: true })).collect();
        layout_entries.extend(self.uniforms.iter().map(|(b, _)| layout_entry(*b, Kind::Uniform)));
        layout_entries.extend(self.texel_tables.iter().map(|(b, _)| layout_entry(*b, Kind::TexelTable)));
        layout_entries.push(layout_entry(self.output.0, Kind::Storage { read_only: false }));
        let bgl = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: None, entries: &layout_entries });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&bgl)],
            immediate_size: 0,
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(self.entry),
            layout: Some(&layout),
            module: &module,
            entry_point: Some(self.entry),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: self.constants,
                zero_initialize_workgroup_memory: false,
            },
            cache: None,
        });
        let inputs = inputs.iter().map(|input| (input, wgpu::BufferUsages::STORAGE));
        let uniforms = self.uniforms.iter().map(|input| (input, wgpu::BufferUsages::UNIFORM));
        let buffers: Vec<(u32, wgpu::Buffer)> = inputs
            .chain(uniforms)
            .map(|((binding, bytes), usage)| {
                let buffer =
                    device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: None, contents: bytes, usage });
                (*binding, buffer)
            })
            .collect();
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("kernel output"),
            size: self.output.1,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("kernel readback"),
            size: self.output.1,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut entries: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .map(|(binding, buf)| wgpu::BindGroupEntry { binding: *binding, resource: buf.as_entire_binding() })
            .collect();
        let tables: Vec<(u32, wgpu::Texture, wgpu::TextureView)> = self
            .texel_tables
            .iter()
            .map(|(binding, bytes)| {
                let (texture, view) = bindings::texel_table(device, &gpu.queue, "kernel table", bytes);
                (*binding, texture, view)
            })
            .collect();
        entries.extend(tables.iter().map(|(binding, _, view)| bindings::texel_table_entry(*binding, view)));
        entries.push(wgpu::BindGroupEntry { binding: self.output.0, resource: output.as_entire_binding() });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &bgl, entries: &entries });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(self.workgroups, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&output, 0, &staging, 0, self.output.1);
        let index = gpu.queue.submit([encoder.finish()]);
        if let Some(err) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(err.to_string()));
        }
        staging.map_async(wgpu::MapMode::Read, .., |_| {});
        wait_for_submission(device, Some(index))?;
        wait_for_submission(device, None)?;
        let bytes = staging.get_mapped_range(..).map_err(|e| GpuError::Device(e.to_string()))?.to_vec();
        staging.unmap();
        Ok(bytes)
    }
}
