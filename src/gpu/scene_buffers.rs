//! The scene packed for the GPU. Layouts mirror the structs in `shaders/scene.wgsl` (uniform
//! rules: a vec3 is 16-byte aligned, 12 bytes long), checked against naga's reflection of the
//! WGSL by `tests/shader_layouts.rs`.
//!
//! Spheres and planes with the quadrics go in uniform buffers of fixed capacity (the `MAX_*`
//! below, also generated into the WGSL): the kernel reads them at lane-uniform indices, which
//! uniform buffers serve as broadcasts. Each stays under wgpu's default 64 KiB binding limit
//! (`crate::scene::MAX_*`, enforced by scene validation). The materials go in a texel table
//! (`MATERIAL_TEXELS` texels each, the bytes of `GpuMaterial`): each hit reads its own material,
//! at an index that differs per lane.

use std::sync::Arc;

use bytemuck::{Pod, Zeroable};
use glam::DVec3;
use wgpu::util::DeviceExt;

use crate::accel::{Bvh, BvhNode};
use crate::scene::{BsdfData, EmitterKind, Light, Scene, MAX_DELTA_LIGHTS, MAX_PLANES, MAX_QUADRICS, MAX_SPHERES};
use crate::shaders::bindings::{self, Binding};
use crate::shaders::flags::{MATERIAL_EMISSIVE, MATERIAL_ONE_SIDED, NO_BACK, NO_BLEND, NO_BUMP_MAP, NO_EMISSION_TEXTURE, NO_LIGHT_TEXTURE, NO_NORMAL_MAP, TRIANGLE_HAS_NORMALS, TRIANGLE_HAS_UVS, TRIANGLE_TWO_SIDED};

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
    pub p3: [f32; 4],
    /// The `BsdfKind` (its `constant()`, generated into the WGSL as `BSDF_KIND_*`).
    pub kind: u32,
    /// Mitsuba's `mask` (`Opacity::pack`): the opacity, or -(start + 1) of its texture's record
    /// in the BSDF data; 1 where the material is opaque.
    pub opacity: f32,
    /// Mitsuba's `twosided` with two BSDFs: the material whose BSDF scatters on the back
    /// (`Material::back`), `NO_BACK` where none.
    pub back: u32,
    /// Mitsuba's `normalmap` (`NormalMap::pack`): the start of its texture's record in the BSDF
    /// data, `NO_NORMAL_MAP` where none.
    pub normal_map: u32,
    /// Mitsuba's `bumpmap` (`BumpMap::pack`): the start of its record in the BSDF data (the
    /// scale, then the texture's record), `NO_BUMP_MAP` where none.
    pub bump_map: u32,
    /// Mitsuba's `blendbsdf` (`Material::blend`): the material whose BSDF is blended with this
    /// one's, `NO_BLEND` where none, and its weight (`Opacity::pack`: the weight, or -(start +
    /// 1) of its texture's record in the BSDF data).
    pub blend: u32,
    pub blend_weight: f32,
    /// Mitsuba's area emitter with a textured `radiance` (`Material::emission_texture`): the
    /// start of its texture's record in the BSDF data, `NO_EMISSION_TEXTURE` where its emission
    /// is one colour.
    pub emission_texture: u32,
}

/// A disk or cylinder (`Quadric`, scene.wgsl): its affine maps as rows (object = to_object
/// applied to world; a row r maps p to dot(r.xyz, p) + r.w), the disk's unit normal, and the
/// rest.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuQuadric {
    /// World to object, rows x, y, z.
    pub object_x: [f32; 4],
    pub object_y: [f32; 4],
    pub object_z: [f32; 4],
    /// Object to world, rows x, y, z.
    pub world_x: [f32; 4],
    pub world_y: [f32; 4],
    pub world_z: [f32; 4],
    /// A disk's unit normal in world space, flip_normals applied; an SDF grid's record start
    /// in the BSDF data (the bits of the first number) and 1 for smooth normals.
    pub normal: [f32; 3],
    pub material: u32,
    /// Surface area in world space (a light's density).
    pub area: f32,
    /// -1 where flip_normals, else 1 (a cylinder's normal is computed at the hit).
    pub normal_sign: f32,
    /// The light it is (`u32::MAX`: none).
    pub light: u32,
    /// `TRIANGLE_TWO_SIDED` where it emits on both sides.
    pub flags: u32,
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

