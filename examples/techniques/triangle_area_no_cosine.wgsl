// triangle_area_no_cosine.wgsl — a classic mistake, kept to show what pathlab does with it:
// points are drawn uniformly by area, as in triangle_area.wgsl, but the density is converted
// to solid angle with dist^2 / A alone, without the light's cosine. The pdf then disagrees
// with the sampler everywhere but head-on: it integrates to the mean of cos(theta_light) over
// the triangle's solid angle instead of 1, every sample's weight comes out too large by
// 1 / cos(theta_light), and a triangle seen at a slant renders too bright. pathlab's check
// refuses the technique before it renders:
//
//   pathlab check-technique light:examples/techniques/triangle_area_no_cosine.wgsl --scene assets/scenes/cornell_box.toml

fn sample_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, u: vec2f) -> vec3f {
    let s = sqrt(u.x);
    return (1.0 - s) * light.p0 + (s * (1.0 - u.y)) * light.p1 + (s * u.y) * light.p2;
}

fn pdf_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, p: vec3f) -> f32 {
    let area = 0.5 * length(cross(light.p1 - light.p0, light.p2 - light.p0));
    let to_x = x - p;
    return dot(to_x, to_x) / area;
}
