//! Acceleration of ray queries against triangles: the watertight ray-triangle test
//! (`triangle`) and the bounding volume hierarchy built on the CPU, flat for the GPU (`bvh`).
//! The kernel's traversal (`shaders/bvh.wgsl`) mirrors `Bvh::closest` and `Bvh::any`;
//! `tests/bvh.rs` holds both against brute force.

pub mod bvh;
pub mod shared_vertices;
pub mod triangle;

pub use bvh::{Bvh, BvhNode, Triangle};

/// Scenes of at most this many triangles test them all in turn from a uniform buffer instead of
/// traversing the BVH (generated into the WGSL; see bvh.wgsl). Measured on lavapipe
/// (2026-12-03, `pathlab bench ... --methods mis`, M samples/s, unrolled tests against the BVH
/// in texel tables): the Cornell box (36 triangles) 1.32 against 0.56; Veach's scene (52
/// triangles, whose kernel also inlines a shadow ray per light) 0.68 against 0.77: the
/// unrolled tests grow the kernel's code (to megabytes, with every inlined query) faster than
/// they save loads.
pub const BRUTE_FORCE_TRIANGLES: u32 = 40;
pub use shared_vertices::{SharedVertices, MAX_SHARED_VERTICES};
pub use triangle::ShearedRay;
