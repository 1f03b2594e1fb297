// emitters/environment.wgsl — the constant environment (Mitsuba's `constant`), radiance
// frame.environment from every direction at infinity (src/scene/emitters/environment.rs).
// Escaped rays always find it; next event estimation samples it only where the method asks
// (NUM_ENVIRONMENT_LIGHTS = 1), drawing directions uniformly over the sphere as Mitsuba's
// ConstantBackgroundEmitter does: density 1 / (4 pi).

// A direction from ctx towards the environment: uniform on the sphere, at infinite distance.
fn sample_environment_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    let wi = square_to_uniform_sphere(u);
    return EmitterSample(wi, INFINITY, pdf_uniform_sphere(), frame.environment, INVALID);
}

// Solid-angle density with which sample_environment_emitter gives wi.
fn pdf_environment_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    return pdf_uniform_sphere();
}

// Radiance an escaped ray receives (none where the environment is black).
fn eval_environment_emitter(ray_d: vec3f) -> vec3f {
    return select(vec3f(0.0), frame.environment, HAS_ENVIRONMENT);
}
