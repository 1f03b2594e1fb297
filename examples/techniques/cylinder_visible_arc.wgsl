// cylinder_visible_arc.wgsl — a cylinder-light technique none of the built-ins is: from a point
// x outside a cylinder light and within its length, only the arc of its surface that x can see
// is sampled, where area sampling (Mitsuba's, pathlab's built-in) spends samples on the far
// side, hidden by the cylinder itself. In the cylinder's own frame (the points base + cos(phi)
// axis_u + sin(phi) axis_v + z axis), x at distance rho > 1 from the axis, in direction alpha,
// with 0 <= z_x <= 1, sees exactly the points with |phi - alpha| <= beta = acos(1 / rho): the
// sight lines to the others enter the cylinder within its length. There phi is drawn uniform
// in [alpha - beta, alpha + beta] and z uniform in [0, 1]. Elsewhere (inside it, or beyond an
// end, where x may see the inner surface through the opening) the whole cylinder is sampled.
// From 1.5 radii the visible arc is 96 of 360 degrees; from far away it tends to half.
//
//   pathlab check-technique light:examples/techniques/cylinder_visible_arc.wgsl --scene tests/fixtures/quadrics/quadrics.xml

// x in the cylinder's frame (the dual basis of its three axes).
fn visible_arc_local(light: CylinderLight, x: vec3f) -> vec3f {
    let d = x - light.base;
    let det = dot(light.axis_u, cross(light.axis_v, light.axis));
    return vec3f(dot(d, cross(light.axis_v, light.axis)), dot(d, cross(light.axis, light.axis_u)), dot(d, cross(light.axis_u, light.axis_v))) / det;
}

// The arc x sees: its centre alpha (x) and half-width beta (y); half-width pi for the whole.
fn visible_arc_of(light: CylinderLight, x: vec3f) -> vec2f {
    let l = visible_arc_local(light, x);
    let rho = length(l.xy);
    if (rho > 1.0 && l.z >= 0.0 && l.z <= 1.0) {
        return vec2f(atan2(l.y, l.x), acos(1.0 / rho));
    }
    return vec2f(0.0, PI);
}

fn sample_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, u: vec2f) -> vec3f {
    let arc = visible_arc_of(light, x);
    let phi = arc.x + (2.0 * u.y - 1.0) * arc.y;
    return light.base + cos(phi) * light.axis_u + sin(phi) * light.axis_v + u.x * light.axis;
}

fn pdf_cylinder_light_technique(x: vec3f, n: vec3f, light: CylinderLight, p: vec3f) -> f32 {
    let arc = visible_arc_of(light, x);
    let l = visible_arc_local(light, p);
    let phi = atan2(l.y, l.x);
    // The angle from the arc's centre, in [-pi, pi]: outside the arc, no density.
    var offset = phi - arc.x;
    offset = offset - 2.0 * PI * round(offset / (2.0 * PI));
    if (abs(offset) > arc.y) {
        return 0.0;
    }
    let c = cross(-sin(phi) * light.axis_u + cos(phi) * light.axis_v, light.axis);
    let to_x = x - p;
    let dist2 = dot(to_x, to_x);
    let cos_light = abs(dot(c, to_x)) / (length(c) * sqrt(dist2));
    // A sample on the arc's very edge, where the sight line grazes the cylinder, sees none of
    // it (and an infinite density there would be a fault).
    if (!(cos_light > 0.0)) {
        return 0.0;
    }
    // Uniform in (phi, z) over the arc x [0, 1]: an area density of 1 / (2 beta |c|).
    return dist2 / (2.0 * arc.y * length(c) * cos_light);
}
