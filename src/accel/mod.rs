//! Acceleration of ray queries against triangles: the watertight ray-triangle test
//! (`triangle`) and the bounding volume hierarchy built on the CPU, flat for the GPU (`bvh`).
//! The kernel's traversal (`shaders/bvh.wgsl`) mirrors `Bvh::closest` and `Bvh::any`;
//! `tests/bvh.rs` holds both against brute force.

pub mod bvh;
pub mod shared_vertices;
pub mod triangle;

pub use bvh::{Bvh, BvhNode, BvhRecord, Triangle, Visit};

/// Scenes of at most this many triangles test them all in turn from a uniform buffer instead of
/// traversing the BVH (generated into the WGSL; see bvh.wgsl), each distinct vertex sheared
/// once per ray (`SharedVertices`). Measured on lavapipe (2026-12-05, `OLD=<the build with 40>
/// scripts/compare_builds.sh`, M rays/s, BVH against unrolled tests): Veach's scene (52
/// triangles, whose kernel also inlines a shadow ray per light) 9.3-9.5 against 11.1-11.3; an
/// icosphere of 80, 9.6-9.8 against 10.7-11.6; a patch of 128, 9.4-9.5 against 5.6-5.7. Each
/// size pays for its unrolled code at pipeline creation (Veach's: 1.3 s -> 2.2 s a process).
/// Before the vertices were shared (2026-12-03) the Cornell box (36) ran 1.32 M samples/s
/// unrolled against 0.56 through the BVH, and Veach's scene 0.68 against 0.77.
pub const BRUTE_FORCE_TRIANGLES: u32 = 64;
pub use shared_vertices::{SharedVertices, MAX_SHARED_VERTICES};
pub use triangle::ShearedRay;
