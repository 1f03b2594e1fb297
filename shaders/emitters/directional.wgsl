// emitters/directional.wgsl — a directional light (Mitsuba's `directional`,
// src/scene/emitters/directional.rs): irradiance E arriving along one direction from infinity.
// A delta light: next event estimation samples it with density 1 and radiance E, its shadow ray
// running to infinity; no ray can hit it.

// The direction from ctx towards directional light l: against the way the light travels.
fn sample_directional_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let light = delta_lights[light_entry(l).object];
    return EmitterSample(-light.direction, INFINITY, 1.0, light.intensity, INVALID, true);
}

// A delta light gives no direction a density: 0 (never asked, as no ray finds it).
fn pdf_directional_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    return 0.0;
}

// No ray finds a direction: no radiance.
fn eval_directional_emitter() -> vec3f {
    return vec3f(0.0);
}
