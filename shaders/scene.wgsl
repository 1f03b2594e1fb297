// scene.wgsl — the scene as the path-tracing kernel sees it: layouts mirror src/gpu/scene_buffers.rs.

// Scene features, fixed per pipeline (set through pipeline constants).
override NUM_SPHERES: u32 = 0u;
override NUM_PLANES: u32 = 0u;
override NUM_LIGHTS: u32 = 0u;
// False when the environment is black: escaped rays are not looked up.
override HAS_ENVIRONMENT: bool = true;

struct Sphere {
    center: vec3f,
    radius: f32,
    material: u32,
    // Index into `lights`, or INVALID when the sphere does not emit.
    light: u32,
    _pad0: u32,
    _pad1: u32,
}

// Points x with dot(normal, x) = offset.
struct Plane {
    normal: vec3f,
    offset: f32,
    material: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

struct Material {
    diffuse: vec3f,
    glossiness: f32,
    specular: vec3f,
    // Probability of sampling the Phong lobe (luminance ratio of ks to kd + ks).
    p_spec: f32,
    emission: vec3f,
    is_emissive: u32,
}

struct FrameParams {
    camera_origin: vec3f,
    width: u32,
    // Direction to the image centre, and half-extents of the image plane at distance 1.
    camera_forward: vec3f,
    height: u32,
    camera_right: vec3f,
    sample_start: u32,
    camera_up: vec3f,
    sample_count: u32,
    environment: vec3f,
    seed: u32,
    max_depth: u32,
    // Pixel rectangle covered by this dispatch (a tile of the image).
    tile_x: u32,
    tile_y: u32,
    tile_width: u32,
    tile_height: u32,
    // Always 0; see opaque() in accumulate.wgsl.
    opaque_zero: u32,
    _pad1: u32,
    _pad2: u32,
}

@group(0) @binding(0) var<uniform> frame: FrameParams;
@group(0) @binding(1) var<storage, read> spheres: array<Sphere>;
@group(0) @binding(2) var<storage, read> planes: array<Plane>;
@group(0) @binding(3) var<storage, read> materials: array<Material>;
// Sphere index of each light.
@group(0) @binding(4) var<storage, read> lights: array<u32>;

fn material_phong(m: Material) -> Phong {
    return Phong(m.diffuse, m.specular, m.glossiness, m.p_spec);
}