/// A triangle's texture coordinates at its three vertices (`TriangleUvs`, bvh.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuTriangleUvs {
    pub uv0: [f32; 2],
    pub uv1: [f32; 2],
    pub uv2: [f32; 2],
}

/// A sphere's object axes in world space (`SphereAxes`, intersect.wgsl), which place its uv
/// parametrisation (`Sphere::uv`).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuSphereAxes {
    pub x: [f32; 3],
    pub _pad0: u32,
    pub y: [f32; 3],
    pub _pad1: u32,
    pub z: [f32; 3],
    pub _pad2: u32,
}

/// A point, spot or directional light (`DeltaLight`, emitter.wgsl): what each kind's file reads.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuDeltaLight {
    /// Point and spot: the position.
    pub position: [f32; 3],
    /// Spot: cos of the cutoff angle.
    pub cos_cutoff: f32,
    /// Spot: the axis it shines along; directional: the direction the light travels.
    pub direction: [f32; 3],
    /// Spot: cos of the beam width.
    pub cos_beam: f32,
    /// Point and spot: the intensity (W/sr); directional: the irradiance.
    pub intensity: [f32; 3],
    /// Spot: the cutoff angle in radians.
    pub cutoff: f32,
    /// The light's frame x axis (a projected texture's u direction, Mitsuba's "left").
    pub x_axis: [f32; 3],
    /// Spot: 1 / (cutoff - beam width) in radians (infinite where they meet: a hard edge).
    pub inv_transition: f32,
    /// The light's frame y axis (a projected texture's v direction).
    pub y_axis: [f32; 3],
    /// The projected texture's record in the BSDF data, `NO_LIGHT_TEXTURE` where none.
    pub texture: u32,
    /// uv of direction d in the light's frame: 1/2 + uv_scale (d_x, d_y) / d_z.
    pub uv_scale: [f32; 2],
    pub _pad: [u32; 2],
}

// A material is `MATERIAL_TEXELS` texels of the materials' table (`material_record`, scene.wgsl).
const _: () = assert!(std::mem::size_of::<GpuMaterial>() == 16 * bindings::MATERIAL_TEXELS as usize);

/// One entry of the light table (`LightEntry`, light_table.wgsl).
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub struct GpuLight {
    pub object: u32,
    pub power_prob: f32,
    pub alias_index: u32,
    pub threshold: f32,
}

/// Most triangles an adapter holds whose largest storage binding is `binding_limit` bytes and
/// whose 2D textures are at most `texture_rows` texels high: the vertex normals' storage array
/// takes 48 bytes per triangle, and the texel tables (`bindings::Kind::TexelTable`) 3 texels per
/// triangle and 4 per BVH node record, of which there are fewer than 2 per triangle (so 8 texels
/// per triangle bound both).
pub fn max_triangles(binding_limit: u64, texture_rows: u64) -> u64 {
    let in_binding = binding_limit / std::mem::size_of::<GpuTriangleNormals>() as u64;
    let in_texel_tables = crate::shaders::bindings::TEXEL_TABLE_WIDTH as u64 * texture_rows / 8;
    in_binding.min(in_texel_tables)
}

/// The scene's triangles packed for the kernel: in the BVH's leaf order, with the BVH and the
/// light table.
#[derive(Debug, Clone)]
pub struct PackedTriangles {
    pub triangles: Vec<GpuTriangle>,
    /// One per triangle where some mesh has normals, else empty.
    pub normals: Vec<GpuTriangleNormals>,
    /// One per triangle where some mesh has texture coordinates, else empty.
    pub uvs: Vec<GpuTriangleUvs>,
    /// The mesh attributes that textures read (`Scene::mesh_attribute_names`), the values at
    /// each triangle's three corners as RGB (a grey for one channel; zero where its mesh has no
    /// such attribute): triangle k (leaf order), slot s, corner c at (k slots + s) 3 + c
    /// (`mesh_attributes` in texture.wgsl).
    pub attributes: Vec<[f32; 4]>,
    pub bvh: Bvh,
    pub lights: Vec<GpuLight>,
}

