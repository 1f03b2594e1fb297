// quadrics/bspline_curve.wgsl — one segment of Mitsuba's bsplinecurve (src/shapes/bsplinecurve.cpp;
// the host's is src/scene/quadrics/bspline_curve.rs): the circles of radius r(v) in the planes
// normal to a uniform cubic B-spline c(v), v in [0, 1], r a cubic B-spline too; open ends, back
// faces culled. Its record (a Quadric, src/gpu/scene_buffers.rs): object_x, object_y, object_z,
// world_x its four control points (xyz) and radii (w); world_y = (segment number, the shape's
// segment count, the margin by which the chain of swept spheres along its chords is widened
// to hold it).

// The searches below run as loops, or, where the host sets this (`PipelineKey::bspline_unrolled`:
// scenes whose looped searches would pass llvmpipe's loop budget), as the unrolled code
// generated after this file (`bspline_chain_unrolled`, `bspline_newton_unrolled`).
override BSPLINE_UNROLLED: bool = false;

// The centre line and radius at v, with their derivatives.
struct BsplinePoint {
    c: vec3f,
    dc: vec3f,
    ddc: vec3f,
    r: f32,
    dr: f32,
}

// Segment q's centre line and radius at v: the uniform cubic B-spline basis and its
// derivatives applied to the control points and radii together.
fn bspline_at(q: Quadric, v: f32) -> BsplinePoint {
    let w = 1.0 - v;
    let v2 = v * v;
    let v3 = v2 * v;
    let b = vec4f(w * w * w, 3.0 * v3 - 6.0 * v2 + 4.0, -3.0 * v3 + 3.0 * v2 + 3.0 * v + 1.0, v3) / 6.0;
    let db = vec4f(-w * w, 3.0 * v2 - 4.0 * v, -3.0 * v2 + 2.0 * v + 1.0, v2) * 0.5;
    let ddb = vec4f(w, 3.0 * v - 2.0, 1.0 - 3.0 * v, v);
    let c = q.object_x * b.x + q.object_y * b.y + q.object_z * b.z + q.world_x * b.w;
    let dc = q.object_x * db.x + q.object_y * db.y + q.object_z * db.z + q.world_x * db.w;
    let ddc = q.object_x * ddb.x + q.object_y * ddb.y + q.object_z * ddb.z + q.world_x * ddb.w;
    return BsplinePoint(c.xyz, dc.xyz, ddc.xyz, c.w, dc.w);
}

// Mitsuba's normal at point p of the circle of b: (|c'|^2 - (p - c) . c'') (p - c) - r r' c',
// the gradient of the surface's two equations.
fn bspline_normal_at(b: BsplinePoint, p: vec3f) -> vec3f {
    let q = p - b.c;
    return normalize((dot(b.dc, b.dc) - dot(q, b.ddc)) * q - b.r * b.dr * b.dc);
}

// One Newton step on (p - c(v)) . c'(v) = 0 and |p - c(v)|^2 = r(v)^2, p = o + t d, from
// s = (t, v) (v kept within [-1, 2]).
fn bspline_newton_step(q: Quadric, o: vec3f, d: vec3f, s: vec2f) -> vec2f {
    let b = bspline_at(q, s.y);
    let r = o + s.x * d - b.c;
    let f1 = dot(r, b.dc);
    let f2 = dot(r, r) - b.r * b.r;
    let j00 = dot(d, b.dc);
    let j01 = dot(r, b.ddc) - dot(b.dc, b.dc);
    let j10 = 2.0 * dot(r, d);
    let j11 = -2.0 * (dot(r, b.dc) + b.r * b.dr);
    let det = j00 * j11 - j01 * j10;
    let inv = select(0.0, 1.0 / det, det != 0.0);
    return vec2f(s.x - (f1 * j11 - f2 * j01) * inv, clamp(s.y - (j00 * f2 - j10 * f1) * inv, -1.0, 2.0));
}

// BSPLINE_NEWTON_STEPS Newton steps from `start`.
fn bspline_newton(q: Quadric, o: vec3f, d: vec3f, start: vec2f) -> vec2f {
    if (BSPLINE_UNROLLED) {
        return bspline_newton_unrolled(q, o, d, start);
    }
    var s = start;
    for (var k = 0u; k < BSPLINE_NEWTON_STEPS; k++) {
        s = bspline_newton_step(q, o, d, s);
    }
    return s;
}

// Newton's method from `start`: (t, v) where it converged (the point within 2e-4 of the radius
// of its circle, in its plane) to a hit facing the ray with v in [0, 1] (give or take
// BSPLINE_V_SLACK: at a joint both segments' solutions count) and t in (t_min, t_max); else
// t = -1.
fn bspline_solve(q: Quadric, o: vec3f, d: vec3f, start: vec2f, t_min: f32, t_max: f32) -> vec2f {
    let s = bspline_newton(q, o, d, start);
    let t = s.x;
    let v = s.y;
    let b = bspline_at(q, v);
    let p = o + t * d;
    let r = p - b.c;
    let tolerance = 2e-4 * b.r + 4e-6 * max(max3(abs(p)), 1.0);
    let converged = abs(length(r) - b.r) <= tolerance && abs(dot(r, normalize(b.dc))) <= tolerance;
    let valid = converged && v >= -BSPLINE_V_SLACK && v <= 1.0 + BSPLINE_V_SLACK && t > t_min && t < t_max && dot(bspline_normal_at(b, p), d) < 0.0;
    return vec2f(select(-1.0, t, valid), v);
}

