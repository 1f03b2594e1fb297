// techniques/none_triangle_light.wgsl — stands in for the triangle functions of a `light`
// technique where none is loaded or the loaded one does not sample triangle lights
// (LIGHT_TECHNIQUE_TRIANGLES is then false, and these are never called).

fn sample_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, u: vec2f) -> vec3f {
    return light.p0;
}

fn pdf_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, p: vec3f) -> f32 {
    return 0.0;
}
