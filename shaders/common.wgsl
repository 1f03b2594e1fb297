// common.wgsl — constants and small numerically careful helpers shared by every kernel.

const PI: f32 = 3.14159265358979323846;
const INV_PI: f32 = 0.31830988618379067154;
const INV_2PI: f32 = 0.15915494309189533577;
const INV_4PI: f32 = 0.07957747154594766788;
const TWO_PI: f32 = 6.28318530717958647692;
// Largest f32 below 1: samples live in [0, ONE_MINUS_EPSILON].
const ONE_MINUS_EPSILON: f32 = 0.99999994;
const INFINITY: f32 = 3.4028235e38;
const INVALID: u32 = 0xffffffffu;

// Texel j of a texel table: row j / TEXEL_TABLE_WIDTH, column j mod TEXEL_TABLE_WIDTH.
fn texel_coords(j: u32) -> vec2u {
    return vec2u(j % TEXEL_TABLE_WIDTH, j / TEXEL_TABLE_WIDTH);
}

fn safe_sqrt(x: f32) -> f32 {
    return sqrt(max(x, 0.0));
}

fn max3(v: vec3f) -> f32 {
    return max(v.x, max(v.y, v.z));
}

fn min3(v: vec3f) -> f32 {
    return min(min(v.x, v.y), v.z);
}

// min(a, b) and max(a, b) for operands that are not NaN, as lavapipe computes them (b where
// they are equal, so also the same zero's sign), without the NaN handling WGSL's min and max
// require: a compare and a blend per component more on lavapipe. Where a NaN may occur, the
// caller says why the result does not matter.
fn ordered_min(a: f32, b: f32) -> f32 {
    return select(b, a, a < b);
}

fn ordered_max(a: f32, b: f32) -> f32 {
    return select(b, a, a > b);
}

// The same per component.
fn ordered_min_vec(a: vec3f, b: vec3f) -> vec3f {
    return select(b, a, a < b);
}

fn ordered_max_vec(a: vec3f, b: vec3f) -> vec3f {
    return select(b, a, a > b);
}

// exp(x) - 1 without cancellation near 0 (Taylor series to x^5 where |x| < 1e-2).
fn expm1_stable(x: f32) -> f32 {
    if (abs(x) < 1e-2) {
        return x * (1.0 + x * (0.5 + x * (1.0 / 6.0 + x * (1.0 / 24.0 + x * (1.0 / 120.0)))));
    }
    return exp(x) - 1.0;
}

// log(1 - d) for 0 <= d < 1 without cancellation for small d.
fn log1m_stable(d: f32) -> f32 {
    if (d < 1e-2) {
        return -d * (1.0 + d * (0.5 + d * (1.0 / 3.0 + d * (0.25 + d * 0.2))));
    }
    return log(1.0 - d);
}

// Barycentrics (of p1 and p2) of a point p in the plane of the triangle p0 p1 p2: the solution
// of p - p0 = b1 e1 + b2 e2 in the least-squares sense (Cramer's rule on the normal equations).
fn plane_barycentrics(p0: vec3f, p1: vec3f, p2: vec3f, p: vec3f) -> vec2f {
    let e1 = p1 - p0;
    let e2 = p2 - p0;
    let d = p - p0;
    let d11 = dot(e1, e1);
    let d12 = dot(e1, e2);
    let d22 = dot(e2, e2);
    let d1 = dot(d, e1);
    let d2 = dot(d, e2);
    return vec2f(d22 * d1 - d12 * d2, d11 * d2 - d12 * d1) / (d11 * d22 - d12 * d12);
}

// The partial derivatives of a surface's position along its uv parametrisation, with their
// lengths (Mitsuba's si.dp_du, si.dp_dv): surface_partials (intersect.wgsl), triangle_partials
// (bvh.wgsl).
struct Partials {
    du: vec3f,
    dv: vec3f,
}

// Orthonormal basis around a unit vector n (Duff et al. 2017, branchless).
struct Frame {
    t: vec3f,
    b: vec3f,
    n: vec3f,
}

fn frame_from_normal(n: vec3f) -> Frame {
    let s = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    let t = vec3f(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    let bb = vec3f(b, s + n.y * n.y * a, -n.y);
    return Frame(t, bb, n);
}

fn frame_to_world(f: Frame, v: vec3f) -> vec3f {
    return f.t * v.x + f.b * v.y + f.n * v.z;
}

fn frame_to_local(f: Frame, v: vec3f) -> vec3f {
    return vec3f(dot(v, f.t), dot(v, f.b), dot(v, f.n));
}

// Direction with polar angle given by (cos, sin) around +z and azimuth phi.
fn spherical_direction(cos_theta: f32, sin_theta: f32, phi: f32) -> vec3f {
    return vec3f(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}

// Mirror direction of w about the unit normal n.
fn reflect_about(w: vec3f, n: vec3f) -> vec3f {
    return 2.0 * dot(w, n) * n - w;
}

// asin and atan2 to ~1 ulp. Vulkan lets the built-ins err far more (llvmpipe's asin is off by
// up to 2e-4 absolute, its atan2 by 3e-6: measured), which the interior angles of a small
// spherical triangle cannot afford. Cephes' single-precision minimax polynomials (asinf,
// atanf), with their range reductions.
fn asin_accurate(x_in: f32) -> f32 {
    let a = min(abs(x_in), 1.0);
    let big = a > 0.5;
    // |x| > 1/2: asin(a) = pi/2 - 2 asin(sqrt((1 - a) / 2)).
    let z = select(a * a, 0.5 * (1.0 - a), big);
    let x = select(a, sqrt(z), big);
    let p = ((((4.2163199048e-2 * z + 2.4181311049e-2) * z + 4.5470025998e-2) * z + 7.4953002686e-2) * z + 1.6666752422e-1) * z * x + x;
    let r = select(p, 1.5707963267948966 - 2.0 * p, big);
    return select(r, -r, x_in < 0.0);
}

fn atan_accurate(x_in: f32) -> f32 {
    let a = abs(x_in);
    // Reduce to |x| <= tan(pi/8): atan(a) = pi/2 + atan(-1/a) or pi/4 + atan((a-1)/(a+1)).
    var y = 0.0;
    var x = a;
    if (a > 2.414213562373095) {
        y = 1.5707963267948966;
        x = -1.0 / a;
    } else if (a > 0.4142135623730950) {
        y = 0.7853981633974483;
        x = (a - 1.0) / (a + 1.0);
    }
    let z = x * x;
    let r = y + (((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1) * z * x + x;
    return select(r, -r, x_in < 0.0);
}

fn atan2_accurate(y: f32, x: f32) -> f32 {
    if (x == 0.0) {
        return select(select(0.0, -0.5 * PI, y < 0.0), 0.5 * PI, y > 0.0);
    }
    let t = atan_accurate(y / x);
    if (x > 0.0) {
        return t;
    }
    return select(t - PI, t + PI, y >= 0.0);
}
