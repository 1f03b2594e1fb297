// emitter.wgsl — what every emitter shares: the point lights are sampled from and the record
// a light sample gives. Each kind of emitter is one file of shaders/emitters/ (sphere.wgsl,
// triangle.wgsl, environment.wgsl) with
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
// it carries towards x, and the sphere the shadow ray must not count as a blocker (INVALID for
// others).
struct EmitterSample {
    wi: vec3f,
    dist: f32,
    pdf: f32,
    emission: vec3f,
    skip: u32,
}
