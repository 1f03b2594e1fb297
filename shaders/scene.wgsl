// scene.wgsl — the scene as the path-tracing kernel sees it: layouts mirror src/gpu/scene_buffers.rs and
// src/gpu/frame_params.rs (checked by tests/shader_layouts.rs); binding numbers are generated.

// Scene features, fixed per pipeline (set through pipeline constants).
override NUM_SPHERES: u32 = 0u;
override NUM_PLANES: u32 = 0u;
// Mitsuba's analytic disks and cylinders (quadrics/): surfaces.quadrics[0 .. NUM_DISKS) are disks, the
// light disks first (disk light l is quadric l), then NUM_CYLINDERS cylinders.
override NUM_DISKS: u32 = 0u;
override NUM_CYLINDERS: u32 = 0u;
// Then NUM_CURVE_SEGMENTS segments of Mitsuba's linearcurves (quadrics/linear_curve.wgsl),
// never lights.
override NUM_CURVE_SEGMENTS: u32 = 0u;
// Then NUM_BSPLINE_SEGMENTS segments of Mitsuba's bsplinecurves (quadrics/bspline_curve.wgsl),
// never lights.
override NUM_BSPLINE_SEGMENTS: u32 = 0u;
// Then NUM_SDF_GRIDS of Mitsuba's sdfgrids (quadrics/sdf_grid.wgsl), never lights.
override NUM_SDF_GRIDS: u32 = 0u;
// The lights' counts (NUM_LIGHTS, NUM_<KIND>_LIGHTS) are generated after light_table.wgsl:
// the emissive spheres are the first NUM_SPHERE_LIGHTS spheres (the host orders them so), and
// sphere light l is sphere l.
// Planes that can lie between a path vertex and a light come first; the others (every light
// and the camera strictly on the same side) are skipped by shadow rays.
override NUM_OCCLUDING_PLANES: u32 = 0u;
// False when the environment is black: escaped rays are not looked up.
override HAS_ENVIRONMENT: bool = true;
// The environment is an image (emitters/environment.wgsl): escaped rays look it up.
override HAS_ENVIRONMENT_MAP: bool = false;
// False when no path vertex can be inside a light sphere (the camera is outside every light and
// no other object reaches into one): sampling lights from inside compiles out.
override LIGHT_INTERIORS_REACHABLE: bool = true;
// True when some material reads the hit's uv parametrisation (a texture): only then is it
// computed (Hit.uv is 0 otherwise).
override HAS_UVS: bool = false;
// True when the camera has a thin lens (an aperture radius > 0): camera rays leave from a point
// of the lens, which takes sample dimensions 2 and 3 (integrator.wgsl).
override THIN_LENS: bool = false;
// True when the camera is orthographic (Camera::projection): camera rays are parallel, along
// camera_forward, from the rectangle camera_right x camera_up about camera_origin.
override ORTHOGRAPHIC: bool = false;
// True when some delta light projects a texture (a spot's `texture`): only then is it looked up
// (emitter.wgsl's projected_texture).
override HAS_LIGHT_TEXTURES: bool = false;

struct Sphere {
    center: vec3f,
    radius: f32,
    material: u32,
    _pad0: u32,
    _pad1: u32,
    _pad2: u32,
}

