//! Acceleration of ray queries against triangles: the watertight ray-triangle test
//! (`triangle`) and the bounding volume hierarchy built on the CPU, flat for the GPU (`bvh`).
//! The kernel's traversal (`shaders/bvh.wgsl`) mirrors `Bvh::closest` and `Bvh::any`;
//! `tests/bvh.rs` holds both against brute force.

pub mod bvh;
pub mod triangle;

pub use bvh::{Bvh, BvhNode, Triangle};

/// Scenes of at most this many triangles test them all in turn from a uniform buffer instead of
/// traversing the BVH (generated into the WGSL; see bvh.wgsl).
pub const BRUTE_FORCE_TRIANGLES: u32 = 64;
pub use triangle::ShearedRay;
