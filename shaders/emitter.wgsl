// emitter.wgsl — what every emitter shares: the point lights are sampled from and the record
// a light sample gives, and the delta lights' records. Each kind of emitter is one file of
// shaders/emitters/ (sphere.wgsl, triangle.wgsl, disk.wgsl, cylinder.wgsl, point.wgsl,
// spot.wgsl, directional.wgsl, environment.wgsl) with
//   sample_<kind>_emitter(l, ctx, u)  a direction from ctx towards light l, with its density;
//   pdf_<kind>_emitter(l, ctx, wi)    the density sample_ gives wi (for a wi that meets it);
//   eval_<kind>_emitter(...)          the radiance a ray that found it receives.
// The dispatcher on a light's kind (sample_emitter, pdf_emitter), the kinds' numbers
// EMITTER_KIND_*, and (after light_table.wgsl) one NUM_<KIND>_LIGHTS override per kind and
// NUM_LIGHTS, their sum, are generated from the registry (src/scene/emitters/mod.rs). Each kind's lights are one range of
// the light table (light_table.wgsl), the kinds in the registry's order.

// The point next event estimation samples from (pbrt-v4's LightSampleContext, Mitsuba's
// reference interaction): the shading point x, the object it lies on (INVALID for none),
// whether it was reached from that object's inner side, and the shading normal on the viewer's
// side (only a researcher's light technique reads it).
struct LightSampleContext {
    x: vec3f,
    object: u32,
    from_inside: bool,
    n: vec3f,
}

// A light sample seen from a shading point: direction, distance (INFINITY for a light at
// infinity), solid-angle density of the light's strategy (selection not included), the radiance
// it carries towards x, the sphere the shadow ray must not count as a blocker (INVALID for
// others), and whether the light is a delta (a point or a direction: `pdf` is then 1 and
// `emission` the radiance already integrated over the delta, I / d^2 or E; no BSDF-sampled
// ray can find it, so its MIS weight is 1).
struct EmitterSample {
    wi: vec3f,
    dist: f32,
    pdf: f32,
    emission: vec3f,
    skip: u32,
    delta: bool,
}

// A point, spot, directional or projector light (src/gpu/scene_buffers.rs GpuDeltaLight): the
// point lights, the spot lights, the directional lights, then the projectors;
// light_entry(l).object names one.
struct DeltaLight {
    // Point and spot: the position.
    position: vec3f,
    // Spot: cos of the cutoff angle.
    cos_cutoff: f32,
    // Spot: the axis it shines along; directional: the direction the light travels.
    direction: vec3f,
    // Spot: cos of the beam width.
    cos_beam: f32,
    // Point and spot: the intensity (W/sr); directional: the irradiance.
    intensity: vec3f,
    // Spot: the cutoff angle (radians).
    cutoff: f32,
    // The light's frame x axis (a projected texture's u direction).
    x_axis: vec3f,
    // Spot: 1 / (cutoff - beam width).
    inv_transition: f32,
    // The light's frame y axis (a projected texture's v direction).
    y_axis: vec3f,
    // The projected texture's record in bsdf_data (NO_LIGHT_TEXTURE: none).
    texture: u32,
    // uv of direction d in the light's frame: 1/2 + uv_scale (d_x, d_y) / d_z.
    uv_scale: vec2f,
}

// The image point of direction d from a light that projects a texture: d in the light's frame
// (x_axis, y_axis, direction), 1/2 + uv_scale (d_x, d_y) / d_z.
fn projected_uv(light: DeltaLight, d: vec3f) -> vec2f {
    let local = vec3f(dot(d, light.x_axis), dot(d, light.y_axis), dot(d, light.direction));
    return vec2f(0.5) + light.uv_scale * local.xy / local.z;
}

// The value of light's projected texture at image point uv, looked up as a surface texture
// (HAS_LIGHT_TEXTURES; 1 where it projects none).
fn projected_texture(light: DeltaLight, uv: vec2f) -> vec3f {
    if (!HAS_LIGHT_TEXTURES || light.texture == NO_LIGHT_TEXTURE) {
        return vec3f(1.0);
    }
    return eval_texture(light.texture, uv_context(uv));
}

@group(0) @binding(BINDING_DELTA_LIGHTS) var<uniform> delta_lights: array<DeltaLight, MAX_DELTA_LIGHTS>;

// The direction and distance from x to a light at point p, and the radiance I / d^2 of
// intensity I there (the inverse-square law of a point source; none where x is at p).
fn sample_point_source(p: vec3f, intensity: vec3f, x: vec3f) -> EmitterSample {
    let to_p = p - x;
    let dist = length(to_p);
    let ok = dist > 0.0;
    let wi = select(vec3f(0.0, 0.0, 1.0), to_p / dist, ok);
    let emission = select(vec3f(0.0), intensity / (dist * dist), ok);
    return EmitterSample(wi, dist, select(0.0, 1.0, ok), emission, INVALID, true);
}
