//! Everything that talks to wgpu: the device (`device`), the kernel's view of a scene (its
//! features and object order, `features`), the path-tracing pipelines and their
//! specialisation constants (`pipeline`), the per-dispatch uniform and camera (`frame_params`),
//! the scene's GPU buffers (`scene_buffers`), a harness for small single-dispatch kernels
//! (`kernel`), and the bounded map the pipeline cache keeps (`recent`).

mod device;
pub mod features;
mod frame_params;
mod kernel;
mod pipeline;
mod recent;
mod scene_buffers;

pub use device::{adapter_summary, list_adapters, quiet_device_select, wait_for_submission, Gpu, GpuError, ADAPTER_ENV};
pub use features::SceneFeatures;
pub use kernel::{Kernel, KernelData, KernelLayout, KernelRun};
pub use pipeline::{loop_iterations_per_sample, AdapterTuning, pipeline_constants, LoopBound, PathTracerPipelines, PipelineKey, PipelineStats, NO_TRAVERSAL_GUARD, ONE_WORD_TRAIL_DEPTH};
pub use frame_params::FrameParams;
pub use scene_buffers::{
    max_triangles, GpuDeltaLight, GpuLight, GpuMaterial, GpuPlane, GpuQuadric, GpuSphere, GpuSphereAxes, GpuTriangle, GpuTriangleNormals, GpuTriangleUvs, PackedTriangles,
    SceneBufferContents, SceneBuffers,
};
