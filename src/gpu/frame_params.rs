//! The per-dispatch uniform of the path tracer (`FrameParams` in `shaders/scene.wgsl`): the
//! camera's frame, image-plane extents and thin lens, the sample range, seed and the tile of rows a
//! dispatch covers.

use bytemuck::{Pod, Zeroable};

use crate::scene::Scene;

use super::scene_buffers::f3;

/// Per-frame uniform (`FrameParams` in scene.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct FrameParams {
    pub camera_origin: [f32; 3],
    pub width: u32,
    pub camera_forward: [f32; 3],
    pub height: u32,
    pub camera_right: [f32; 3],
    pub sample_start: u32,
    pub camera_up: [f32; 3],
    pub sample_count: u32,
    pub environment: [f32; 3],
    pub seed: u32,
    pub max_depth: u32,
    pub tile_x: u32,
    pub tile_y: u32,
    pub tile_width: u32,
    pub tile_height: u32,
    /// Always 0: lets the kernel build identities the compiler cannot simplify away.
    pub opaque_zero: u32,
    /// Row of the bound accumulator that the tile's first row goes to.
    pub accum_row: u32,
    /// The thin lens (`Camera::aperture_radius`, `focus_distance`); 0: a pinhole.
    pub aperture_radius: f32,
    pub focus_distance: f32,
    pub _pad: [u32; 3],
}

impl FrameParams {
    /// Camera and render settings of `scene`; sample range, seed and tile are set per frame.
    pub fn for_scene(scene: &Scene) -> FrameParams {
        let cam = &scene.camera;
        let forward = (cam.look_at - cam.position).normalize();
        let right = forward.cross(cam.up).normalize();
        let up = right.cross(forward);
        // Half-extents of the image plane at distance 1 along `forward` (perspective), or of the
        // rectangle the rays leave (orthographic).
        let (half_w, half_h) = cam.projection.half_extents(scene.render.width, scene.render.height);
        FrameParams {
            camera_origin: f3(cam.position),
            width: scene.render.width,
            camera_forward: f3(forward),
            height: scene.render.height,
            camera_right: f3(right * half_w),
            sample_start: 0,
            camera_up: f3(up * half_h),
            sample_count: 0,
            environment: f3(scene.render.environment),
            seed: 0,
            max_depth: scene.render.max_depth,
            tile_x: 0,
            tile_y: 0,
            tile_width: scene.render.width,
            tile_height: scene.render.height,
            opaque_zero: 0,
            accum_row: 0,
            aperture_radius: cam.aperture_radius as f32,
            focus_distance: cam.focus_distance as f32,
            _pad: [0; 3],
        }
    }
}