// A sphere's object axes in world space: they place its uv parametrisation (sphere_uv).
struct SphereAxes {
    x: vec3f,
    y: vec3f,
    z: vec3f,
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
    emission: vec3f,
    flags: u32,
    // The BSDF's parameter block: what each slot holds is its kind's (`<stem>_of` in
    // shaders/bsdfs/<stem>.wgsl, packed by src/scene/bsdfs/<stem>.rs).
    p0: vec4f,
    p1: vec4f,
    p2: vec4f,
    p3: vec4f,
    // A BSDF_KIND_*.
    kind: u32,
    // Mitsuba's mask (shaders/bsdfs/mask.wgsl): the opacity, or, where negative, the reference
    // -(start + 1) of its texture's record in bsdf_data; 1 where opaque.
    opacity: f32,
    // Mitsuba's twosided with two BSDFs: the material whose BSDF scatters on the back, NO_BACK
    // where none.
    back: u32,
    // Mitsuba's normalmap (shaders/bsdfs/normal_map.wgsl): the start of its texture's record in
    // bsdf_data, NO_NORMAL_MAP where none.
    normal_map: u32,
    // Mitsuba's bumpmap (shaders/bsdfs/bump_map.wgsl): the start of its record in bsdf_data (the
    // scale, then its texture's record), NO_BUMP_MAP where none.
    bump_map: u32,
    // Mitsuba's blendbsdf (src/scene/bsdfs/blend.rs, `blend_pick`): the material whose BSDF is
    // blended with this one's, NO_BLEND where none, and its weight (or, where negative, the
    // reference -(start + 1) of its texture's record in bsdf_data).
    blend: u32,
    blend_weight: f32,
    // Mitsuba's area emitter with a textured radiance (src/scene/mod.rs, Material::
    // emission_texture): the start of its texture's record in bsdf_data, NO_EMISSION_TEXTURE
    // where the emission is one colour.
    emission_texture: u32,
}

// Flags of a material: MATERIAL_EMISSIVE and MATERIAL_ONE_SIDED, generated from
// src/shaders/flags.rs.

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
    // Row of the bound accumulator that the tile's first row goes to (0 unless the dispatch
    // covers only part of the accumulator's rows: the viewer's partial passes).
    accum_row: u32,
    // The thin lens (THIN_LENS): the aperture's radius and the distance of the plane in focus.
    aperture_radius: f32,
    focus_distance: f32,
}

// The scene lives in uniform buffers of fixed capacity (MAX_* are generated by the host, which
// refuses larger scenes). Uniform, not storage: the loops over spheres and planes read them at
// an index that is the same in every lane, which uniform buffers serve as one broadcast load
// (GPUs: the constant cache; lavapipe: a scalar load, where a storage read is a per-lane loop).
@group(0) @binding(BINDING_FRAME) var<uniform> frame: FrameParams;
@group(0) @binding(BINDING_SPHERES) var<uniform> spheres: array<Sphere, MAX_SPHERES>;
// The planes and the quadrics share one uniform buffer: with a ninth buffer of their own,
// lavapipe (Mesa 22.3) overflowed a table of its compiler and crashed at random
// (tests/lavapipe_inline_uniforms.rs tells which buffers it may record).
struct Surfaces {
    planes: array<Plane, MAX_PLANES>,
    quadrics: array<Quadric, MAX_QUADRICS>,
}
@group(0) @binding(BINDING_SURFACES) var<uniform> surfaces: Surfaces;
// The materials in scene order, MATERIAL_TEXELS texels each (`GpuMaterial`'s bytes): a texel
// table, as every hit reads its material at a per-lane index (lavapipe reads a texel as one
// 16-byte load per lane, a uniform array element as one load per lane and component).
@group(0) @binding(BINDING_MATERIALS) var material_texels: texture_storage_2d<rgba32uint, read>;

// Material i, its bits as the host wrote them (texels MATERIAL_TEXELS i to MATERIAL_TEXELS i + 6;
// the driver drops the loads of fields a caller does not read).
fn material_record(i: u32) -> Material {
    let j = MATERIAL_TEXELS * i;
    let a = textureLoad(material_texels, texel_coords(j));
    let p0 = textureLoad(material_texels, texel_coords(j + 1u));
    let p1 = textureLoad(material_texels, texel_coords(j + 2u));
    let p2 = textureLoad(material_texels, texel_coords(j + 3u));
    let p3 = textureLoad(material_texels, texel_coords(j + 4u));
    let b = textureLoad(material_texels, texel_coords(j + 5u));
    let c = textureLoad(material_texels, texel_coords(j + 6u));
    return Material(bitcast<vec3f>(a.xyz), a.w, bitcast<vec4f>(p0), bitcast<vec4f>(p1), bitcast<vec4f>(p2), bitcast<vec4f>(p3),
        b.x, bitcast<f32>(b.y), b.z, b.w, c.x, c.y, bitcast<f32>(c.z), c.w);
}
// Read only for uvs, at the hit sphere: a storage buffer.
@group(0) @binding(BINDING_SPHERE_AXES) var<storage, read> sphere_axes: array<SphereAxes>;

