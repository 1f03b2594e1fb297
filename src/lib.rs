//! pathlab: a GPU path tracer for studying Monte Carlo rendering.
//!
//! - `scene`: the TOML scene format, parsed and validated before any GPU work;
//! - `method`: samplers, BSDF sampling, light sampling and the study's presets;
//! - `shaders`: assembly and naga validation of the WGSL kernels in `shaders/`;
//! - `gpu`: device, specialised pipelines, scene buffers;
//! - `render`: the frame loop, accumulation and readback;
//! - `output`: EXR and PNG files, written atomically;
//! - `display`: the display transform (sRGB or gamma, exposure) of PNGs, figures and metrics;
//! - `estimate`: error estimates without a reference, and rendering to a target error;
//! - `metrics`: MSE, relative MSE, bias, PSNR, SSIM, FLIP;
//! - `figures`: error maps, plots and image grids with an embedded font;
//! - `shard`: sample ranges of split renders and their exact merge;
//! - `sequences`: the CPU twin of the WGSL samplers;
//! - `study`: `pathlab study`: reference, tables, convergence, bias verdicts, report;
//! - `stats`: quantiles, Šidák correction, per-pixel z-tests;
//! - `viewer`: `pathlab view`, the egui window: progressive display, live metrics, plots.

pub mod display;
pub mod estimate;
pub mod figures;
pub mod gpu;
pub mod metrics;
pub mod method;
pub mod output;
pub mod render;
pub mod scene;
pub mod sequences;
pub mod shard;
pub mod shaders;
pub mod stats;
pub mod study;
pub mod viewer;

/// pathlab's version, recorded in every output file.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
