// lights.wgsl — sampling the shapes area lights are made of, seen from a shading point x (as
// pbrt-v4's Sphere::Sample and Triangle::Sample): spheres, then triangles. The emitters of
// shaders/emitters/ call these; they read no scene, so the sampling tests run them alone.
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

// ---- Triangle lights ----
//
// A triangle (p0, p1, p2) emits on the side of its winding normal cross(p1 - p0, p2 - p0)
// unless two-sided. Two strategies (TRIANGLE_SAMPLING):
//   area:        a point uniform on the triangle (pdf 1 / area), converted to solid angle at x
//                by dist^2 / |cos(theta_light)|, as Mitsuba does;
//   solid-angle: a direction uniform in the spherical triangle the triangle subtends at x
//                (Arvo 1995, pbrt-v4's SampleSphericalTriangle): pdf 1 / Omega; where Omega
//                is below TRIANGLE_MIN_SOLID_ANGLE or above TRIANGLE_MAX_SOLID_ANGLE (f32
//                cannot sample such triangles accurately) it falls back to area sampling, as
//                pbrt-v4's Triangle::Sample does. The upper threshold is pbrt-v4's (6.22 sr);
//                the lower one is 2e-2 sr, not pbrt's 3e-4: in f32 on the GPU the chi-square
//                test rejects Arvo's sampling below about 1e-2 sr (p < 1e-4 at 1.5e-3 and
//                3.3e-3 sr, p = 0.002 at 9e-3 sr; tests/chi2_sampling.rs), where the
//                sub-triangle's area and the new vertex lose too many digits.
// pdf_triangle_light() returns the density either strategy gives a direction, a function of
// (x, wi) alone, as multiple importance sampling requires.

// How triangle lights are sampled (set through pipeline constants; values generated from
// `method::TriangleSampling`).
override TRIANGLE_SAMPLING: u32 = TRIANGLES_AREA;

const TRIANGLE_MIN_SOLID_ANGLE: f32 = 2e-2;
const TRIANGLE_MAX_SOLID_ANGLE: f32 = 6.22;

// Solid angle of the triangle seen from x.
fn triangle_solid_angle(p0: vec3f, p1: vec3f, p2: vec3f, x: vec3f) -> f32 {
    return spherical_triangle_solid_angle(normalize(p0 - x), normalize(p1 - x), normalize(p2 - x));
}

// Whether the solid-angle strategy samples this triangle from x (else: by area).
fn triangle_uses_solid_angle(omega: f32) -> bool {
    return TRIANGLE_SAMPLING == TRIANGLES_SOLID_ANGLE && omega >= TRIANGLE_MIN_SOLID_ANGLE && omega <= TRIANGLE_MAX_SOLID_ANGLE;
}

// Distance from x along unit wi to the triangle's plane (n: its unit normal), or -1.
fn distance_to_plane(p0: vec3f, n: vec3f, x: vec3f, wi: vec3f) -> f32 {
    let t = dot(p0 - x, n) / dot(wi, n);
    return select(-1.0, t, t > 0.0 && t < INFINITY);
}

// Solid-angle density at x of a point drawn uniformly on a surface of `area`, seen at distance
// dist along wi where the surface's unit normal is n: dist^2 / (area |cos(theta_light)|).
fn pdf_area_point(area: f32, n: vec3f, dist: f32, wi: vec3f) -> f32 {
    let cos_light = abs(dot(n, wi));
    let pdf = dist * dist / (area * cos_light);
    return select(0.0, pdf, cos_light > 0.0 && dist > 0.0 && pdf < INFINITY);
}

// Solid-angle density of the triangles' area strategy.
fn pdf_triangle_area(area: f32, n: vec3f, dist: f32, wi: vec3f) -> f32 {
    return pdf_area_point(area, n, dist, wi);
}

// Uniform point on the triangle: barycentrics (1 - sqrt(u0), sqrt(u0) (1 - u1), sqrt(u0) u1).
fn sample_triangle_area_point(p0: vec3f, p1: vec3f, p2: vec3f, u: vec2f) -> vec3f {
    let s = sqrt(u.x);
    return (1.0 - s) * p0 + (s * (1.0 - u.y)) * p1 + (s * u.y) * p2;
}

// A direction from x towards the triangle with the pipeline's strategy. `dist` is the distance
// to the point on the triangle; pdf 0 marks a sample that cannot contribute.
fn sample_triangle_light(p0: vec3f, p1: vec3f, p2: vec3f, x: vec3f, u: vec2f) -> LightSample {
    let c = cross(p1 - p0, p2 - p0);
    let area = 0.5 * length(c);
    let n = normalize(c);
    if (TRIANGLE_SAMPLING == TRIANGLES_SOLID_ANGLE) {
        let omega = triangle_solid_angle(p0, p1, p2, x);
        if (triangle_uses_solid_angle(omega)) {
            let wi = sample_spherical_triangle(normalize(p0 - x), normalize(p1 - x), normalize(p2 - x), u);
            let dist = distance_to_plane(p0, n, x, wi);
            let ok = dot(wi, wi) > 0.0 && dist > 0.0;
            return LightSample(wi, max(dist, 0.0), select(0.0, 1.0 / omega, ok));
        }
    }
    let p = sample_triangle_area_point(p0, p1, p2, u);
    let to_p = p - x;
    let dist = length(to_p);
    let wi = to_p / dist;
    return LightSample(wi, dist, pdf_triangle_area(area, n, dist, wi));
}

// Solid-angle density with which sample_triangle_light() produces wi from x (for a direction
// that meets the triangle).
fn pdf_triangle_light(p0: vec3f, p1: vec3f, p2: vec3f, x: vec3f, wi: vec3f) -> f32 {
    if (TRIANGLE_SAMPLING == TRIANGLES_SOLID_ANGLE) {
        let omega = triangle_solid_angle(p0, p1, p2, x);
        if (triangle_uses_solid_angle(omega)) {
            return 1.0 / omega;
        }
    }
    let c = cross(p1 - p0, p2 - p0);
    let n = normalize(c);
    return pdf_triangle_area(0.5 * length(c), n, distance_to_plane(p0, n, x, wi), wi);
}
