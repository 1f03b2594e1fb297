// spherical_triangle.wgsl — uniform solid-angle sampling of a spherical triangle
// (Arvo 1995, "Stratified Sampling of Spherical Triangles"), for next event
// estimation towards triangle lights.
//
// Ported from pbrt-v4 (github.com/mmp/pbrt-v4 @ 5f7a6068):
//   - SampleSphericalTriangle()        src/pbrt/util/sampling.cpp
//   - SphericalTriangleArea()          src/pbrt/util/vecmath.h
//   - DifferenceOfProducts(), SumOfProducts(), SafeASin()   src/pbrt/util/math.h
//   - Cross(), AngleBetween(), GramSchmidt()                src/pbrt/util/vecmath.h
// pbrt's optional bilinear warp for the cos(theta) factor (SampleBilinear /
// BilinearPDF in Triangle::Sample) is deliberately NOT included: the
// directions returned here are uniform in solid angle, so
//     pdf(w) = 1 / spherical_triangle_solid_angle(a, b, c)   [1/sr]
// for every w inside the spherical triangle.
//
// Requires from common.wgsl: PI, safe_sqrt.
//
// Caller's contract (same as pbrt's Triangle::Sample): use this only when
//     3e-4 sr <= spherical_triangle_solid_angle(a, b, c) <= 6.22 sr
// and fall back to uniform area sampling of the triangle otherwise (tiny or
// almost-hemispherical spherical triangles are numerically unstable in f32).

// a*b - c*d with the rounding error of c*d compensated (Kahan's algorithm,
// pbrt-v4 DifferenceOfProducts). Note: WGSL only guarantees fma's accuracy to
// be that of e1 * e2 + e3, so on a backend that does not fuse it, this
// degrades gracefully to the plain a*b - c*d (the error term becomes ~0).
fn sph_difference_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let difference_of_products = fma(a, b, -cd);
    let error = fma(-c, d, cd);
    return difference_of_products + error;
}

// a*b + c*d with the rounding error of c*d compensated (pbrt-v4 SumOfProducts).
fn sph_sum_of_products(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let sum_of_products = fma(a, b, cd);
    let error = fma(c, d, -cd);
    return sum_of_products + error;
}

// Cross product with each component evaluated by DifferenceOfProducts
// (pbrt-v4 Cross(Vector3, Vector3)); more accurate than the builtin cross()
// for nearly parallel vectors, which is exactly the small-triangle case.
fn sph_cross(v: vec3f, w: vec3f) -> vec3f {
    return vec3f(
        sph_difference_of_products(v.y, w.z, v.z, w.y),
        sph_difference_of_products(v.z, w.x, v.x, w.z),
        sph_difference_of_products(v.x, w.y, v.y, w.x),
    );
}

// asin with its argument clamped to [-1, 1] (pbrt-v4 SafeASin).
fn sph_safe_asin(x: f32) -> f32 {
    return asin_accurate(clamp(x, -1.0, 1.0));
}

// Angle between two unit vectors, equivalent to acos(dot(v1, v2)) but accurate
// near 0 and pi (pbrt-v4 AngleBetween, via plunk.org/~hatch/rightway.html):
// the chord length |v2 - v1| = 2 sin(theta/2), and |v1 + v2| = 2 cos(theta/2).
fn sph_angle_between(v1: vec3f, v2: vec3f) -> f32 {
    if (dot(v1, v2) < 0.0) {
        return PI - 2.0 * sph_safe_asin(length(v1 + v2) * 0.5);
    }
    return 2.0 * sph_safe_asin(length(v2 - v1) * 0.5);
}

// Component of v orthogonal to the unit vector w (pbrt-v4 GramSchmidt; the
// result is NOT normalized).
fn sph_gram_schmidt(v: vec3f, w: vec3f) -> vec3f {
    return v - dot(v, w) * w;
}

// normalize() that returns the zero vector instead of NaN for a zero input.
// (pbrt calls Normalize() directly; this guard only matters in exactly
// degenerate configurations, where the zero vector is multiplied by a sine
// that is itself 0, so the result equals pbrt's intended limit.)
fn sph_safe_normalize(v: vec3f) -> vec3f {
    let len2 = dot(v, v);
    return select(vec3f(0.0), v * inverseSqrt(len2), len2 > 0.0);
}

// Solid angle [sr] subtended by the spherical triangle with unit-vector
// vertices a, b, c (pbrt-v4 SphericalTriangleArea; Van Oosterom & Strackee
// 1983):
//     tan(Omega / 2) = |a . (b x c)| / (1 + a.b + a.c + b.c)
// atan2 keeps the correct quadrant when the denominator is negative
// (Omega > pi). pbrt writes abs(2 atan2(triple, denom)), which is the same.
fn spherical_triangle_solid_angle(a: vec3f, b: vec3f, c: vec3f) -> f32 {
    let triple = dot(a, sph_cross(b, c));
    return 2.0 * atan2_accurate(abs(triple), 1.0 + dot(a, b) + dot(a, c) + dot(b, c));
}

