// techniques/none_microfacet.wgsl — stands in for the microfacet functions of a `bsdf`
// technique where none is loaded or the loaded one does not define them
// (BSDF_TECHNIQUE_MICROFACET is then false, and these are never called; with a two-alpha
// technique it is true, and BSDF_TECHNIQUE_MICROFACET_UV routes every call to that one).

fn sample_microfacet_technique(wo: vec3f, alpha: f32, distribution: u32, u: vec2f) -> vec3f {
    return vec3f(0.0, 0.0, 1.0);
}

fn pdf_microfacet_technique(wo: vec3f, m: vec3f, alpha: f32, distribution: u32) -> f32 {
    return 0.0;
}