impl PackedTriangles {
    /// Bytes of the triangles, their normals and uvs, the BVH (nodes and parents) and the
    /// light table.
    pub fn gpu_bytes(&self) -> usize {
        std::mem::size_of_val(&self.triangles[..])
            + std::mem::size_of_val(&self.normals[..])
            + std::mem::size_of_val(&self.uvs[..])
            + std::mem::size_of_val(&self.attributes[..])
            + self.bvh.nodes.len() * std::mem::size_of::<crate::accel::BvhRecord>()
            + std::mem::size_of_val(&self.bvh.pair_parents()[..])
            + std::mem::size_of_val(&self.lights[..])
    }

    /// The distinct vertex positions of a small scene's triangles (kernel order) and each
    /// triangle's corners among them; None where the kernel traverses the BVH.
    pub fn shared_vertices(&self) -> Option<(crate::accel::SharedVertices, Vec<[f32; 3]>)> {
        crate::accel::SharedVertices::of(&self.corners())
    }

    /// Each triangle's corners p0, p1, p2 (kernel order).
    pub fn corners(&self) -> Vec<[[f32; 3]; 3]> {
        self.triangles.iter().map(|t| [t.p0, t.p1, t.p2]).collect()
    }

    /// Each triangle's material (kernel order).
    pub fn materials(&self) -> Vec<u32> {
        self.triangles.iter().map(|t| t.material).collect()
    }

    /// Builds the BVH over every mesh triangle and lays the triangles out in its leaf order,
    /// with the light table of `Scene::sampled_lights(sample_environment)`.
    pub fn new(scene: &Scene, sample_environment: bool) -> PackedTriangles {
        // Scene order: (mesh, triangle) of every triangle; triangle t of mesh m is number
        // first[m] + t, and light_of[that] the light it is.
        let refs: Vec<(usize, usize)> =
            scene.meshes.iter().enumerate().flat_map(|(m, mesh)| (0..mesh.triangles.len()).map(move |t| (m, t))).collect();
        let first: Vec<usize> = scene.meshes.iter().scan(0, |n, mesh| Some(std::mem::replace(n, *n + mesh.triangles.len()))).collect();
        let (lights, alias) = scene.light_selection(sample_environment);
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
        let any_uvs = scene.meshes.iter().any(|m| !m.uvs.is_empty());
        let mut gpu_index = vec![0u32; refs.len()];
        let mut triangles = Vec::with_capacity(refs.len());
        let mut normals = Vec::new();
        let mut uvs = Vec::new();
        for (k, &i) in bvh.order.iter().enumerate() {
            let (m, t) = refs[i as usize];
            gpu_index[i as usize] = k as u32;
            let mesh = &scene.meshes[m];
            let [p0, p1, p2] = mesh.vertices(t).map(f3);
            let has_normals = !mesh.normals.is_empty();
            let has_uvs = !mesh.uvs.is_empty();
            let flags = if mesh.two_sided_emission { TRIANGLE_TWO_SIDED } else { 0 }
                | if has_normals { TRIANGLE_HAS_NORMALS } else { 0 }
                | if has_uvs { TRIANGLE_HAS_UVS } else { 0 };
            triangles.push(GpuTriangle { p0, material: mesh.material as u32, p1, light: light_of[i as usize], p2, flags });
            if any_normals {
                let [n0, n1, n2] = if has_normals { mesh.triangles[t].map(|v| f3(mesh.normals[v as usize])) } else { [[0.0; 3]; 3] };
                normals.push(GpuTriangleNormals { n0, _pad0: 0, n1, _pad1: 0, n2, _pad2: 0 });
            }
            if any_uvs {
                let [uv0, uv1, uv2] =
                    if has_uvs { mesh.triangles[t].map(|v| mesh.uvs[v as usize].map(|c| c as f32)) } else { [[0.0; 2]; 3] };
                uvs.push(GpuTriangleUvs { uv0, uv1, uv2 });
            }
        }
        let mut attributes = Vec::new();
        let names = scene.mesh_attribute_names();
        if !names.is_empty() {
            for &i in &bvh.order {
                let (m, t) = refs[i as usize];
                let mesh = &scene.meshes[m];
                for name in &names {
                    let corners = mesh.attribute(name).map_or([[0.0; 3]; 3], |a| a.corners(t, mesh.triangles[t]));
                    attributes.extend(corners.map(|[r, g, b]| [r, g, b, 0.0]));
                }
            }
        }
        // The light table, each kind's lights one range in `EmitterKind` order: sphere light l
        // is kernel sphere l, a triangle is named by its index in leaf order, the environment
        // by nothing.
        let lights = lights
            .iter()
            .enumerate()
            .map(|(l, light)| GpuLight {
                object: match *light {
                    Light::Sphere(_) => l as u32,
                    // Each kind's lights come first among its quadrics, in light order.
                    Light::Disk(i) | Light::Cylinder(i) => super::features::quadric_order(scene).iter().position(|&q| q == i).unwrap_or(0) as u32,
                    Light::Triangle { mesh, triangle } => gpu_index[first[mesh] + triangle],
                    // Index into `delta_lights`: the point lights, the spot lights, the
                    // directional lights, the projectors (`SceneBuffers::pack_delta_lights`).
                    Light::Point(i) => i as u32,
                    Light::Spot(i) => (scene.point_lights.len() + i) as u32,
                    Light::Directional(i) => (scene.point_lights.len() + scene.spot_lights.len() + i) as u32,
                    Light::Projector(i) => (scene.point_lights.len() + scene.spot_lights.len() + scene.directional_lights.len() + i) as u32,
                    Light::Environment => 0,
                },
                power_prob: alias.prob[l] as f32,
                alias_index: alias.alias[l],
                threshold: alias.threshold[l] as f32,
            })
            .collect();
        PackedTriangles { triangles, normals, uvs, attributes, bvh, lights }
    }
}

