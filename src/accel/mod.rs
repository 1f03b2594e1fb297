//! Acceleration of ray queries against triangles: the watertight ray-triangle test
//! (`triangle`) and the bounding volume hierarchy built on the CPU, flat for the GPU (`bvh`).
//! The kernel's traversal (`shaders/bvh.wgsl`) mirrors `Bvh::closest` and `Bvh::any`;
//! `tests/bvh.rs` holds both against brute force.

pub mod bvh;
pub mod triangle;

pub use bvh::{Bvh, BvhNode, Triangle};
pub use triangle::ShearedRay;
