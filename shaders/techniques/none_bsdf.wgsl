// techniques/none_bsdf.wgsl — stands in for the Phong functions of a `bsdf` technique where
// none is loaded or the loaded one samples microfacet normals only (BSDF_TECHNIQUE_PHONG is then
// false, and these are never called).

fn sample_bsdf_technique(wo: vec3f, m: PhongMaterial, u: vec2f, u_lobe: f32) -> vec3f {
    return vec3f(0.0, 0.0, 1.0);
}

fn pdf_bsdf_technique(wo: vec3f, m: PhongMaterial, wi: vec3f) -> f32 {
    return 0.0;
}
