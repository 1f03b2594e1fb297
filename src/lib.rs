//! pathlab: a GPU path tracer for studying Monte Carlo rendering.
//!
//! From the bottom layer up (a module uses only those above it in this list):
//!
//! - `names`: one spelling per named choice (`named_enum!`), and `progress`: how long
//!   operations report to their front-end (the library prints nothing);
//! - `film`: the per-pixel accumulator and the film (mean, variance of the mean) made of it;
//! - `method`: samplers, BSDF sampling, light sampling and the study's presets;
//! - `display`: the display transform (sRGB or gamma, exposure) of PNGs, figures and metrics;
//! - `scene`: the TOML scene format with its triangle meshes (OBJ, PLY, Mitsuba's rectangle and
//!   cube), parsed and validated before any GPU work, its lights, and its canonical content hash;
//! - `output`: EXR and PNG files, written atomically;
//! - `stats`: quantiles, Šidák correction, per-pixel z-tests, power-law fits;
//! - `metrics`: MSE, relative MSE, bias, PSNR, SSIM, FLIP;
//! - `estimate`: error estimates without a reference, and target errors;
//! - `figures`: error maps, plots and image grids with an embedded font;
//! - `accel`: the watertight ray-triangle test and the BVH over triangles (built on the CPU, flat
//!   for the GPU; the CPU twins of `shaders/bvh.wgsl`);
//! - `shaders`: assembly and naga validation of the WGSL kernels in `shaders/`, with the
//!   constants and bindings generated from the Rust definitions;
//! - `sequences`: the CPU twin of the WGSL samplers;
//! - `gpu`: device, specialised pipelines, scene buffers;
//! - `chi2`: the chi-square harness of sampling routines (the kernel's sampler against its pdf);
//! - `technique`: proving a researcher's technique (`pathlab check-technique`);
//! - `render`: the renderer, checkpoints, rendering to a target, one `RenderJob` for every command;
//! - `shard`: sample ranges of split renders and their exact merge;
//! - `advise`: which method reaches a target error first;
//! - `study`: `pathlab study`: reference, tables, convergence, bias verdicts, report;
//! - `viewer` (feature `viewer`): `pathlab view`, the egui window.

pub mod accel;
pub mod advise;
pub mod chi2;
pub mod display;
pub mod estimate;
pub mod figures;
pub mod film;
pub mod gpu;
pub mod method;
pub mod metrics;
pub mod names;
pub mod output;
pub mod progress;
pub mod render;
pub mod scene;
pub mod sequences;
pub mod shaders;
pub mod shard;
pub mod stats;
pub mod study;
pub mod technique;
#[cfg(feature = "viewer")]
pub mod viewer;

/// pathlab's version, recorded in every output file.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
