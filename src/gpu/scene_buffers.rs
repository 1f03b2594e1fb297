//! The scene packed for the GPU. Layouts mirror the structs in `shaders/scene.wgsl` (uniform
//! rules: a vec3 is 16-byte aligned, 12 bytes long), checked against naga's reflection of the
//! WGSL by `tests/shader_layouts.rs`.
//!
//! Spheres, planes and materials go in uniform buffers of fixed capacity (the `MAX_*`
//! below, also generated into the WGSL): the kernel reads them at lane-uniform indices, which
//! uniform buffers serve as broadcasts. Each stays under wgpu's default 64 KiB binding limit
//! (`crate::scene::MAX_*`, enforced by scene validation).

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use wgpu::util::DeviceExt;

use crate::scene::{Scene, MAX_MATERIALS, MAX_PLANES, MAX_SPHERES};

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

pub(crate) fn f3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

/// Rec. 709 luminance, to choose between the BSDF lobes (`p_spec`).
fn luminance(c: DVec3) -> f64 {
    c.dot(DVec3::new(0.212671, 0.715160, 0.072169))
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
    }

    #[test]
    fn capacities_fit_default_uniform_bindings() {
        let limit = wgpu::Limits::default().max_uniform_buffer_binding_size as usize;
        assert!(MAX_SPHERES * std::mem::size_of::<GpuSphere>() <= limit);
        assert!(MAX_PLANES * std::mem::size_of::<GpuPlane>() <= limit);
        assert!(MAX_MATERIALS * std::mem::size_of::<GpuMaterial>() <= limit);
    }
}
