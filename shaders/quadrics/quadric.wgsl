// quadrics/quadric.wgsl — what the quadrics share (src/scene/quadrics/mod.rs; one file per kind
// beside this one): their record, and affine maps. They read no scene (the kernel's
// `quadrics` binding is scene.wgsl's), so the sampling tests run them alone.

// A disk or cylinder: the unit shape of its object space (src/scene/quadrics/) placed by an
// affine map (its layout mirrors GpuQuadric, src/gpu/scene_buffers.rs; checked by
// tests/shader_layouts.rs). Each map is three rows r: a point p maps to dot(r.xyz, p) + r.w, a vector v to
// dot(r.xyz, v).
struct Quadric {
    to_object: array<vec4f, 3>,
    to_world: array<vec4f, 3>,
    // A disk's unit normal in world space, flip_normals applied.
    normal: vec3f,
    material: u32,
    // Surface area in world space.
    area: f32,
    // -1 where flip_normals, else 1.
    normal_sign: f32,
    // The light it is, INVALID for none.
    light: u32,
    // TRIANGLE_TWO_SIDED where it emits on both sides.
    flags: u32,
}

// An affine map's rows applied to a point and to a vector.
fn affine_point(m: array<vec4f, 3>, p: vec3f) -> vec3f {
    return vec3f(dot(m[0].xyz, p) + m[0].w, dot(m[1].xyz, p) + m[1].w, dot(m[2].xyz, p) + m[2].w);
}

fn affine_vector(m: array<vec4f, 3>, v: vec3f) -> vec3f {
    return vec3f(dot(m[0].xyz, v), dot(m[1].xyz, v), dot(m[2].xyz, v));
}
