// emitters/point.wgsl — a point light (Mitsuba's `point`, src/scene/emitters/point.rs):
// intensity I in every direction from one point. A delta light: next event estimation samples
// it with density 1 and radiance I / d^2 (the inverse-square law); no ray can hit it.

// The direction from ctx towards point light l.
fn sample_point_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let light = delta_lights[light_entry(l).object];
    return sample_point_source(light.position, light.intensity, ctx.x);
}

// A delta light gives no direction a density: 0 (never asked, as no ray finds it).
fn pdf_point_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    return 0.0;
}

// No ray finds a point: no radiance.
fn eval_point_emitter() -> vec3f {
    return vec3f(0.0);
}
