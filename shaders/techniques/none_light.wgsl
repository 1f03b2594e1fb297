// techniques/none_light.wgsl — stands in for the spherical-light functions of a `light`
// technique where none is loaded or the loaded one does not sample spherical lights
// (LIGHT_TECHNIQUE_SPHERES is then false, and these are never called).

fn sample_light_technique(x: vec3f, n: vec3f, light: SphereLight, u: vec2f) -> vec3f {
    return light.center;
}

fn pdf_light_technique(x: vec3f, n: vec3f, light: SphereLight, p: vec3f) -> f32 {
    return 0.0;
}
