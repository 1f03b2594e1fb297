// quadrics/linear_curve.wgsl — one segment of Mitsuba's linearcurve (src/shapes/linearcurve.cpp;
// the host's is src/scene/quadrics/linear_curve.rs): the sphere swept from (p0, r0) to (p1, r1),
// the convex hull of its two end spheres (Embree's round linear curve, which Mitsuba renders
// through). Its record (a Quadric, src/gpu/scene_buffers.rs): object_x = (p0, r0), object_y =
// (p1, r1), object_z = (u_rot, segment number), world_x = (u_rad, the shape's segment count),
// world_y = (unit axis, 1 where it starts its curve). Back faces are culled: a ray meets it only
// where it enters it. A segment that does not start its curve has no start sphere (Embree's
// neighbour rule): the previous segment's end sphere is the joint, so a joint's hit, and its
// uv, are the previous segment's whatever the rounding of each segment's arithmetic.

// t where the ray o + t d enters segment q, in (t_min, t_max), or -1 (Quilez's rounded-cone
// intersection): the entry into the cone tangent to both end spheres, where its contact sphere
// lies between them (0 < y < d2, y / d2 the contact's parameter), else the nearer entry into an
// end sphere (an entry on the start sphere only where the segment starts its curve). The exits
// are back faces. The line's entry is found from its point nearest the
// segment's middle, t_shift along it: the quadratics' coefficients then hold distances of the
// segment's size, not of the ray's origin, and lose little to cancellation in f32 (1e-4 of t
// from an origin 30 radii away, without).
fn intersect_linear_curve(q: Quadric, o_ray: vec3f, d: vec3f, t_min: f32, t_max: f32) -> f32 {
    let t = round_cone_entry(q.object_x.xyz, q.object_x.w, q.object_y.xyz, q.object_y.w, o_ray, d, t_min, t_max, q.world_y.w > 0.0);
    return select(-1.0, t, t < INFINITY);
}

// t where the ray o + t d enters the sphere swept from (pa, ra) to (pb, rb), in (t_min, t_max),
// or INFINITY: the entry into the tangent cone where its contact lies between the spheres, else
// the nearer entry into an end sphere (the start sphere's only where `own_start`).
fn round_cone_entry(pa: vec3f, ra: f32, pb: vec3f, rb: f32, o_ray: vec3f, d: vec3f, t_min: f32, t_max: f32, own_start: bool) -> f32 {
    let t_shift = dot(0.5 * (pa + pb) - o_ray, d) / dot(d, d);
    let o = o_ray + t_shift * d;
    let ba = pb - pa;
    let oa = o - pa;
    let ob = o - pb;
    let rr = ra - rb;
    let m0 = dot(ba, ba);
    let m1 = dot(ba, oa);
    let m2 = dot(ba, d);
    let m3 = dot(d, oa);
    let m4 = dot(d, d);
    let m5 = dot(oa, oa);
    let m6 = dot(ob, d);
    let m7 = dot(ob, ob);
    // The tangent cone: k2 t^2 + 2 k1 t + k0 = 0.
    let d2 = m0 - rr * rr;
    let k2 = d2 * m4 - m2 * m2;
    let k1 = d2 * m3 - m1 * m2 + m2 * rr * ra;
    let k0 = d2 * m5 - m1 * m1 + 2.0 * m1 * rr * ra - m0 * ra * ra;
    let h = k1 * k1 - k0 * k2;
    let t_cone = (-sqrt(max(h, 0.0)) - k1) / k2;
    let y = m1 - ra * rr + t_cone * m2;
    // The end spheres.
    let h0 = m3 * m3 - m4 * (m5 - ra * ra);
    let h1 = m6 * m6 - m4 * (m7 - rb * rb);
    let t0 = select(INFINITY, (-m3 - sqrt(max(h0, 0.0))) / m4, h0 > 0.0);
    let t1 = select(INFINITY, (-m6 - sqrt(max(h1, 0.0))) / m4, h1 > 0.0);
    let on_cone = y > 0.0 && y < d2;
    let entry = t_shift + select(min(t0, t1), t_cone, on_cone);
    let own = own_start || on_cone || t1 <= t0;
    return select(INFINITY, entry, h >= 0.0 && own && entry > t_min && entry < t_max);
}

// The contact sphere's parameter at point p of segment q, in [0, 1]: ((p - p0) . d + r0 (r1 -
// r0)) / (|d|^2 - (r1 - r0)^2) on the cone, clamped to an end sphere.
fn linear_curve_v_local(q: Quadric, p: vec3f) -> f32 {
    return round_cone_v(q.object_x.xyz, q.object_x.w, q.object_y.xyz, q.object_y.w, p);
}

// The contact sphere's parameter at point p of the sphere swept from (pa, ra) to (pb, rb).
fn round_cone_v(pa: vec3f, ra: f32, pb: vec3f, rb: f32, p: vec3f) -> f32 {
    let d = pb - pa;
    let dr = rb - ra;
    return clamp((dot(p - pa, d) + ra * dr) / (dot(d, d) - dr * dr), 0.0, 1.0);
}

// The contact sphere's centre at point p of segment q.
fn linear_curve_centre(q: Quadric, p: vec3f) -> vec3f {
    return mix(q.object_x.xyz, q.object_y.xyz, linear_curve_v_local(q, p));
}

// Mitsuba's normal: from the contact sphere's centre to p.
fn linear_curve_normal(q: Quadric, p: vec3f) -> vec3f {
    return normalize(p - linear_curve_centre(q, p));
}

// Mitsuba's uv: u the angle around the segment's axis from u_rad towards u_rot, / 2 pi in
// [0, 1); v the contact's parameter plus the segment's number, over the shape's count.
fn linear_curve_uv(q: Quadric, p: vec3f) -> vec2f {
    let n = linear_curve_normal(q, p);
    var u = atan2(dot(q.object_z.xyz, n), dot(q.world_x.xyz, n)) * INV_2PI;
    u = select(u, u + 1.0, u < 0.0);
    return vec2f(u, (linear_curve_v_local(q, p) + q.object_z.w) / q.world_x.w);
}

// dp/du = 2 pi axis x (p - c) and dp/dv = count ((p1 - p0) + (r1 - r0) n) (Mitsuba's).
fn linear_curve_partials(q: Quadric, p: vec3f) -> Partials {
    let c = linear_curve_centre(q, p);
    let n = normalize(p - c);
    let du = 2.0 * PI * cross(q.world_y.xyz, p - c);
    let dv = q.world_x.w * ((q.object_y.xyz - q.object_x.xyz) + (q.object_y.w - q.object_x.w) * n);
    return Partials(du, dv);
}
