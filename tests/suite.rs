//! The integration tests as one binary: one link instead of one per file, and the test harness
//! runs tests of different files side by side (`cargo test --release --test suite cornell_box::`
//! runs one file's tests). Each module is one file of tests/, with its own opening comment;
//! `common` is what they share.

mod common;

mod advise;
mod anisotropic;
mod analytic_scenes;
mod bump_maps;
mod blends;
mod build_features;
mod bvh;
mod checkpoint;
mod chi2_sampling;
mod cli_compare;
mod cli_errors;
mod cli_render;
mod cli_study;
mod conductors;
mod cornell_box;
mod cornell_conductors;
mod deploy;
mod delta_lights;
mod dielectrics;
mod direct_integrator;
mod environment_light;
mod environment_map;
mod heterogeneous_media;
mod hide_emitters;
#[cfg(feature = "viewer")]
mod display_pass;
mod error_estimate;
mod exact_cases;
mod extremes;
mod file_mutations;
mod lamps;
mod masks;
mod media;
mod mesh_attributes;
mod normal_maps;
mod lavapipe_inline_uniforms;
mod orthographic;
mod mesh_scenes;
mod metrics_fixtures;
mod mitsuba_scenes;
mod noise_floor;
mod plastics;
mod polygon_lights;
mod projected_lights;
mod polarized_plastics;
mod principled;
mod quadrics;
mod linear_curves;
mod bspline_curves;
mod sdf_grids;
mod render_presets;
mod rough_plastics;
mod serialized_meshes;
mod roulette;
mod rough_textures;
mod sampler_twin;
mod shader_layouts;
mod shaders_validate;
mod shard_merge;
mod spectra;
mod study_reproduction;
mod techniques;
mod textured_lights;
mod textures;
mod thin_lens;
mod twosided;
mod unbiased_study;
mod uv_parametrisation;
mod volume_textures;
mod veach_mis;
#[cfg(feature = "viewer")]
mod viewer;
#[cfg(feature = "viewer")]
mod viewer_driver;
