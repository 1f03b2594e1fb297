//! A minimal harness that runs WGSL compute entry points over host-provided buffers and reads
//! one buffer back: used by tests to run the library's own WGSL functions (samplers, warps,
//! BSDFs) in small kernels, by the chi-square harness, and by tools that need a single GPU
//! computation. `Kernel` compiles a module once and dispatches its entry points as often as
//! needed; `KernelRun` is one compile and one dispatch.

use wgpu::util::DeviceExt;

use crate::shaders::bindings::{self, layout_entry, Kind};
use crate::shaders::specialise;
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
        let numbers = |list: &[(u32, Vec<u8>)]| list.iter().map(|(b, _)| *b).collect::<Vec<u32>>();
        let layout = KernelLayout { storage: &numbers(&self.inputs), uniforms: &numbers(&self.uniforms), texel_tables: &numbers(&self.texel_tables), output: self.output.0 };
        let kernel = Kernel::new(gpu, self.source, &[self.entry], self.constants, &layout)?;
        let data = KernelData { storage: &slices(&self.inputs), uniforms: &slices(&self.uniforms), texel_tables: &slices(&self.texel_tables) };
        kernel.dispatch(gpu, self.entry, &data, self.output.1, self.workgroups)
    }
}

/// (binding, bytes) pairs borrowed from owned ones.
fn slices(list: &[(u32, Vec<u8>)]) -> Vec<(u32, &[u8])> {
    list.iter().map(|(b, bytes)| (*b, bytes.as_slice())).collect()
}

/// The bindings of a kernel, by number.
pub struct KernelLayout<'a> {
    /// Read-only storage buffers.
    pub storage: &'a [u32],
    pub uniforms: &'a [u32],
    /// Texel tables (`bindings::Kind::TexelTable`).
    pub texel_tables: &'a [u32],
    /// The read-write storage buffer that comes back.
    pub output: u32,
}

/// The data of one dispatch: (binding, bytes) for the bindings of its `KernelLayout`. A
/// storage binding given none is bound to 16 zero bytes (an entry point that does not read it).
pub struct KernelData<'a> {
    pub storage: &'a [(u32, &'a [u8])],
    pub uniforms: &'a [(u32, &'a [u8])],
    pub texel_tables: &'a [(u32, &'a [u8])],
}

/// A module compiled once, with a pipeline per entry point and one bind group layout, to
/// dispatch as often as needed (lavapipe runs its SPIR-V front end for every pipeline made).
pub struct Kernel {
    pipelines: Vec<(String, wgpu::ComputePipeline)>,
    bind_group_layout: wgpu::BindGroupLayout,
    /// Storage bindings, the library's data bindings the source declares included.
    storage: Vec<u32>,
    output: u32,
}

