//! The bind groups of the kernels, defined once: each binding's number, its WGSL name and its
//! kind. The numbers are generated into the assembled WGSL (`@binding(BINDING_FRAME)`), the
//! pipelines' layouts are built from the same tables, and the host binds buffers by these
//! constants.

/// What a binding holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Uniform,
    /// A storage buffer, read-only or read-write.
    Storage { read_only: bool },
    /// A read-only table of 16-byte records: an `rgba32uint` storage texture of
    /// `TEXEL_TABLE_WIDTH` texels per row, record j at (j mod width, j / width) (see
    /// `texel_table_bytes`). For records the kernel reads at a per-lane index in its inner
    /// loops: lavapipe reads a texel as one branch-free 16-byte load per lane, where a storage
    /// buffer read is a loop over the lanes with two branches per lane and component.
    TexelTable,
}

/// Texels per row of a texel table (a power of two, far below every adapter's 2D texture
/// limit: WebGPU's default is 8192).
pub const TEXEL_TABLE_WIDTH: u32 = 4096;
// A BVH node record's texels lie in one row (bvh.wgsl's `bvh_record`).
const _: () = assert!(TEXEL_TABLE_WIDTH % crate::accel::bvh::RECORD_TEXELS == 0);

/// Texels of one material in the materials' texel table (`MATERIALS`): `gpu::GpuMaterial`'s
/// 112 bytes, which it asserts.
pub const MATERIAL_TEXELS: u32 = 7;

/// A table's bytes (a multiple of 16) padded with zeros to whole rows, and its number of rows
/// (at least one: a binding cannot be empty).
pub fn texel_table_bytes(bytes: &[u8]) -> (Vec<u8>, u32) {
    assert!(bytes.len() % 16 == 0, "texel table records are 16 bytes");
    let row = TEXEL_TABLE_WIDTH as usize * 16;
    let rows = bytes.len().div_ceil(row).max(1);
    let mut padded = bytes.to_vec();
    padded.resize(rows * row, 0);
    (padded, rows as u32)
}

/// One binding of group 0: number, the WGSL constant's suffix (`BINDING_<NAME>`), kind.
#[derive(Debug, Clone, Copy)]
pub struct Binding {
    pub number: u32,
    pub name: &'static str,
    pub kind: Kind,
}

/// Per-dispatch uniform: camera, sample range, tile (`FrameParams`, scene.wgsl).
pub const FRAME: Binding = Binding { number: 0, name: "FRAME", kind: Kind::Uniform };
/// The scene's spheres, its planes and quadrics (disks and cylinders), and its materials
/// (scene.wgsl): planes and quadrics in one buffer (`Surfaces`), as lavapipe crashed on kernels
/// that read eight uniform buffers.
pub const SPHERES: Binding = Binding { number: 1, name: "SPHERES", kind: Kind::Uniform };
pub const SURFACES: Binding = Binding { number: 2, name: "SURFACES", kind: Kind::Uniform };
/// The materials (`GpuMaterial`, seven texels each) are a texel table: every hit reads its own.
pub const MATERIALS: Binding = Binding { number: 3, name: "MATERIALS", kind: Kind::TexelTable };
/// One band's accumulator (accumulate.wgsl).
pub const ACCUM: Binding = Binding { number: 5, name: "ACCUM", kind: Kind::Storage { read_only: false } };
/// The Halton bases, `primes(HALTON_DIMENSIONS)` (sampler.wgsl).
pub const HALTON_PRIMES: Binding = Binding { number: 6, name: "HALTON_PRIMES", kind: Kind::Uniform };