// Direction uniformly distributed in solid angle over the spherical triangle
// with unit-vector vertices a, b, c (any winding), given u in [0,1)^2.
// Ported from pbrt-v4 SampleSphericalTriangle() (without the barycentric
// conversion: we return the direction itself).
//
// Returns vec3f(0.0) when the triangle is degenerate (two vertices parallel,
// zero spherical excess, or the Arvo quadratic's denominator vanishes). pbrt
// signals these cases with pdf = 0 / an empty sample; the caller should treat
// a zero return as "no sample" (check dot(w, w) == 0.0).
//
// pdf of a successful sample = 1 / spherical_triangle_solid_angle(a, b, c).
fn sample_spherical_triangle(a: vec3f, b: vec3f, c: vec3f, u: vec2f) -> vec3f {
    // Normals of the three great circles through the edges: n_ab is the
    // normal of the plane through the origin, a and b, etc.
    var n_ab = sph_cross(a, b);
    var n_bc = sph_cross(b, c);
    var n_ca = sph_cross(c, a);
    if (dot(n_ab, n_ab) == 0.0 || dot(n_bc, n_bc) == 0.0 || dot(n_ca, n_ca) == 0.0) {
        return vec3f(0.0); // two vertices coincide (or are antipodal)
    }
    n_ab = normalize(n_ab);
    n_bc = normalize(n_bc);
    n_ca = normalize(n_ca);

    // Interior (dihedral) angles alpha, beta, gamma at vertices a, b, c:
    // the angle between the two great-circle planes meeting at each vertex.
    // The sign flips orient both normals consistently for either winding.
    let alpha = sph_angle_between(n_ab, -n_ca);
    let beta = sph_angle_between(n_bc, -n_ab);
    let gamma = sph_angle_between(n_ca, -n_bc);

    // The spherical excess A = alpha + beta + gamma - pi, taken from the solid angle formula
    // (no cancellation, and the same value pdf_triangle_light() divides by). Arvo step 1:
    // the sub-triangle (a, b, c') gets area A' = u0 A, uniform in [0, A].
    let area = spherical_triangle_solid_angle(a, b, c);
    if (area <= 0.0) {
        return vec3f(0.0); // zero (or negative, by rounding) spherical excess
    }
    let ap = u.x * area;

    // phi = A' + pi - alpha, the sum of the sub-triangle's two other angles. With the
    // identities sin(A' + pi) = -sin(A'), cos(A' + pi) = -cos(A') (A' small: no rounding of
    // pi + A'):
    //     sin(phi) = sin(alpha - A'),   cos(phi) = -cos(alpha - A')
    let cos_alpha = cos(alpha);
    let sin_alpha = sin(alpha);
    let sin_ap = sin(ap);
    let cos_ap = cos(ap);
    // 1 - cos(A') = 2 sin^2(A'/2), without cancellation.
    let s_half = sin(0.5 * ap);
    let one_minus_cos_ap = 2.0 * s_half * s_half;
    let sin_phi = cos_ap * sin_alpha - sin_ap * cos_alpha;
    let cos_phi = -(cos_ap * cos_alpha + sin_ap * sin_alpha);

    // Arvo's cos(b') from the quadratic: b' is the arc length from a to the new vertex c' on
    // edge ac such that triangle (a, b, c') has area A'. With
    //     k1 = cos(phi) + cos(alpha) = cos(alpha) (1 - cos A') - sin(A') sin(alpha)
    //     k2 = sin(phi) - sin(alpha) cos(c) = sin(alpha) ((1 - cos c) - (1 - cos A')) - sin(A') cos(alpha)
    // (cos(c) = a . b, the side opposite c; 1 - cos(c) = |a - b|^2 / 2), written so that
    // neither cancels for small triangles, Arvo's closed form is
    //     cos(b') = (k2 + (k2 cos(phi) - k1 sin(phi)) cos(alpha))
    //             / ((k2 sin(phi) + k1 cos(phi)) sin(alpha)),
    // with both inner terms evaluated with compensated products.
    let k1 = cos_alpha * one_minus_cos_ap - sin_ap * sin_alpha;
    let ab = a - b;
    let k2 = sin_alpha * (0.5 * dot(ab, ab) - one_minus_cos_ap) - sin_ap * cos_alpha;
    let denom = sph_sum_of_products(k2, sin_phi, k1, cos_phi) * sin_alpha;
    if (denom == 0.0) {
        // pbrt CHECKs !IsNaN(cosBp) here; happens when the triangle covers
        // (nearly) the whole hemisphere, which the 6.22 sr cap should exclude.
        return vec3f(0.0);
    }
    var cos_bp = (k2 + sph_difference_of_products(k2, cos_phi, k1, sin_phi) * cos_alpha) / denom;
    cos_bp = clamp(cos_bp, -1.0, 1.0);

    // New vertex c' = rotate a towards c by the arc length b', using the
    // orthonormal frame {a, GramSchmidt(c, a)} of the great circle through a, c.
    let sin_bp = safe_sqrt(1.0 - cos_bp * cos_bp);
    let cp = cos_bp * a + sin_bp * sph_safe_normalize(sph_gram_schmidt(c, a));

    // Arvo step 2: sample the great arc from b to c'. Uniform area inside the
    // sub-triangle means the point's angular distance theta from b has density
    // proportional to sin(theta), i.e. cos(theta) is uniform in [b . c', 1]:
    //     cos(theta) = 1 - u1 (1 - c' . b).
    // 1 - cos(theta) = u1 (1 - c' . b), with 1 - c' . b = |c' - b|^2 / 2 and
    // sin^2(theta) = v (2 - v): no cancellation when the arc is short.
    let cb = cp - b;
    let v = u.y * 0.5 * dot(cb, cb);
    let cos_theta = 1.0 - v;
    let sin_theta = safe_sqrt(v * (2.0 - v));
    let w = cos_theta * b + sin_theta * sph_safe_normalize(sph_gram_schmidt(cp, b));

    // pbrt returns w un-renormalised (it goes on to barycentrics); we return
    // the direction itself, so renormalise away the f32 drift.
    return normalize(w);
}