// The search for a segment's hit along a ray: the chain's point reached so far, and the two
// nearest entries (t, v) found (t INFINITY: none).
struct BsplineChain {
    a: BsplinePoint,
    nearest: vec2f,
    second: vec2f,
}

// The chain's piece ending at chord point i (of BSPLINE_PIECES) added to the search: the swept
// sphere from the previous point to c(i / BSPLINE_PIECES), radii widened by `margin`, and its
// entry kept where it is among the two nearest.
fn bspline_chain_piece(q: Quadric, o: vec3f, d: vec3f, t_min: f32, t_max: f32, margin: f32, chain: BsplineChain, i: u32) -> BsplineChain {
    let a = chain.a;
    let b = bspline_at(q, f32(i) / f32(BSPLINE_PIECES));
    let ra = max(a.r, 0.0) + margin;
    let rb = max(b.r, 0.0) + margin;
    let t = round_cone_entry(a.c, ra, b.c, rb, o, d, t_min, t_max, true);
    let candidate = vec2f(t, (f32(i - 1u) + round_cone_v(a.c, ra, b.c, rb, o + min(t, t_max) * d)) / f32(BSPLINE_PIECES));
    let first = t < chain.nearest.x;
    let second = select(select(chain.second, candidate, t < chain.second.x), chain.nearest, first);
    return BsplineChain(b, select(chain.nearest, candidate, first), second);
}

// The search over every piece of segment q's chain.
fn bspline_chain(q: Quadric, o: vec3f, d: vec3f, t_min: f32, t_max: f32, margin: f32) -> BsplineChain {
    if (BSPLINE_UNROLLED) {
        return bspline_chain_unrolled(q, o, d, t_min, t_max, margin);
    }
    var chain = BsplineChain(bspline_at(q, 0.0), vec2f(INFINITY, 0.0), vec2f(INFINITY, 0.0));
    for (var i = 1u; i <= BSPLINE_PIECES; i++) {
        chain = bspline_chain_piece(q, o, d, t_min, t_max, margin, chain, i);
    }
    return chain;
}

// Whether the ray o + t d, t in [0, t_max], meets the bounds of segment q: the box of its four
// control points widened by its largest radius, which holds the tube (a uniform B-spline's
// point is a convex combination of its control points, its radius one of theirs), and by
// 1e-4 of its size and the margin more (a hit's v may pass [0, 1] by BSPLINE_V_SLACK).
fn bspline_bounds_met(q: Quadric, o: vec3f, d: vec3f, t_max: f32) -> bool {
    let lo = min(min(q.object_x.xyz, q.object_y.xyz), min(q.object_z.xyz, q.world_x.xyz));
    let hi = max(max(q.object_x.xyz, q.object_y.xyz), max(q.object_z.xyz, q.world_x.xyz));
    let r = max(max(q.object_x.w, q.object_y.w), max(q.object_z.w, q.world_x.w));
    return ray_meets_box(lo, hi, r + q.world_y.z + 1e-4 * (max3(hi - lo) + r), o, d, t_max);
}

// (t, v) where the ray o + t d enters segment q, t in (t_min, t_max), or t = -1. Candidates
// are the entries into a chain of BSPLINE_PIECES swept spheres along the centre line's chords,
// widened by the record's margin (the tube lies inside them); Newton's method runs from the
// two nearest (a ray grazing one bend of the segment may meet another).
fn intersect_bspline_curve(q: Quadric, o: vec3f, d: vec3f, t_min: f32, t_max: f32) -> vec2f {
    let chain = bspline_chain(q, o, d, t_min, t_max, q.world_y.z);
    var hit = vec2f(-1.0, 0.0);
    if (chain.nearest.x < INFINITY) {
        hit = bspline_solve(q, o, d, chain.nearest, t_min, t_max);
    }
    if (chain.second.x < INFINITY) {
        let other = bspline_solve(q, o, d, chain.second, t_min, t_max);
        hit = select(hit, other, other.x > 0.0 && (hit.x < 0.0 || other.x < hit.x));
    }
    return hit;
}

// Mitsuba's normal at point p of segment q on the circle of v.
fn bspline_curve_normal(q: Quadric, p: vec3f, v: f32) -> vec3f {
    return bspline_normal_at(bspline_at(q, v), p);
}

// Mitsuba's uv at point p of segment q on the circle of v: u the angle around the unit tangent
// a from u_rad towards u_rot (u_rot the world's +z made orthogonal to a, (0, 1, 0) where a is
// exactly +-z; u_rad = u_rot x a: the host's angle_frame), / 2 pi in [0, 1); v plus the
// segment's number, over the shape's count.
fn bspline_curve_uv(q: Quadric, p: vec3f, v: f32) -> vec2f {
    let b = bspline_at(q, v);
    let a = normalize(b.dc);
    let u_rot = select(normalize(vec3f(0.0, 0.0, 1.0) - a * a.z), vec3f(0.0, 1.0, 0.0), abs(a.z) == 1.0);
    let u_rad = cross(u_rot, a);
    let n = normalize(p - b.c);
    var u = atan2(dot(u_rot, n), dot(u_rad, n)) * INV_2PI;
    u = select(u, u + 1.0, u < 0.0);
    return vec2f(u, (v + q.world_y.x) / q.world_y.y);
}

// dp/du = 2 pi r (T x n) at point p of segment q on the circle of v (Mitsuba's partials: T the
// unit tangent, n the unit radius vector).
fn bspline_curve_tangent(q: Quadric, p: vec3f, v: f32) -> vec3f {
    let b = bspline_at(q, v);
    return 2.0 * PI * b.r * cross(normalize(b.dc), normalize(p - b.c));
}
