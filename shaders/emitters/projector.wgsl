// emitters/projector.wgsl — a projector (Mitsuba's `projector`, src/scene/emitters/projector.rs):
// a pinhole projecting an irradiance image, the perspective camera run backwards. A delta light:
// next event estimation samples it with density 1; no ray can hit it.

// The direction from ctx towards projector l and the radiance it sends there: I / d^2 with
// intensity I = pi scale E(uv) / cos^3(theta) (light.intensity holds pi scale), uv the image
// point of the direction from the light to x, theta its angle from the axis; 0 outside the
// image's frustum (uv outside [0, 1]^2, or behind the projector), as Mitsuba's
// sample_direction.
fn sample_projector_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let light = delta_lights[light_entry(l).object];
    var es = sample_point_source(light.position, light.intensity, ctx.x);
    let d = -es.wi;
    let cos_theta = dot(light.direction, d);
    let uv = projected_uv(light, d);
    let inside = cos_theta > 0.0 && all(uv >= vec2f(0.0)) && all(uv <= vec2f(1.0));
    es.emission = select(vec3f(0.0), es.emission * projected_texture(light, clamp(uv, vec2f(0.0), vec2f(1.0))) / (cos_theta * cos_theta * cos_theta), inside);
    return es;
}

// A delta light gives no direction a density: 0 (never asked, as no ray finds it).
fn pdf_projector_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    return 0.0;
}

// No ray finds a pinhole: no radiance.
fn eval_projector_emitter() -> vec3f {
    return vec3f(0.0);
}
