// quadrics/quadric.wgsl — what the quadrics share (src/scene/quadrics/mod.rs; one file per kind
// beside this one): their record, and affine maps. They read no scene (the kernel's
// `quadrics` binding is scene.wgsl's), so the sampling tests run them alone.

// A disk or cylinder: the unit shape of its object space (src/scene/quadrics/) placed by an
// affine map (its layout mirrors GpuQuadric, src/gpu/scene_buffers.rs; checked by
// tests/shader_layouts.rs). Each map is three rows r: a point p maps to dot(r.xyz, p) + r.w, a vector v to
// dot(r.xyz, v).
struct Quadric {
    // World to object, rows x, y, z.
    object_x: vec4f,
    object_y: vec4f,
    object_z: vec4f,
    // Object to world, rows x, y, z.
    world_x: vec4f,
    world_y: vec4f,
    world_z: vec4f,
    // A disk's unit normal in world space, flip_normals applied; an SDF grid's record start in
    // bsdf_data (the bits of x) and 1 for smooth normals (y) (quadrics/sdf_grid.wgsl).
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

// A world point and a world vector in q's object space, and an object point in the world.
// (Rows as fields, not an array: lavapipe's compiler (Mesa 22.3) crashed, at random, on
// kernels passing array<vec4f, 3> to functions.)
fn quadric_point_to_object(q: Quadric, p: vec3f) -> vec3f {
    return vec3f(dot(q.object_x.xyz, p) + q.object_x.w, dot(q.object_y.xyz, p) + q.object_y.w, dot(q.object_z.xyz, p) + q.object_z.w);
}

fn quadric_vector_to_object(q: Quadric, v: vec3f) -> vec3f {
    return vec3f(dot(q.object_x.xyz, v), dot(q.object_y.xyz, v), dot(q.object_z.xyz, v));
}

fn quadric_point_to_world(q: Quadric, p: vec3f) -> vec3f {
    return vec3f(dot(q.world_x.xyz, p) + q.world_x.w, dot(q.world_y.xyz, p) + q.world_y.w, dot(q.world_z.xyz, p) + q.world_z.w);
}

fn quadric_vector_to_world(q: Quadric, v: vec3f) -> vec3f {
    return vec3f(dot(q.world_x.xyz, v), dot(q.world_y.xyz, v), dot(q.world_z.xyz, v));
}

// Whether the ray o + t d, t in [0, t_max], meets the box [lo - pad, hi + pad]: the slabs'
// intervals intersected. A direction's zero components are made tiny, so that the slabs stay
// finite.
fn ray_meets_box(lo: vec3f, hi: vec3f, pad: f32, o: vec3f, d: vec3f, t_max: f32) -> bool {
    let inv = 1.0 / select(d, vec3f(1e-30), d == vec3f(0.0));
    let t0 = (lo - vec3f(pad) - o) * inv;
    let t1 = (hi + vec3f(pad) - o) * inv;
    let near = max(max3(min(t0, t1)), 0.0);
    let far = min(min3(max(t0, t1)), t_max);
    return near <= far;
}
