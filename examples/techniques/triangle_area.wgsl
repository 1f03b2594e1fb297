// triangle_area.wgsl — a triangle-light technique: points uniform by area on the triangle
// (barycentrics 1 - sqrt(u0), sqrt(u0) (1 - u1), sqrt(u0) u1), the strategy of Mitsuba's
// area emitters and pathlab's `--triangles area`, written as a researcher would write their
// own. Its density per unit solid angle at x is the area density 1 / A times
// dist^2 / |cos(theta_light)|, the Jacobian from area to solid angle; pdf_ is asked only about
// points of the triangle that x sees (pathlab never asks from the triangle's own plane).
//
//   pathlab check-technique light:examples/techniques/triangle_area.wgsl --scene assets/scenes/cornell_box.toml
//   pathlab render assets/scenes/cornell_box.toml --technique light:examples/techniques/triangle_area.wgsl --method mis+light=triangle_area

fn sample_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, u: vec2f) -> vec3f {
    let s = sqrt(u.x);
    return (1.0 - s) * light.p0 + (s * (1.0 - u.y)) * light.p1 + (s * u.y) * light.p2;
}

fn pdf_triangle_light_technique(x: vec3f, n: vec3f, light: TriangleLight, p: vec3f) -> f32 {
    let c = cross(light.p1 - light.p0, light.p2 - light.p0);
    let area = 0.5 * length(c);
    let to_x = x - p;
    let dist2 = dot(to_x, to_x);
    // |cos(theta_light)|: the triangle is seen from either side.
    let cos_light = abs(dot(c, to_x)) / (length(c) * sqrt(dist2));
    return dist2 / (area * cos_light);
}
