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

use crate::accel::{Bvh, BvhNode};
use crate::scene::{AliasTable, Light, Scene, MAX_MATERIALS, MAX_PLANES, MAX_SPHERES};
use crate::shaders::flags::{MATERIAL_EMISSIVE, MATERIAL_ONE_SIDED, TRIANGLE_HAS_NORMALS, TRIANGLE_TWO_SIDED};

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
    pub emission: [f32; 3],
    /// `MATERIAL_EMISSIVE`, `MATERIAL_ONE_SIDED`.
    pub flags: u32,
    /// The BSDF's parameter block (`Bsdf::pack`: its kind's file says what each slot holds).
    pub p0: [f32; 4],
    pub p1: [f32; 4],
    pub p2: [f32; 4],
    /// The `BsdfKind` (its `constant()`, generated into the WGSL as `BSDF_KIND_*`).
    pub kind: u32,
    pub _pad: [u32; 3],
}

/// A triangle as the kernel reads it (`Triangle`, bvh.wgsl): vertices, material, the light it
/// is (`u32::MAX`: none) and flags.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTriangle {
    pub p0: [f32; 3],
    pub material: u32,
    pub p1: [f32; 3],
    pub light: u32,
    pub p2: [f32; 3],
    pub flags: u32,
}

/// A triangle's vertex normals (`TriangleNormals`, bvh.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTriangleNormals {
    pub n0: [f32; 3],
    pub _pad0: u32,
    pub n1: [f32; 3],
    pub _pad1: u32,
    pub n2: [f32; 3],
    pub _pad2: u32,
}

/// One entry of the light table (`LightEntry`, light_table.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuLight {
    pub object: u32,
    pub power_prob: f32,
    pub alias_index: u32,
    pub threshold: f32,
    /// Its `EmitterKind`.
    pub kind: u32,
}

/// Most triangles one storage binding of `binding_limit` bytes holds (the triangle array is
/// the largest of the three).
pub fn max_triangles(binding_limit: u64) -> u64 {
    binding_limit / std::mem::size_of::<GpuTriangle>() as u64
}

/// The scene's triangles packed for the kernel: in the BVH's leaf order, with the BVH and the
/// light table.
#[derive(Debug, Clone)]
pub struct PackedTriangles {
    pub triangles: Vec<GpuTriangle>,
    /// One per triangle where some mesh has normals, else empty.
    pub normals: Vec<GpuTriangleNormals>,
    pub bvh: Bvh,
    pub lights: Vec<GpuLight>,
}

impl PackedTriangles {
    /// Bytes of the four storage buffers.
    pub fn gpu_bytes(&self) -> usize {
        std::mem::size_of_val(&self.triangles[..])
            + std::mem::size_of_val(&self.normals[..])
            + std::mem::size_of_val(&self.bvh.nodes[..])
            + std::mem::size_of_val(&self.lights[..])
    }

    /// Builds the BVH over every mesh triangle and lays the triangles out in its leaf order,
    /// with the light table of `Scene::sampled_lights(sample_environment)`.
    pub fn new(scene: &Scene, sample_environment: bool) -> PackedTriangles {
        // Scene order: (mesh, triangle) of every triangle; triangle t of mesh m is number
        // first[m] + t, and light_of[that] the light it is.
        let refs: Vec<(usize, usize)> =
            scene.meshes.iter().enumerate().flat_map(|(m, mesh)| (0..mesh.triangles.len()).map(move |t| (m, t))).collect();
        let first: Vec<usize> = scene.meshes.iter().scan(0, |n, mesh| Some(std::mem::replace(n, *n + mesh.triangles.len()))).collect();
        let lights = scene.sampled_lights(sample_environment);
        let mut light_of = vec![u32::MAX; refs.len()];
        for (l, light) in lights.iter().enumerate() {
            if let Light::Triangle { mesh, triangle } = *light {
                light_of[first[mesh] + triangle] = l as u32;
            }
        }
        let geometry: Vec<crate::accel::Triangle> =
            refs.iter().map(|&(m, t)| scene.meshes[m].vertices(t).map(|v| v.as_vec3())).collect();
        let bvh = if geometry.is_empty() { Bvh { nodes: vec![BvhNode::zeroed()], order: Vec::new(), depth: 0 } } else { Bvh::build(&geometry) };
        let any_normals = scene.meshes.iter().any(|m| !m.normals.is_empty());
        let mut gpu_index = vec![0u32; refs.len()];
        let mut triangles = Vec::with_capacity(refs.len());
        let mut normals = Vec::new();
        for (k, &i) in bvh.order.iter().enumerate() {
            let (m, t) = refs[i as usize];
            gpu_index[i as usize] = k as u32;
            let mesh = &scene.meshes[m];
            let [p0, p1, p2] = mesh.vertices(t).map(f3);
            let has_normals = !mesh.normals.is_empty();
            let flags = if mesh.two_sided_emission { TRIANGLE_TWO_SIDED } else { 0 } | if has_normals { TRIANGLE_HAS_NORMALS } else { 0 };
            triangles.push(GpuTriangle { p0, material: mesh.material as u32, p1, light: light_of[i as usize], p2, flags });
            if any_normals {
                let [n0, n1, n2] = if has_normals { mesh.triangles[t].map(|v| f3(mesh.normals[v as usize])) } else { [[0.0; 3]; 3] };
                normals.push(GpuTriangleNormals { n0, _pad0: 0, n1, _pad1: 0, n2, _pad2: 0 });
            }
        }
        // The light table, each kind's lights one range in `EmitterKind` order: sphere light l
        // is kernel sphere l, a triangle is named by its index in leaf order, the environment
        // by nothing.
        let weights: Vec<f64> = lights.iter().map(|&l| scene.light_power(l)).collect();
        let alias = AliasTable::new(&weights);
        let lights = lights
            .iter()
            .enumerate()
            .map(|(l, light)| GpuLight {
                object: match *light {
                    Light::Sphere(_) => l as u32,
                    Light::Triangle { mesh, triangle } => gpu_index[first[mesh] + triangle],
                    Light::Environment => 0,
                },
                power_prob: alias.prob[l] as f32,
                alias_index: alias.alias[l],
                threshold: alias.threshold[l] as f32,
                kind: light.kind().constant(),
            })
            .collect();
        PackedTriangles { triangles, normals, bvh, lights }
    }
}

