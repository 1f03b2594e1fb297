// techniques/none_env.wgsl — stands in for an `env` technique where none is loaded
// (ENV_TECHNIQUE is then false, and these are never called).

fn sample_env_technique(n: vec3f, u: vec2f) -> vec3f {
    return n;
}

fn pdf_env_technique(n: vec3f, wi: vec3f) -> f32 {
    return 0.0;
}