/// The triangles in BVH leaf order (`Triangle`, bvh.wgsl: three texels each), their vertex
/// normals, the BVH nodes' records (`BvhRecord`: four texels each).
pub const TRIANGLES: Binding = Binding { number: 7, name: "TRIANGLES", kind: Kind::TexelTable };
pub const TRIANGLE_NORMALS: Binding = Binding { number: 8, name: "TRIANGLE_NORMALS", kind: Kind::Storage { read_only: true } };
pub const BVH_NODES: Binding = Binding { number: 9, name: "BVH_NODES", kind: Kind::TexelTable };
/// The BVH nodes' parents, one per pair of children, four per texel (`Bvh::pair_parents`): the
/// stackless traversal climbs them.
pub const BVH_PARENTS: Binding = Binding { number: 17, name: "BVH_PARENTS", kind: Kind::TexelTable };
/// The light table: objects and the power alias table (`LightEntry`, light_table.wgsl), one texel
/// per light.
pub const LIGHTS: Binding = Binding { number: 10, name: "LIGHTS", kind: Kind::TexelTable };

/// Their distinct vertex positions (`accel::SharedVertices`), in a uniform buffer
/// (`small_vertices`, bvh.wgsl): the unrolled tests shear each once per ray.
pub const SMALL_VERTICES: Binding = Binding { number: 18, name: "SMALL_VERTICES", kind: Kind::Uniform };

/// The triangles' texture coordinates (`TriangleUvs`, bvh.wgsl) and the spheres' object axes
/// (`SphereAxes`, intersect.wgsl): the uv parametrisation, read only where a material does.
pub const TRIANGLE_UVS: Binding = Binding { number: 12, name: "TRIANGLE_UVS", kind: Kind::Storage { read_only: true } };
/// The values of the mesh attributes that `mesh_attribute` textures read, at each triangle's
/// corners (`PackedTriangles::attributes`).
pub const MESH_ATTRIBUTES: Binding = Binding { number: 19, name: "MESH_ATTRIBUTES", kind: Kind::Storage { read_only: true } };
pub const SPHERE_AXES: Binding = Binding { number: 13, name: "SPHERE_AXES", kind: Kind::Storage { read_only: true } };

/// The numbers BSDFs read beyond their parameter blocks (`BsdfData`, bsdf.wgsl): roughplastic's
/// transmittance tables.
pub const BSDF_DATA: Binding = Binding { number: 14, name: "BSDF_DATA", kind: Kind::Storage { read_only: true } };

/// The environment map (`EnvironmentMap::pack`, emitters/environment.wgsl): its size, scale,
/// rotation and texels.
pub const ENVIRONMENT_MAP: Binding = Binding { number: 15, name: "ENVIRONMENT_MAP", kind: Kind::Storage { read_only: true } };

/// The point, spot and directional lights (`DeltaLight`, emitter.wgsl).
pub const DELTA_LIGHTS: Binding = Binding { number: 16, name: "DELTA_LIGHTS", kind: Kind::Uniform };

/// The path tracer's bind group.
pub const PATH_TRACER: [Binding; 18] = [
    FRAME,
    SPHERES,
    SURFACES,
    MATERIALS,
    ACCUM,
    HALTON_PRIMES,
    TRIANGLES,
    TRIANGLE_NORMALS,
    BVH_NODES,
    BVH_PARENTS,
    LIGHTS,
    SMALL_VERTICES,
    TRIANGLE_UVS,
    MESH_ATTRIBUTES,
    SPHERE_AXES,
    BSDF_DATA,
    ENVIRONMENT_MAP,
    DELTA_LIGHTS,
];

/// The display pass's parameters (`DisplayParams`, display.wgsl).
pub const DISPLAY_PARAMS: Binding = Binding { number: 0, name: "DISPLAY_PARAMS", kind: Kind::Uniform };
/// One band's accumulator, read.
pub const DISPLAY_BAND: Binding = Binding { number: 1, name: "DISPLAY_BAND", kind: Kind::Storage { read_only: true } };
/// The reference image (rgb + pad per pixel).
pub const DISPLAY_REFERENCE: Binding = Binding { number: 2, name: "DISPLAY_REFERENCE", kind: Kind::Storage { read_only: true } };
/// The magma table of the false-colour views.
pub const DISPLAY_COLOUR_MAP: Binding = Binding { number: 3, name: "DISPLAY_COLOUR_MAP", kind: Kind::Uniform };
/// The shown image, packed RGBA8.
pub const DISPLAY_SHOWN: Binding = Binding { number: 4, name: "DISPLAY_SHOWN", kind: Kind::Storage { read_only: false } };