pub(crate) fn f3(v: DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

/// The bytes of one scene buffer, as it is uploaded, and the binding it goes to.
pub struct SceneBufferContents {
    pub binding: Binding,
    pub label: &'static str,
    pub bytes: Vec<u8>,
}

/// The scene's buffers and texel tables on the device, each at its binding
/// (`shaders::bindings`).
pub struct SceneBuffers {
    pub buffers: Vec<(Binding, wgpu::Buffer)>,
    pub tables: Vec<(Binding, wgpu::Texture, wgpu::TextureView)>,
}

impl SceneBuffers {
    /// The bind-group entries of every scene buffer and texel table.
    pub fn entries(&self) -> Vec<wgpu::BindGroupEntry<'_>> {
        let buffers = self.buffers.iter().map(|(binding, buffer)| bindings::entry(*binding, buffer));
        let tables = self.tables.iter().map(|(binding, _, view)| bindings::texel_table_entry(binding.number, view));
        buffers.chain(tables).collect()
    }

    /// Every buffer of the scene, its bytes and its binding: a new buffer of the scene is
    /// listed here and nowhere else. Spheres, planes and the small scene's vertex positions
    /// are uniform arrays at their full capacity (the WGSL arrays are fixed-size; the kernel
    /// reads only the first elements, as many as its pipeline constants say); the storage
    /// buffers and texel tables (triangles, their normals and uvs, the BVH, the materials, the
    /// light table, the spheres' axes) hold one zero element where the scene has none, as
    /// bindings cannot be empty.
    pub fn contents(scene: &Scene, packed: &PackedTriangles) -> Vec<SceneBufferContents> {
        let contents = |binding: Binding, label: &'static str, bytes: Vec<u8>| SceneBufferContents { binding, label, bytes };
        let (materials, mut bsdf_data) = Self::pack_materials(scene);
        let delta_lights = Self::pack_delta_lights(scene, &mut bsdf_data);
        let surfaces = Self::pack_surfaces(scene, &mut bsdf_data);
        vec![
            contents(bindings::SPHERES, "spheres", uniform_array(&Self::pack_spheres(scene), MAX_SPHERES)),
            contents(bindings::SURFACES, "planes and quadrics", surfaces),
            contents(bindings::MATERIALS, "materials", storage_array(&materials)),
            contents(bindings::DELTA_LIGHTS, "delta lights", uniform_array(&delta_lights, MAX_DELTA_LIGHTS)),
            contents(bindings::BSDF_DATA, "bsdf data", storage_array(&bsdf_data.0)),
            contents(bindings::ENVIRONMENT_MAP, "environment map", storage_array(&scene.environment_map.as_ref().map_or(Vec::new(), |m| m.pack()))),
            contents(bindings::TRIANGLES, "triangles", storage_array(&packed.triangles)),
            contents(bindings::TRIANGLE_NORMALS, "triangle normals", storage_array(&packed.normals)),
            contents(bindings::TRIANGLE_UVS, "triangle uvs", storage_array(&packed.uvs)),
            contents(bindings::MESH_ATTRIBUTES, "mesh attributes", storage_array(&packed.attributes)),
            contents(bindings::BVH_NODES, "bvh nodes", storage_array(&packed.bvh.records())),
            contents(bindings::BVH_PARENTS, "bvh parents", storage_array(&packed.bvh.pair_parents())),
            contents(bindings::LIGHTS, "lights", storage_array(&packed.lights)),
            contents(bindings::SPHERE_AXES, "sphere axes", storage_array(&Self::pack_sphere_axes(scene))),
            contents(
                bindings::SMALL_VERTICES,
                "small vertices",
                uniform_array(
                    &packed.shared_vertices().map_or(Vec::new(), |(_, positions)| positions.iter().map(|p| [p[0], p[1], p[2], 0.0]).collect()),
                    crate::accel::MAX_SHARED_VERTICES as usize,
                ),
            ),
        ]
    }

    /// Uploads `contents`: buffers, and texel tables where the binding is one.
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, scene: &Scene, packed: &PackedTriangles) -> SceneBuffers {
        let (mut buffers, mut tables) = (Vec::new(), Vec::new());
        for c in Self::contents(scene, packed) {
            let usage = match c.binding.kind {
                bindings::Kind::Uniform => wgpu::BufferUsages::UNIFORM,
                bindings::Kind::Storage { .. } => wgpu::BufferUsages::STORAGE,
                bindings::Kind::TexelTable => {
                    let (texture, view) = bindings::texel_table(device, queue, c.label, &c.bytes);
                    tables.push((c.binding, texture, view));
                    continue;
                }
            };
            let descriptor = wgpu::util::BufferInitDescriptor { label: Some(c.label), contents: &c.bytes, usage };
            buffers.push((c.binding, device.create_buffer_init(&descriptor)));
        }
        SceneBuffers { buffers, tables }
    }
}