// The BSDF of material i met from the side given (`from_inside`: its back) at a point of uv
// parametrisation `uv`: that of `bsdf_material` (i itself, or the material a blend picked,
// `blend_pick`), or on its back its back material's where it has one (`material_on_side`), the
// opacity of i's mask always (a mask wraps both sides and a blend).
// Where a parameter slot holds a texture, it is looked up there (texture.wgsl, where some
// material reads uvs). Its kind and last two slots are read only where the pipeline has other
// kinds than Phong (whose two slots are the rest): a read at a per-lane index costs per texel
// on SIMD CPU drivers (when materials were a uniform array, reading the whole Material cost the
// study scene a quarter of its speed).
fn material_bsdf(material: u32, bsdf_material: u32, from_inside: bool, ctx: TextureEvalContext) -> Bsdf {
    let i = material_on_side(bsdf_material, from_inside);
    let m = material_record(i);
    var b = Bsdf(BSDF_KIND_PHONG, m.p0, m.p1, vec4f(0.0), vec4f(0.0), false, 1.0, vec3f(0.0), vec3f(0.0));
    if (bsdf_kinds_vary()) {
        b.kind = m.kind;
        b.p2 = m.p2;
        b.p3 = m.p3;
    }
    if (HAS_UVS) {
        b = bsdf_apply_textures(b, ctx);
    }
    if (HAS_MASKS) {
        b.opacity = material_opacity(material, ctx);
    }
    return b;
}

// Some material blends another material's BSDF (SceneFeatures::has_blends).
override HAS_BLENDS: bool = false;

// Which BSDF scatters at a vertex on material i, given the vertex's lobe sample u: Mitsuba's
// blendbsdf, f = (1 - w) f_0 + w f_1, by a pick (src/scene/bsdfs/blend.rs). f_1, the blended
// material's, when u < w, and u rescaled to u / w; else f_0, material i's own, and u rescaled to
// (u - w) / (1 - w): the picked BSDF's lobe choice then sees a uniform number, independent of
// the pick. w is the material's weight, or its texture's value at uv (Mitsuba's eval_1, clipped
// to [0, 1]).
struct BlendPick {
    material: u32,
    u: f32,
}

fn blend_pick(i: u32, ctx: TextureEvalContext, u: f32) -> BlendPick {
    let other = material_record(i).blend;
    if (!HAS_BLENDS || other == NO_BLEND) {
        return BlendPick(i, u);
    }
    var w = material_record(i).blend_weight;
    if (HAS_UVS && w < 0.0) {
        w = mask_opacity_of_texel(eval_texture(u32(-w - 1.0), ctx));
    }
    if (u < w) {
        return BlendPick(other, u / w);
    }
    return BlendPick(i, (u - w) / (1.0 - w));
}

// Some material has another BSDF on its back (SceneFeatures::has_back_bsdfs).
override HAS_BACK_BSDFS: bool = false;

// The material whose BSDF scatters where a ray meets material i from the side given: its own,
// or on the back, where it has one, its back's (Mitsuba's twosided with two BSDFs: the back's
// BSDF in the frame turned to the back, as the integrator turns n_s towards the viewer).
fn material_on_side(i: u32, from_inside: bool) -> u32 {
    if (HAS_BACK_BSDFS && from_inside && material_record(i).back != NO_BACK) {
        return material_record(i).back;
    }
    return i;
}

// Some material's opacity is a texture (SceneFeatures::textured_opacity).
override TEXTURED_OPACITY: bool = true;

// The opacity of material i at uv and world position p (Mitsuba's mask): its constant, or its
// texture's value there.
fn material_opacity(i: u32, ctx: TextureEvalContext) -> f32 {
    let o = material_record(i).opacity;
    if (!HAS_UVS || !TEXTURED_OPACITY || o >= 0.0) {
        return o;
    }
    return mask_opacity_of_texel(eval_texture(u32(-o - 1.0), ctx));
}