pub(crate) fn f3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

/// The scene's uniform buffers, each allocated at its full capacity (the WGSL arrays are
/// fixed-size); the kernel reads only the first elements, as many as its pipeline constants say.
pub struct SceneBuffers {
    pub spheres: wgpu::Buffer,
    pub planes: wgpu::Buffer,
    pub materials: wgpu::Buffer,
    /// Storage buffers of the triangles, their normals, the BVH and the light table (one
    /// zero element where the scene has none: bindings cannot be empty).
    pub triangles: wgpu::Buffer,
    pub triangle_normals: wgpu::Buffer,
    pub bvh_nodes: wgpu::Buffer,
    pub lights: wgpu::Buffer,
    /// The first `BRUTE_FORCE_TRIANGLES` triangles (all of a small scene), as a uniform buffer.
    pub small_triangles: wgpu::Buffer,
}

impl SceneBuffers {
    /// The bind-group entries of every scene buffer, each at its binding (`shaders::bindings`):
    /// a new buffer of the scene is listed here and nowhere else.
    pub fn entries(&self) -> Vec<wgpu::BindGroupEntry<'_>> {
        use crate::shaders::bindings::{self, entry};
        vec![
            entry(bindings::SPHERES, &self.spheres),
            entry(bindings::PLANES, &self.planes),
            entry(bindings::MATERIALS, &self.materials),
            entry(bindings::TRIANGLES, &self.triangles),
            entry(bindings::TRIANGLE_NORMALS, &self.triangle_normals),
            entry(bindings::BVH_NODES, &self.bvh_nodes),
            entry(bindings::LIGHTS, &self.lights),
            entry(bindings::SMALL_TRIANGLES, &self.small_triangles),
        ]
    }
}

/// A read-only storage buffer holding `items` (at least one zeroed element).
fn storage_array<T: Pod + Zeroable>(device: &wgpu::Device, label: &str, items: &[T]) -> wgpu::Buffer {
    let mut bytes = bytemuck::cast_slice::<T, u8>(items).to_vec();
    if bytes.is_empty() {
        bytes.resize(std::mem::size_of::<T>(), 0);
    }
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: &bytes, usage: wgpu::BufferUsages::STORAGE })
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
                let [p0, p1, p2] = m.bsdf.pack();
                GpuMaterial {
                    emission: f3(m.emission),
                    flags: if m.is_emissive() { MATERIAL_EMISSIVE } else { 0 } | if m.two_sided { 0 } else { MATERIAL_ONE_SIDED },
                    p0,
                    p1,
                    p2,
                    kind: m.bsdf_kind().constant(),
                    _pad: [0; 3],
                }
            })
            .collect()
    }

    /// The spheres in kernel order (`features::sphere_order`): the lights first.
    pub fn pack_spheres(scene: &Scene) -> Vec<GpuSphere> {
        super::features::sphere_order(scene)
            .into_iter()
            .map(|i| {
                let s = &scene.spheres[i];
                GpuSphere { center: f3(s.center), radius: s.radius as f32, material: s.material as u32, _pad: [0; 3] }
            })
            .collect()
    }

    /// The planes in kernel order (`features::plane_order`): those that can occlude a light first.
    pub fn pack_planes(scene: &Scene) -> Vec<GpuPlane> {
        super::features::plane_order(scene)
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

    pub fn new(device: &wgpu::Device, scene: &Scene, packed: &PackedTriangles) -> SceneBuffers {
        SceneBuffers {
            spheres: uniform_array(device, "spheres", &Self::pack_spheres(scene), MAX_SPHERES),
            planes: uniform_array(device, "planes", &Self::pack_planes(scene), MAX_PLANES),
            materials: uniform_array(device, "materials", &Self::pack_materials(scene), MAX_MATERIALS),
            triangles: storage_array(device, "triangles", &packed.triangles),
            triangle_normals: storage_array(device, "triangle normals", &packed.normals),
            bvh_nodes: storage_array(device, "bvh nodes", &packed.bvh.nodes),
            lights: storage_array(device, "lights", &packed.lights),
            small_triangles: {
                let n = packed.triangles.len().min(crate::accel::BRUTE_FORCE_TRIANGLES as usize);
                uniform_array(device, "small triangles", &packed.triangles[..n], crate::accel::BRUTE_FORCE_TRIANGLES as usize)
            },
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
        assert_eq!(std::mem::size_of::<GpuMaterial>(), 80);
        assert_eq!(std::mem::size_of::<GpuTriangle>(), 48);
        assert_eq!(std::mem::size_of::<GpuTriangleNormals>(), 48);
        assert_eq!(std::mem::size_of::<GpuLight>(), 20);
    }

    #[test]
    fn capacities_fit_default_uniform_bindings() {
        let limit = wgpu::Limits::default().max_uniform_buffer_binding_size as usize;
        assert!(MAX_SPHERES * std::mem::size_of::<GpuSphere>() <= limit);
        assert!(MAX_PLANES * std::mem::size_of::<GpuPlane>() <= limit);
        assert!(MAX_MATERIALS * std::mem::size_of::<GpuMaterial>() <= limit);
    }
}