/// The bytes of a read-only storage buffer holding `items` (at least one zeroed element).
fn storage_array<T: Pod + Zeroable>(items: &[T]) -> Vec<u8> {
    let mut bytes = bytemuck::cast_slice::<T, u8>(items).to_vec();
    if bytes.is_empty() {
        bytes.resize(std::mem::size_of::<T>(), 0);
    }
    bytes
}

/// The bytes of a uniform buffer of `capacity` elements of `T`, starting with `items`, zero
/// after them. Callers (validation) guarantee `items.len() <= capacity`.
fn uniform_array<T: Pod>(items: &[T], capacity: usize) -> Vec<u8> {
    let mut bytes = bytemuck::cast_slice::<T, u8>(items).to_vec();
    bytes.resize(capacity.max(items.len()) * std::mem::size_of::<T>(), 0);
    bytes
}

impl SceneBuffers {
    /// The materials in scene order, and the numbers their BSDFs read beyond their blocks.
    pub fn pack_materials(scene: &Scene) -> (Vec<GpuMaterial>, BsdfData) {
        let mut data = BsdfData(Vec::new(), scene.mesh_attribute_names());
        // The media's records first (`medium_at` in medium.wgsl reads medium k at
        // k MEDIUM_RECORD_FLOATS), then their grids, then every BSDF's data.
        let records = crate::scene::media::MEDIUM_RECORD_FLOATS;
        data.0.resize(scene.media.len() * records, 0.0);
        for (k, m) in scene.media.iter().enumerate() {
            let record = m.pack(&mut data);
            data.0[k * records..(k + 1) * records].copy_from_slice(&record);
        }
        let materials = scene
            .materials
            .iter()
            .map(|m| {
                let [p0, p1, p2, p3] = m.bsdf.pack(&mut data);
                GpuMaterial {
                    emission: f3(m.emission),
                    flags: if m.is_emissive() { MATERIAL_EMISSIVE } else { 0 }
                        | if m.two_sided { 0 } else { MATERIAL_ONE_SIDED }
                        | crate::shaders::flags::medium_flags(m.interior, m.exterior),
                    p0,
                    p1,
                    p2,
                    p3,
                    kind: m.bsdf_kind().constant(),
                    opacity: m.opacity.as_ref().map_or(1.0, |o| o.pack(&mut data)),
                    back: m.back.map_or(NO_BACK, |b| b as u32),
                    normal_map: m.normal_map.as_ref().map_or(NO_NORMAL_MAP, |n| n.pack(&mut data)),
                    bump_map: m.bump_map.as_ref().map_or(NO_BUMP_MAP, |b| b.pack(&mut data)),
                    blend: m.blend.as_ref().map_or(NO_BLEND, |b| b.material as u32),
                    blend_weight: m.blend.as_ref().map_or(0.0, |b| b.weight.pack(&mut data)),
                    emission_texture: m.emission_texture.as_ref().map_or(NO_EMISSION_TEXTURE, |t| t.pack(&mut data)),
                }
            })
            .collect();
        (materials, data)
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

    /// The delta lights as `delta_lights` holds them: the point lights, then the spot lights,
    /// then the directional lights, then the projectors, each in scene order (the light table names them by this
    /// index); the textures they project are appended to `data`.
    pub fn pack_delta_lights(scene: &Scene, data: &mut BsdfData) -> Vec<GpuDeltaLight> {
        let zero = GpuDeltaLight { texture: NO_LIGHT_TEXTURE, ..GpuDeltaLight::zeroed() };
        let points = scene.point_lights.iter().map(|l| GpuDeltaLight { position: f3(l.position), intensity: f3(l.intensity), ..zero });
        let spots: Vec<GpuDeltaLight> = scene
            .spot_lights
            .iter()
            .map(|l| {
                let (cutoff, beam) = (l.cutoff_angle.to_radians(), l.beam_width.to_radians());
                let mut g = GpuDeltaLight {
                    position: f3(l.position),
                    direction: f3(l.direction),
                    intensity: f3(l.intensity),
                    cos_cutoff: cutoff.cos() as f32,
                    cos_beam: beam.cos() as f32,
                    cutoff: cutoff as f32,
                    inv_transition: (1.0 / (cutoff - beam)) as f32,
                    ..zero
                };
                if let Some(t) = &l.texture {
                    // spot.cpp's direction_to_uv: 1/2 + d_xy / (2 d_z tan(cutoff)).
                    let (x, y) = crate::scene::emitters::light_frame(l.direction, t.up);
                    g.x_axis = f3(x);
                    g.y_axis = f3(y);
                    g.texture = t.texture.pack(data);
                    g.uv_scale = [(0.5 / cutoff.tan()) as f32; 2];
                }
                g
            })
            .collect();
        let directionals = scene.directional_lights.iter().map(|l| GpuDeltaLight { direction: f3(l.direction), intensity: f3(l.irradiance), ..zero });
        // A projector: pi scale as its intensity, which the image's value at uv times
        // 1 / cos^3(theta) makes the intensity towards the point (`ProjectorLight`).
        let projectors: Vec<GpuDeltaLight> = scene
            .projector_lights
            .iter()
            .map(|l| {
                let (x, y) = crate::scene::emitters::light_frame(l.direction, l.up);
                let (su, sv) = l.uv_scale();
                GpuDeltaLight {
                    position: f3(l.position),
                    direction: f3(l.direction),
                    intensity: [(std::f64::consts::PI * l.scale) as f32; 3],
                    x_axis: f3(x),
                    y_axis: f3(y),
                    texture: l.irradiance.pack(data),
                    uv_scale: [su as f32, sv as f32],
                    ..zero
                }
            })
            .collect();
        points.chain(spots).chain(directionals).chain(projectors).collect()
    }

    /// The spheres' object axes, in kernel order.
    pub fn pack_sphere_axes(scene: &Scene) -> Vec<GpuSphereAxes> {
        super::features::sphere_order(scene)
            .into_iter()
            .map(|i| {
                let [x, y, z] = scene.spheres[i].axes.map(f3);
                GpuSphereAxes { x, _pad0: 0, y, _pad1: 0, z, _pad2: 0 }
            })
            .collect()
    }

    /// The `Surfaces` buffer (scene.wgsl): the planes at their full capacity, then the quadrics
    /// at theirs.
    pub fn pack_surfaces(scene: &Scene, data: &mut BsdfData) -> Vec<u8> {
        let mut bytes = uniform_array(&Self::pack_planes(scene), MAX_PLANES);
        bytes.extend(uniform_array(&Self::pack_quadrics(scene, data), MAX_QUADRICS));
        bytes
    }

    /// The quadrics in kernel order (`features::quadric_order`): each kind's lights first, each
    /// naming its light-table entry (the disk lights' follow the sphere and triangle lights',
    /// the cylinder lights' the disk lights'). An SDF grid's values are appended to `data`
    /// (each grid once, however many quadrics share it).
    pub fn pack_quadrics(scene: &Scene, data: &mut BsdfData) -> Vec<GpuQuadric> {
        let mut grids: Vec<(*const crate::scene::quadrics::SdfGrid, u32)> = Vec::new();
        let first_disk_light = (scene.lights_of(EmitterKind::Sphere).len() + scene.lights_of(EmitterKind::Triangle).len()) as u32;
        let num_disk_lights = scene.lights_of(EmitterKind::Disk).len();
        let num_disks = scene.quadrics.iter().filter(|q| q.kind == crate::scene::QuadricKind::Disk).count();
        let num_cylinder_lights = scene.lights_of(EmitterKind::Cylinder).len();
        let rows = |m: glam::DAffine3| {
            let c = m.to_cols_array();
            // Columns x, y, z, translation (3 each) to rows [x_r, y_r, z_r, t_r].
            [0, 1, 2].map(|r| [c[r] as f32, c[3 + r] as f32, c[6 + r] as f32, c[9 + r] as f32])
        };
        super::features::quadric_order(scene)
            .into_iter()
            .enumerate()
            .map(|(k, i)| {
                let q = &scene.quadrics[i];
                let sign = if q.flip_normals { -1.0 } else { 1.0 };
                let ([object_x, object_y, object_z], [world_x, world_y, world_z]) = match q.curve() {
                    // A curve segment (quadrics/linear_curve.wgsl's layout): its ends and radii,
                    // the frame of the angle around its axis, its number and the shape's count,
                    // whether it starts its curve.
                    Some(c) => {
                        let axis = c.axis();
                        let (u_rot, u_rad) = crate::scene::quadrics::angle_frame(axis);
                        let v4 = |v: DVec3, w: f64| [v.x as f32, v.y as f32, v.z as f32, w as f32];
                        ([v4(c.p0, c.r0), v4(c.p1, c.r1), v4(u_rot, c.index as f64)], [v4(u_rad, c.count as f64), v4(axis, if c.first { 1.0 } else { 0.0 }), [0.0; 4]])
                    }
                    None => match q.bspline() {
                        // A B-spline segment (quadrics/bspline_curve.wgsl's layout): its control
                        // points and radii, its number, the shape's count and its margin.
                        Some(s) => {
                            let v4 = |k: usize| [s.p[k].x as f32, s.p[k].y as f32, s.p[k].z as f32, s.r[k] as f32];
                            ([v4(0), v4(1), v4(2)], [v4(3), [s.index as f32, s.count as f32, s.margin, 0.0], [0.0; 4]])
                        }
                        None => (rows(q.to_object()), rows(q.to_world)),
                    },
                };
                // An SDF grid (quadrics/sdf_grid.wgsl's layout): where its record starts in the
                // BSDF data (the bits of normal.x), 1 for smooth normals (normal.y).
                let normal = match q.grid() {
                    Some(g) => {
                        let start = match grids.iter().find(|(p, _)| std::ptr::eq(*p, Arc::as_ptr(g))) {
                            Some(&(_, start)) => start,
                            None => {
                                let start = g.pack(data);
                                grids.push((Arc::as_ptr(g), start));
                                start
                            }
                        };
                        [f32::from_bits(start), if g.smooth { 1.0 } else { 0.0 }, 0.0]
                    }
                    None => f3(crate::scene::quadrics::normal_to_world(&q.to_world, DVec3::Z) * sign),
                };
                GpuQuadric {
                    object_x,
                    object_y,
                    object_z,
                    world_x,
                    world_y,
                    world_z,
                    normal,
                    material: q.material as u32,
                    area: q.area() as f32,
                    normal_sign: sign as f32,
                    light: if k < num_disk_lights {
                        first_disk_light + k as u32
                    } else if k >= num_disks && k < num_disks + num_cylinder_lights {
                        first_disk_light + (num_disk_lights + k - num_disks) as u32
                    } else {
                        u32::MAX
                    },
                    flags: if q.two_sided_emission { TRIANGLE_TWO_SIDED } else { 0 },
                }
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_match_wgsl() {
        assert_eq!(std::mem::size_of::<GpuSphere>(), 32);
        assert_eq!(std::mem::size_of::<GpuPlane>(), 32);
        assert_eq!(std::mem::size_of::<GpuQuadric>(), 128);
        assert_eq!(std::mem::size_of::<GpuMaterial>(), 112);
        assert_eq!(std::mem::size_of::<GpuTriangle>(), 48);
        assert_eq!(std::mem::size_of::<GpuTriangleNormals>(), 48);
        assert_eq!(std::mem::size_of::<GpuTriangleUvs>(), 24);
        assert_eq!(std::mem::size_of::<GpuSphereAxes>(), 48);
        assert_eq!(std::mem::size_of::<GpuLight>(), 16);
    }

    #[test]
    fn capacities_fit_default_uniform_bindings() {
        let limit = wgpu::Limits::default().max_uniform_buffer_binding_size as usize;
        assert!(MAX_SPHERES * std::mem::size_of::<GpuSphere>() <= limit);
        assert!(MAX_PLANES * std::mem::size_of::<GpuPlane>() + MAX_QUADRICS * std::mem::size_of::<GpuQuadric>() <= limit);
    }

    /// The most materials a scene may have fill less than one row of their texel table.
    #[test]
    fn the_material_limit_fits_one_texel_row() {
        assert!(crate::scene::MAX_MATERIALS * bindings::MATERIAL_TEXELS as usize <= bindings::TEXEL_TABLE_WIDTH as usize);
    }

    /// The refusal bound holds every table of the largest scene it admits: the normals in one
    /// storage binding, triangles (3 texels) and BVH node records (4 texels, fewer than 2 per
    /// triangle) in textures of at most the adapter's rows.
    #[test]
    fn the_triangle_limit_fits_the_binding_and_the_texel_tables() {
        let width = crate::shaders::bindings::TEXEL_TABLE_WIDTH as u64;
        for (binding, rows) in [(128u64 << 20, 16384u64), (4u64 << 30, 8192), (1 << 20, 8192)] {
            let n = max_triangles(binding, rows);
            assert!(n * std::mem::size_of::<GpuTriangleNormals>() as u64 <= binding);
            assert!((3 * n).div_ceil(width) <= rows, "triangles of {n}");
            assert!((4 * (2 * n - 1)).div_ceil(width) <= rows, "nodes of {n}");
        }
        // lavapipe's 128 MiB binding, not its textures, bounds it there.
        assert_eq!(max_triangles(128 << 20, 16384), (128 << 20) / 48);
    }
}
