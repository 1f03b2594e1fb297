// techniques/none_cylinder_light.wgsl — stands in for the cylinder functions of a `light`
// technique where none is loaded or the loaded one does not sample cylinder lights
// (LIGHT_TECHNIQUE_CYLINDERS is then false, and these are never called).

fn sample_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, u: vec2f) -> vec3f {
    return light.base;
}

fn pdf_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, p: vec3f) -> f32 {
    return 0.0;
}