/// The display pass's bind group.
pub const DISPLAY: [Binding; 5] = [DISPLAY_PARAMS, DISPLAY_BAND, DISPLAY_REFERENCE, DISPLAY_COLOUR_MAP, DISPLAY_SHOWN];

/// `const BINDING_<NAME>: u32 = N;` for every binding of `group`.
pub fn wgsl(group: &[Binding]) -> String {
    group.iter().map(|b| format!("const BINDING_{}: u32 = {}u;\n", b.name, b.number)).collect()
}

/// A bind group layout entry of the compute stage: a resource of `kind` at `number`.
pub fn layout_entry(number: u32, kind: Kind) -> wgpu::BindGroupLayoutEntry {
    let buffer = |ty| wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None };
    let ty = match kind {
        Kind::Uniform => buffer(wgpu::BufferBindingType::Uniform),
        Kind::Storage { read_only } => buffer(wgpu::BufferBindingType::Storage { read_only }),
        Kind::TexelTable => wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::ReadOnly,
            format: wgpu::TextureFormat::Rgba32Uint,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
    };
    wgpu::BindGroupLayoutEntry { binding: number, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None }
}

/// A texel table holding `bytes` (a multiple of 16), uploaded: the texture and its view.
pub fn texel_table(device: &wgpu::Device, queue: &wgpu::Queue, label: &str, bytes: &[u8]) -> (wgpu::Texture, wgpu::TextureView) {
    let (padded, rows) = texel_table_bytes(bytes);
    let size = wgpu::Extent3d { width: TEXEL_TABLE_WIDTH, height: rows, depth_or_array_layers: 1 };
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size,
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba32Uint,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    queue.write_texture(
        texture.as_image_copy(),
        &padded,
        wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(TEXEL_TABLE_WIDTH * 16), rows_per_image: Some(rows) },
        size,
    );
    let view = texture.create_view(&wgpu::TextureViewDescriptor::default());
    (texture, view)
}

/// The layout entries of a whole group.
pub fn layout_entries(group: &[Binding]) -> Vec<wgpu::BindGroupLayoutEntry> {
    group.iter().map(|b| layout_entry(b.number, b.kind)).collect()
}

/// `buffer` bound at `b`.
pub fn entry(b: Binding, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding: b.number, resource: buffer.as_entire_binding() }
}

/// A texel table's `view` bound at `number`.
pub fn texel_table_entry(number: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding: number, resource: wgpu::BindingResource::TextureView(view) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texel_tables_pad_to_whole_rows_and_are_never_empty() {
        let (bytes, rows) = texel_table_bytes(&[]);
        assert_eq!((bytes.len(), rows), (TEXEL_TABLE_WIDTH as usize * 16, 1));
        let record: Vec<u8> = (0..48u8).collect();
        let (bytes, rows) = texel_table_bytes(&record);
        assert_eq!(rows, 1);
        assert_eq!(&bytes[..48], &record[..]);
        assert!(bytes[48..].iter().all(|&b| b == 0));
        let (_, rows) = texel_table_bytes(&vec![0; TEXEL_TABLE_WIDTH as usize * 16 + 16]);
        assert_eq!(rows, 2);
    }

    #[test]
    fn numbers_are_unique_within_a_group() {
        for group in [&PATH_TRACER[..], &DISPLAY[..]] {
            let mut numbers: Vec<u32> = group.iter().map(|b| b.number).collect();
            numbers.sort_unstable();
            numbers.dedup();
            assert_eq!(numbers.len(), group.len());
        }
    }
}
