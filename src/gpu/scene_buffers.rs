//! The scene packed for the GPU. Layouts mirror the structs in `shaders/scene.wgsl` and
//! `shaders/accumulate.wgsl` (std430/uniform rules: a vec3 is 16-byte aligned, 12 bytes long).
//!
//! Spheres, planes and materials go in uniform buffers of fixed capacity (the `MAX_*`
//! below, also generated into the WGSL): the kernel reads them at lane-uniform indices, which
//! uniform buffers serve as broadcasts. Each stays under wgpu's default 64 KiB binding limit
//! (`crate::scene::MAX_*`, enforced by scene validation).

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use wgpu::util::DeviceExt;

use crate::scene::{Fov, Scene, MAX_MATERIALS, MAX_PLANES, MAX_SPHERES};

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuSphere {
    pub center: [f32; 3],
    pub radius: f32,
    pub material: u32,
    pub _pad: [u32; 3],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuPlane {
    pub normal: [f32; 3],
    pub offset: f32,
    pub material: u32,
    pub _pad: [u32; 3],
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuMaterial {
    pub diffuse: [f32; 3],
    pub glossiness: f32,
    pub specular: [f32; 3],
    pub p_spec: f32,
    pub emission: [f32; 3],
    pub is_emissive: u32,
}

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
    pub _pad: u32,
}

/// Per-pixel accumulator (`AccumPixel` in accumulate.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct AccumPixel {
    pub sum: [f32; 3],
    pub count: u32,
    pub sum_err: [f32; 3],
    /// Rays traced for this pixel (camera, bounce and shadow), low and high 32 bits.
    pub rays_lo: u32,
    pub sum_sq: [f32; 3],
    pub rays_hi: u32,
    pub sum_sq_err: [f32; 3],
    pub _pad2: u32,
}

fn f3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

/// Rec. 709 luminance, to choose between the BSDF lobes (`p_spec`).
fn luminance(c: DVec3) -> f64 {
    c.dot(DVec3::new(0.212671, 0.715160, 0.072169))
}

impl AccumPixel {
    /// Rays traced for this pixel so far.
    pub fn rays(&self) -> u64 {
        (self.rays_hi as u64) << 32 | self.rays_lo as u64
    }
}

impl FrameParams {
    /// Camera and render settings of `scene`; sample range, seed and tile are set per frame.
    pub fn for_scene(scene: &Scene) -> FrameParams {
        let cam = &scene.camera;
        let (w, h) = (scene.render.width as f64, scene.render.height as f64);
        let forward = (cam.look_at - cam.position).normalize();
        let right = forward.cross(cam.up).normalize();
        let up = right.cross(forward);
        // Half-extents of the image plane at distance 1 along `forward`.
        let (half_w, half_h) = match cam.fov {
            Fov::X(deg) => {
                let hw = (deg.to_radians() / 2.0).tan();
                (hw, hw * h / w)
            }
            Fov::Y(deg) => {
                let hh = (deg.to_radians() / 2.0).tan();
                (hh * w / h, hh)
            }
        };
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
            _pad: 0,
        }
    }
}

/// The scene's uniform buffers, each allocated at its full capacity (the WGSL arrays are
/// fixed-size); the kernel reads only the first elements, as many as its pipeline constants say.
pub struct SceneBuffers {
    pub spheres: wgpu::Buffer,
    pub planes: wgpu::Buffer,
    pub materials: wgpu::Buffer,
}

/// A uniform buffer of `capacity` elements of `T`, starting with `items`, zero after them.
/// Callers (validation) guarantee `items.len() <= capacity`.
fn uniform_array<T: Pod>(device: &wgpu::Device, label: &str, items: &[T], capacity: usize) -> wgpu::Buffer {
    let mut bytes = bytemuck::cast_slice::<T, u8>(items).to_vec();
    bytes.resize(capacity.max(items.len()) * std::mem::size_of::<T>(), 0);
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    })
}

impl SceneBuffers {
    pub fn pack_materials(scene: &Scene) -> Vec<GpuMaterial> {
        scene
            .materials
            .iter()
            .map(|m| {
                let (ld, ls) = (luminance(m.diffuse), luminance(m.specular));
                let p_spec = if ld + ls > 0.0 { ls / (ld + ls) } else { 0.0 };
                GpuMaterial {
                    diffuse: f3(m.diffuse),
                    glossiness: m.glossiness as f32,
                    specular: f3(m.specular),
                    p_spec: p_spec as f32,
                    emission: f3(m.emission),
                    is_emissive: m.is_emissive() as u32,
                }
            })
            .collect()
    }

    /// The spheres in kernel order (`Scene::gpu_sphere_order`): the lights first.
    pub fn pack_spheres(scene: &Scene) -> Vec<GpuSphere> {
        scene
            .gpu_sphere_order()
            .into_iter()
            .map(|i| {
                let s = &scene.spheres[i];
                GpuSphere { center: f3(s.center), radius: s.radius as f32, material: s.material as u32, _pad: [0; 3] }
            })
            .collect()
    }

    /// The planes in kernel order (`Scene::gpu_plane_order`): those that can occlude a light first.
    pub fn pack_planes(scene: &Scene) -> Vec<GpuPlane> {
        scene
            .gpu_plane_order()
            .into_iter()
            .map(|i| {
                let p = &scene.planes[i];
                GpuPlane {
                    normal: f3(p.normal),
                    offset: p.normal.dot(p.point) as f32,
                    material: p.material as u32,
                    _pad: [0; 3],
                }
            })
            .collect()
    }

    pub fn new(device: &wgpu::Device, scene: &Scene) -> SceneBuffers {
        SceneBuffers {
            spheres: uniform_array(device, "spheres", &Self::pack_spheres(scene), MAX_SPHERES),
            planes: uniform_array(device, "planes", &Self::pack_planes(scene), MAX_PLANES),
            materials: uniform_array(device, "materials", &Self::pack_materials(scene), MAX_MATERIALS),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_match_wgsl() {
        assert_eq!(std::mem::size_of::<GpuSphere>(), 32);
        assert_eq!(std::mem::size_of::<GpuPlane>(), 32);
        assert_eq!(std::mem::size_of::<GpuMaterial>(), 48);
        assert_eq!(std::mem::size_of::<FrameParams>(), 112);
        assert_eq!(std::mem::size_of::<AccumPixel>(), 64);
    }

    #[test]
    fn capacities_fit_default_uniform_bindings() {
        let limit = wgpu::Limits::default().max_uniform_buffer_binding_size as usize;
        assert!(MAX_SPHERES * std::mem::size_of::<GpuSphere>() <= limit);
        assert!(MAX_PLANES * std::mem::size_of::<GpuPlane>() <= limit);
        assert!(MAX_MATERIALS * std::mem::size_of::<GpuMaterial>() <= limit);
    }
}
