// quadric_area.wgsl — a light technique for disk and cylinder lights: points uniform in the
// parameters of each shape, as Mitsuba's disk and cylinder sample their positions (and
// pathlab's built-in strategy for them), written as a researcher would write their own. A disk:
// the concentric map of u onto the unit disk, placed by the light's axes (uniform by area, also
// for an ellipse). A cylinder: phi = 2 pi u1, z = u0 (uniform by area on a circular cylinder).
// Each density is the area density of the procedure times dist^2 / |cos(theta_light)|, the
// Jacobian from area to solid angle at x.
//
//   pathlab check-technique light:examples/techniques/quadric_area.wgsl --scene tests/fixtures/quadrics/quadrics.xml
//   pathlab render tests/fixtures/quadrics/quadrics.xml --technique light:examples/techniques/quadric_area.wgsl --method mis+light=quadric_area

fn sample_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, u: vec2f) -> vec3f {
    let d = square_to_uniform_disk_concentric(u);
    return light.center + d.x * light.axis_u + d.y * light.axis_v;
}

fn pdf_disk_light_technique(x: vec3f, n: vec3f, light: DiskLight, p: vec3f) -> f32 {
    let c = cross(light.axis_u, light.axis_v);
    let area = PI * length(c);
    let to_x = x - p;
    let dist2 = dot(to_x, to_x);
    // |cos(theta_light)|: the disk is seen from either side.
    let cos_light = abs(dot(c, to_x)) / (length(c) * sqrt(dist2));
    return dist2 / (area * cos_light);
}

fn sample_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, u: vec2f) -> vec3f {
    let phi = 2.0 * PI * u.y;
    return light.base + cos(phi) * light.axis_u + sin(phi) * light.axis_v + u.x * light.axis;
}

// The angle of a point p of the cylinder: its coordinates along axis_u and axis_v (the dual
// basis of the three axes).
fn quadric_area_phi(light: CylinderLight, p: vec3f) -> f32 {
    let d = p - light.base;
    let det = dot(light.axis_u, cross(light.axis_v, light.axis));
    return atan2(dot(d, cross(light.axis, light.axis_u)) / det, dot(d, cross(light.axis_v, light.axis)) / det);
}

fn pdf_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, p: vec3f) -> f32 {
    // The area element per dphi dz, |dp/dphi x axis|, and the normal along it.
    let phi = quadric_area_phi(light, p);
    let c = cross(-sin(phi) * light.axis_u + cos(phi) * light.axis_v, light.axis);
    let to_x = x - p;
    let dist2 = dot(to_x, to_x);
    let cos_light = abs(dot(c, to_x)) / (length(c) * sqrt(dist2));
    // Uniform in (phi, z) over [0, 2 pi) x [0, 1]: an area density of 1 / (2 pi |c|).
    return dist2 / (2.0 * PI * length(c) * cos_light);
}
