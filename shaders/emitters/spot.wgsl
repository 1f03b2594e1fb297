// emitters/spot.wgsl — a spot light (Mitsuba's `spot`, src/scene/emitters/spot.rs): a point
// light whose intensity falls off with the angle theta from its axis. A delta light, sampled as
// point.wgsl's.

// Mitsuba's falloff_curve at cos(theta): 1 within the beam width, the linear ramp in the angle
// (cutoff - theta) / (cutoff - beam width) towards the cutoff, 0 beyond it.
fn spot_falloff(light: DeltaLight, cos_theta: f32) -> f32 {
    let ramp = (light.cutoff - acos(clamp(cos_theta, -1.0, 1.0))) * light.inv_transition;
    let beam = select(ramp, 1.0, cos_theta >= light.cos_beam);
    return select(0.0, beam, cos_theta > light.cos_cutoff);
}

// The direction from ctx towards spot light l: I falloff(theta) / d^2, theta the angle between
// the light's axis and the direction from the light to x, times its projected texture in that
// direction (Mitsuba's spot `texture`, looked up only where the falloff is not 0).
fn sample_spot_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let light = delta_lights[light_entry(l).object];
    var es = sample_point_source(light.position, light.intensity, ctx.x);
    let falloff = spot_falloff(light, dot(light.direction, -es.wi));
    es.emission *= falloff;
    if (falloff > 0.0) {
        es.emission *= projected_texture(light, projected_uv(light, -es.wi));
    }
    return es;
}

// A delta light gives no direction a density: 0 (never asked, as no ray finds it).
fn pdf_spot_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    return 0.0;
}

// No ray finds a point: no radiance.
fn eval_spot_emitter() -> vec3f {
    return vec3f(0.0);
}