impl Kernel {
    /// Compiles `entries` of `source` with `constants` over `layout`'s bindings. The BSDF
    /// library's data, the environment map and the mesh attributes are storage bindings too
    /// where the source declares them and the layout does not name them (bound to zeros where
    /// a dispatch gives none).
    pub fn new(gpu: &Gpu, source: &str, entries: &[&str], constants: &[(&str, f64)], layout: &KernelLayout) -> Result<Kernel, GpuError> {
        let device = &gpu.device;
        let mut storage = layout.storage.to_vec();
        for binding in [bindings::BSDF_DATA, bindings::ENVIRONMENT_MAP, bindings::MESH_ATTRIBUTES] {
            let data = binding.number;
            let taken = storage.contains(&data) || layout.uniforms.contains(&data) || layout.output == data;
            if !taken && source.contains(&format!("BINDING_{}) var", binding.name)) {
                storage.push(data);
            }
        }
        // Parsed and validated once; each entry point specialised on the host as the path
        // tracer's pipelines are (`specialise`: the constants substituted, the branches they
        // decide pruned), so that the driver compiles only what the entry reaches under them.
        let parsed = specialise::parse(source).map_err(GpuError::Device)?;
        let specialised = entries.iter().map(|&entry| specialise::specialise(&parsed, entry, constants).map_err(GpuError::Device)).collect::<Result<Vec<_>, _>>()?;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let mut layout_entries: Vec<_> = storage.iter().map(|&b| layout_entry(b, Kind::Storage { read_only: true })).collect();
        layout_entries.extend(layout.uniforms.iter().map(|&b| layout_entry(b, Kind::Uniform)));
        layout_entries.extend(layout.texel_tables.iter().map(|&b| layout_entry(b, Kind::TexelTable)));
        layout_entries.push(layout_entry(layout.output, Kind::Storage { read_only: false }));
        let bind_group_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: None, entries: &layout_entries });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: None,
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let pipelines = entries
            .iter()
            .zip(specialised)
            .map(|(&entry, module)| {
                let module = device.create_shader_module(wgpu::ShaderModuleDescriptor { label: Some(entry), source: wgpu::ShaderSource::Naga(std::borrow::Cow::Owned(module)) });
                let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&pipeline_layout),
                    module: &module,
                    entry_point: Some(entry),
                    compilation_options: wgpu::PipelineCompilationOptions { constants: &[], zero_initialize_workgroup_memory: false },
                    cache: None,
                });
                (entry.to_string(), pipeline)
            })
            .collect();
        if let Some(err) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(err.to_string()));
        }
        Ok(Kernel { pipelines, bind_group_layout, storage, output: layout.output })
    }

    /// Dispatches `entry` over `workgroups` workgroups along x and returns the output buffer
    /// (`output_bytes` long) as `T`s.
    pub fn dispatch<T: bytemuck::Pod>(&self, gpu: &Gpu, entry: &str, data: &KernelData, output_bytes: u64, workgroups: u32) -> Result<Vec<T>, GpuError> {
        let device = &gpu.device;
        let pipeline = &self.pipelines.iter().find(|(e, _)| e == entry).ok_or_else(|| GpuError::Device(format!("the kernel has no entry point {entry}")))?.1;
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let zeros = [0u8; 16];
        let storage = self.storage.iter().map(|&b| (b, data.storage.iter().find(|(n, _)| *n == b).map_or(&zeros[..], |(_, bytes)| *bytes), wgpu::BufferUsages::STORAGE));
        let uniforms = data.uniforms.iter().map(|&(b, bytes)| (b, bytes, wgpu::BufferUsages::UNIFORM));
        let buffers: Vec<(u32, wgpu::Buffer)> = storage
            .chain(uniforms)
            .map(|(binding, contents, usage)| (binding, device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: None, contents, usage })))
            .collect();
        let output = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("kernel output"),
            size: output_bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("kernel readback"),
            size: output_bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut entries: Vec<wgpu::BindGroupEntry> = buffers.iter().map(|(binding, buf)| wgpu::BindGroupEntry { binding: *binding, resource: buf.as_entire_binding() }).collect();
        let tables: Vec<(u32, wgpu::Texture, wgpu::TextureView)> = data
            .texel_tables
            .iter()
            .map(|&(binding, bytes)| {
                let (texture, view) = bindings::texel_table(device, &gpu.queue, "kernel table", bytes);
                (binding, texture, view)
            })
            .collect();
        entries.extend(tables.iter().map(|(binding, _, view)| bindings::texel_table_entry(*binding, view)));
        entries.push(wgpu::BindGroupEntry { binding: self.output, resource: output.as_entire_binding() });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor { label: None, layout: &self.bind_group_layout, entries: &entries });
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(workgroups, 1, 1);
        }
        encoder.copy_buffer_to_buffer(&output, 0, &staging, 0, output_bytes);
        let index = gpu.queue.submit([encoder.finish()]);
        if let Some(err) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(err.to_string()));
        }
        staging.map_async(wgpu::MapMode::Read, .., |_| {});
        wait_for_submission(device, Some(index))?;
        wait_for_submission(device, None)?;
        // One copy out of the mapped buffer, straight into `T`s.
        let values = bytemuck::pod_collect_to_vec(&staging.get_mapped_range(..).map_err(|e| GpuError::Device(e.to_string()))?);
        staging.unmap();
        Ok(values)
    }
}
