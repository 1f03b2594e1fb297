// warp.wgsl — maps from the unit square to directions, each with its solid-angle pdf.
// Local frame: +z is the axis of the distribution (normal, mirror direction or cone axis).

// Uniform on the unit sphere: z = 1 - 2u, sin(theta) = 2 sqrt(u (1 - u)) (no cancellation).
fn square_to_uniform_sphere(u: vec2f) -> vec3f {
    let z = 1.0 - 2.0 * u.x;
    let r = 2.0 * safe_sqrt(u.x * (1.0 - u.x));
    return spherical_direction(z, r, TWO_PI * u.y);
}

fn pdf_uniform_sphere() -> f32 {
    return INV_4PI;
}

// Uniform on the hemisphere z > 0: cos(theta) = 1 - u.
fn square_to_uniform_hemisphere(u: vec2f) -> vec3f {
    let z = 1.0 - u.x;
    let r = safe_sqrt(u.x * (2.0 - u.x));
    return spherical_direction(z, r, TWO_PI * u.y);
}

fn pdf_uniform_hemisphere(cos_theta: f32) -> f32 {
    return select(0.0, INV_2PI, cos_theta > 0.0);
}

// Cosine-weighted hemisphere (Malley): sin^2(theta) = u, pdf cos(theta) / pi.
fn square_to_cosine_hemisphere(u: vec2f) -> vec3f {
    let sin_theta = sqrt(u.x);
    let cos_theta = sqrt(1.0 - u.x);
    return spherical_direction(cos_theta, sin_theta, TWO_PI * u.y);
}

fn pdf_cosine_hemisphere(cos_theta: f32) -> f32 {
    return max(cos_theta, 0.0) * INV_PI;
}

// Phong lobe around +z: cos(alpha) = v^(1/(n+1)) with v = 1 - u in (0, 1].
// 1 - cos(alpha) = -expm1(log(v) / (n+1)) keeps sin(alpha) accurate as alpha -> 0 (huge n).
fn square_to_phong_lobe(u: vec2f, n: f32) -> vec3f {
    let log_cos = log(1.0 - u.x) / (n + 1.0);
    let one_minus_cos = -expm1_stable(log_cos);
    let cos_alpha = 1.0 - one_minus_cos;
    let sin_alpha = safe_sqrt(one_minus_cos * (2.0 - one_minus_cos));
    return spherical_direction(cos_alpha, sin_alpha, TWO_PI * u.y);
}

// cos^n(alpha) from 1 - cos(alpha); zero outside the lobe (cos(alpha) <= 0), also for n = 0.
fn phong_cos_pow(one_minus_cos: f32, n: f32) -> f32 {
    if (one_minus_cos >= 1.0) {
        return 0.0;
    }
    if (n == 0.0) {
        return 1.0;
    }
    return exp(n * log1m_stable(one_minus_cos));
}

// Solid-angle pdf of the Phong lobe: (n+1) / (2 pi) cos^n(alpha).
fn pdf_phong_lobe(one_minus_cos: f32, n: f32) -> f32 {
    return (n + 1.0) * INV_2PI * phong_cos_pow(one_minus_cos, n);
}

// 1 - cos(angle between unit vectors a and b) as |a - b|^2 / 2: keeps its relative accuracy
// when the angle is tiny, unlike 1 - dot(a, b).
fn one_minus_cos_between(a: vec3f, b: vec3f) -> f32 {
    let d = a - b;
    return 0.5 * dot(d, d);
}

// Uniform in the cone cos(theta) >= cos(theta_max) around +z, given 1 - cos(theta_max):
// 1 - cos(theta) = u (1 - cos(theta_max)), sin^2(theta) = v (2 - v) (no cancellation).
fn square_to_uniform_cone(u: vec2f, one_minus_cos_max: f32) -> vec3f {
    let v = u.x * one_minus_cos_max;
    let sin_theta = safe_sqrt(v * (2.0 - v));
    return spherical_direction(1.0 - v, sin_theta, TWO_PI * u.y);
}

// Solid-angle pdf of the cone: 1 / (2 pi (1 - cos(theta_max))).
fn pdf_uniform_cone(one_minus_cos_max: f32) -> f32 {
    return INV_2PI / one_minus_cos_max;
}

// Shirley and Chiu's concentric map of the unit square onto the unit disk.
fn square_to_uniform_disk_concentric(u: vec2f) -> vec2f {
    let x = 2.0 * u.x - 1.0;
    let y = 2.0 * u.y - 1.0;
    let q13 = abs(x) < abs(y);
    let r = select(x, y, q13);
    let rp = select(y, x, q13);
    var phi = 0.25 * PI * rp / r;
    phi = select(phi, 0.5 * PI - phi, q13);
    phi = select(phi, 0.0, x == 0.0 && y == 0.0);
    return vec2f(r * cos(phi), r * sin(phi));
}
