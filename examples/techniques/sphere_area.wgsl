// sphere_area.wgsl — a light technique none of pathlab's built-ins is: points drawn uniformly
// by area on the half of a spherical light that faces the shading point x (the hemisphere
// about the direction from the centre to x), instead of directions uniform in the cone the
// sphere subtends (pathlab's and pbrt-v4's strategy). Its density per unit solid angle at x is
// the area density 1 / (2 pi r^2) times dist^2 / cos(theta_light). Points of that half that x
// cannot see (beyond the visible cap, whose edge is where the sight line grazes the sphere) are
// hidden by the sphere itself and contribute nothing: from close by, most of the half is
// hidden; from far away almost none of it, but cos(theta_light) still varies over the cap.
//
//   pathlab check-technique light:examples/techniques/sphere_area.wgsl --scene assets/scenes/study.toml

fn sample_light_technique(x: vec3f, n: vec3f, light: SphereLight, u: vec2f) -> vec3f {
    let axis = normalize(x - light.center);
    // Uniform on the hemisphere about `axis` (uniform in cos, Archimedes).
    let cos_t = u.x;
    let sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
    let phi = 2.0 * PI * u.y;
    let local = vec3f(sin_t * cos(phi), sin_t * sin(phi), cos_t);
    return light.center + light.radius * frame_to_world(frame_from_normal(axis), local);
}

fn pdf_light_technique(x: vec3f, n: vec3f, light: SphereLight, p: vec3f) -> f32 {
    let normal = (p - light.center) / light.radius;
    let to_x = x - p;
    let dist2 = dot(to_x, to_x);
    let cos_light = dot(normal, to_x) / sqrt(dist2);
    // The visible cap lies in the hemisphere facing x: every point the pdf is asked about is
    // one sample_ can draw.
    if (cos_light <= 0.0) {
        return 0.0;
    }
    return dist2 / (2.0 * PI * light.radius * light.radius * cos_light);
}
