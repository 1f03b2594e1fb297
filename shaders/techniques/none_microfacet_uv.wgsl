// techniques/none_microfacet_uv.wgsl — stands in for the two-alpha microfacet functions of a
// `bsdf` technique where none is loaded or the loaded one does not define them
// (BSDF_TECHNIQUE_MICROFACET_UV is then false, and these are never called).

fn sample_microfacet_uv_technique(wo: vec3f, alpha_uv: vec2f, distribution: u32, u: vec2f) -> vec3f {
    return vec3f(0.0, 0.0, 1.0);
}

fn pdf_microfacet_uv_technique(wo: vec3f, m: vec3f, alpha_uv: vec2f, distribution: u32) -> f32 {
    return 0.0;
}
