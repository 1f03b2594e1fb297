//! Acceleration of ray queries against triangles: the watertight ray-triangle test
//! (`triangle`) and the bounding volume hierarchy built on the CPU, flat for the GPU (`bvh`).
//! This is the CPU side of the triangle meshes to come (issue: meshes, a BVH and area lights):
//! the kernel's traversal will mirror `Bvh::closest` and `Bvh::any`, which the tests hold
//! against brute force.

pub mod bvh;
pub mod triangle;

pub use bvh::{Bvh, BvhNode, Triangle};
pub use triangle::ShearedRay;
