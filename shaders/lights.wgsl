// lights.wgsl — sampling emissive spheres seen from a shading point x.
//
// From outside a sphere, directions are drawn uniformly in the cone it subtends; from inside
// (or from its inner surface), points are drawn uniformly on its area. Both densities are
// returned per unit solid angle at x, and pdf_sphere_light() gives the same value for any
// direction that hits the sphere, as multiple importance sampling requires.

struct LightSample {
    wi: vec3f,
    // Distance from x to the sampled point on the sphere.
    dist: f32,
    // Solid-angle density at x.
    pdf: f32,
}

// 1 - cos(theta_max) of the cone subtended by a sphere of radius r at distance d > r:
// sin^2 / (1 + cos) with sin^2 = (r/d)^2, exact and free of cancellation for tiny spheres.
fn sphere_cone_one_minus_cos_max(dist: f32, radius: f32) -> f32 {
    let s = radius / dist;
    let sin2_max = s * s;
    return sin2_max / (1.0 + safe_sqrt(1.0 - sin2_max));
}

// Uniform direction in the cone subtended by the sphere (x outside it).
fn sample_sphere_light_cone(center: vec3f, radius: f32, x: vec3f, u: vec2f) -> LightSample {
    let to_center = center - x;
    let dist = length(to_center);
    let axis = to_center / dist;
    let omc_max = sphere_cone_one_minus_cos_max(dist, radius);
    let local = square_to_uniform_cone(u, omc_max);
    let wi = normalize(frame_to_world(frame_from_normal(axis), local));
    // Distance to the near intersection: d cos(theta) - sqrt(r^2 - d^2 sin^2(theta)).
    let sin2_theta = local.x * local.x + local.y * local.y;
    let half_chord = safe_sqrt(radius * radius - dist * dist * sin2_theta);
    let t = max(dist * local.z - half_chord, 0.0);
    return LightSample(wi, t, pdf_uniform_cone(omc_max));
}

// Uniform point on the sphere's area (x inside it): pdf_area = 1 / (4 pi r^2), converted to
// solid angle at x by dist^2 / |cos(theta_light)|.
fn sample_sphere_light_area(center: vec3f, radius: f32, x: vec3f, u: vec2f) -> LightSample {
    let n_light = square_to_uniform_sphere(u);
    let p = center + radius * n_light;
    let to_p = p - x;
    let dist = length(to_p);
    let wi = to_p / dist;
    let cos_light = abs(dot(n_light, wi));
    let pdf = dist * dist / (4.0 * PI * radius * radius * cos_light);
    return LightSample(wi, dist, select(0.0, pdf, cos_light > 0.0 && dist > 0.0));
}

// Solid-angle density with which sample_sphere_light_* produces direction wi from x (for a
// direction that meets the sphere). `inside` picks the strategy. From inside, the sampled point
// is where the ray (x, wi) leaves the sphere: the far root -b + sqrt(b^2 - c), recomputed here
// from x itself (not from a traced hit, whose ray started at an offset origin), so the density
// is exactly a function of (x, wi), as next event estimation sampled it.
fn pdf_sphere_light(center: vec3f, radius: f32, x: vec3f, inside: bool, wi: vec3f) -> f32 {
    if (inside) {
        let f = x - center;
        let b = dot(f, wi);
        let c = dot(f, f) - radius * radius;
        let t = -b + safe_sqrt(b * b - c);
        let n_light = (f + wi * t) / radius;
        let cos_light = abs(dot(n_light, wi));
        if (cos_light <= 0.0 || t <= 0.0) {
            return 0.0;
        }
        return t * t / (4.0 * PI * radius * radius * cos_light);
    }
    return pdf_uniform_cone(sphere_cone_one_minus_cos_max(length(center - x), radius));
}

// Power heuristic with beta = 2 (Veach): weight of the strategy with density pdf_a.
// Written as 1 / (1 + (pdf_b / pdf_a)^2) so that huge densities cannot overflow to inf / inf.
fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    if (pdf_a <= 0.0) {
        return 0.0;
    }
    let ratio = pdf_b / pdf_a;
    return 1.0 / (1.0 + ratio * ratio);
}
