// intersect.wgsl — ray/sphere and ray/plane intersection, the quadrics' (quadrics/), the
// triangles through the BVH (bvh.wgsl), closest hit and shadow queries.

struct Hit {
    t: f32,
    // Geometric normal: outward for spheres, the plane's normal for planes, the quadric's
    // (flip_normals applied), the winding normal cross(p1 - p0, p2 - p0) for triangles.
    normal: vec3f,
    material: u32,
    // Sphere index, NUM_SPHERES + plane index, first_quadric_object() + quadric index, or
    // first_triangle_object() + triangle index; INVALID on a miss.
    object: u32,
    // The interpolated vertex normal of a triangle with normals, else the geometric normal.
    shading_normal: vec3f,
    // The uv parametrisation at the hit (sphere_uv, plane_uv, triangle_uv), where HAS_UVS;
    // else 0.
    uv: vec2f,
    // The direction of dp/du there (sphere_tangent, plane_tangent, quadric_tangent,
    // triangle_tangent; not normalised, 0 where the parametrisation is singular), where
    // HAS_TANGENT_FRAMES; else 0.
    tangent: vec3f,
    // A bound on the error of the hit point o + t d and of later tests against its surface,
    // where it exceeds what offset_ray_origin allows for by the point's own magnitude: on a
    // triangle gamma(7) times its largest vertex coordinate (the sheared test's t errs by the
    // vertices' magnitude, as pbrt-v4's bounds say), so that rays leaving a triangle whose
    // vertices are far larger than the point (a floor 2000 wide) do not find it again; 0
    // elsewhere.
    p_error: f32,
    // The barycentrics (of p1 and p2) of a triangle hit, for mesh attributes; else 0.
    bary: vec2f,
}

// Where the textures of the surface hit are looked up, at its point p (texture.wgsl).
fn texture_context(hit: Hit, p: vec3f) -> TextureEvalContext {
    let on_triangle = hit.object != INVALID && hit.object >= first_triangle_object();
    return TextureEvalContext(hit.uv, p, select(INVALID, hit.object - first_triangle_object(), on_triangle), hit.bary);
}

// The first object index of the quadrics (disks, then cylinders, then linear curves' segments,
// then B-spline segments, then SDF grids).
fn first_quadric_object() -> u32 {
    return NUM_SPHERES + NUM_PLANES;
}

// The first object index of the triangles.
fn first_triangle_object() -> u32 {
    return NUM_SPHERES + NUM_PLANES + num_quadrics();
}

// The number of quadrics.
fn num_quadrics() -> u32 {
    return first_sdf_grid() + NUM_SDF_GRIDS;
}

// The quadric index of the first B-spline segment (after the linear curves' segments).
fn first_bspline_segment() -> u32 {
    return NUM_DISKS + NUM_CYLINDERS + NUM_CURVE_SEGMENTS;
}

// The quadric index of the first SDF grid (after the B-spline segments).
fn first_sdf_grid() -> u32 {
    return first_bspline_segment() + NUM_BSPLINE_SEGMENTS;
}

// The first and last B-spline segments whose bounds the ray (o, d) meets before t_max
// (bspline_bounds_met), first > last where it meets none: a pass over every segment with the
// cheap test (a lane-uniform index, read as broadcasts), so that the search itself, which
// lavapipe cannot skip for lanes that need none, runs over that range alone (a loop's trip
// count is the one cost a SIMD group shortens). Segments outside the range cannot be hit, so
// the nearest hit is the one the search over every segment finds, bit for bit. (Linear curve
// segments are tested in full: their exact test costs little more than the bounds', and the
// linear-curve fixture ran 12% slower with the pass.)
fn bspline_candidates(o: vec3f, d: vec3f, t_max: f32) -> vec2u {
    var first = INVALID;
    var last = 0u;
    for (var k = first_bspline_segment(); k < first_sdf_grid(); k++) {
        let met = bspline_bounds_met(quadric_at(k), o, d, t_max);
        first = select(first, min(first, k), met);
        last = select(last, k, met);
    }
    return vec2u(first, last);
}

// Whether quadric k is a B-spline segment.
fn is_bspline_segment(k: u32) -> bool {
    return NUM_BSPLINE_SEGMENTS > 0u && k >= first_bspline_segment() && k < first_sdf_grid();
}

// Whether an object index (not INVALID) names a quadric.
fn is_quadric(object: u32) -> bool {
    return num_quadrics() > 0u && object >= first_quadric_object() && object < first_triangle_object();
}

// The unit normal of quadric k at world point p of it (v: a B-spline segment's parameter there).
fn quadric_normal(k: u32, q: Quadric, p: vec3f, v: f32) -> vec3f {
    if (k < NUM_DISKS) {
        return q.normal;
    }
    if (NUM_SDF_GRIDS > 0u && k >= first_sdf_grid()) {
        return sdf_grid_normal(q, p);
    }
    if (is_bspline_segment(k)) {
        return bspline_curve_normal(q, p, v);
    }
    if (NUM_CURVE_SEGMENTS > 0u && k >= NUM_DISKS + NUM_CYLINDERS) {
        return linear_curve_normal(q, p);
    }
    return cylinder_normal(q, p);
}

// The uv parametrisation of quadric k at world point p of it (v: as for quadric_normal).
fn quadric_uv(k: u32, q: Quadric, p: vec3f, v: f32) -> vec2f {
    if (k < NUM_DISKS) {
        return disk_uv(q, p);
    }
    if (is_bspline_segment(k)) {
        return bspline_curve_uv(q, p, v);
    }
    if (NUM_SDF_GRIDS > 0u && k >= first_sdf_grid()) {
        // No parametrisation (Mitsuba's uv 0).
        return vec2f(0.0);
    }
    if (NUM_CURVE_SEGMENTS > 0u && k >= NUM_DISKS + NUM_CYLINDERS) {
        return linear_curve_uv(q, p);
    }
    return cylinder_uv(q, p);
}

// The direction of dp/du of quadric k at world point p of it (v: as for quadric_normal).
fn quadric_tangent(k: u32, q: Quadric, p: vec3f, v: f32) -> vec3f {
    if (k < NUM_DISKS) {
        return disk_tangent(q, p);
    }
    if (is_bspline_segment(k)) {
        return bspline_curve_tangent(q, p, v);
    }
    if (NUM_SDF_GRIDS > 0u && k >= first_sdf_grid()) {
        return vec3f(0.0);
    }
    if (NUM_CURVE_SEGMENTS > 0u && k >= NUM_DISKS + NUM_CYLINDERS) {
        return linear_curve_partials(q, p).du;
    }
    return cylinder_tangent(q, p);
}

// Smallest root t of |o + t d - c|^2 = r^2 in (t_min, t_max), or -1.
// Numerically robust form (Haines et al., Ray Tracing Gems ch. 7): the discriminant is taken
// from the squared distance between the centre and the ray, so far-away or tiny spheres keep
// their precision; the second root comes from Vieta's formula (c / q), not a subtraction.
// Written with selects, without early returns: SIMD CPU drivers run every branch anyway, and
// GPUs lose nothing on a test this short.
fn intersect_sphere(o: vec3f, d: vec3f, center: vec3f, radius: f32, t_min: f32, t_max: f32) -> f32 {
    let f = o - center;
    let b = dot(f, d);
    let perp = f - b * d;
    let r2 = radius * radius;
    let disc = r2 - dot(perp, perp);
    let c = dot(f, f) - r2;
    let q = -b - select(-1.0, 1.0, b >= 0.0) * safe_sqrt(disc);
    // The two roots ordered by selects (`ordered_min`, `ordered_max`), not min and max: WGSL's
    // min and max must return the number where one operand is NaN, which lavapipe compiles to
    // a compare and two blends more per sphere. Where c / q is NaN (0 / 0) both forms give q;
    // where q is NaN so is disc, and the ranges below fail either way.
    let cq = c / q;
    let t_near = ordered_min(cq, q);
    let t_far = ordered_max(cq, q);
    let far_ok = (disc >= 0.0) & (t_far > t_min) & (t_far < t_max);
    let near_ok = (disc >= 0.0) & (t_near > t_min) & (t_near < t_max);
    return select(select(-1.0, t_far, far_ok), t_near, near_ok);
}

// t of the ray's crossing of the plane dot(n, x) = offset, or -1 when parallel or out of range.
// A ray parallel to the plane divides by zero: t is +-inf or NaN, and both fail the range test.
fn intersect_plane(o: vec3f, d: vec3f, normal: vec3f, offset: f32, t_min: f32, t_max: f32) -> f32 {
    let t = (offset - dot(normal, o)) / dot(normal, d);
    return select(-1.0, t, (t > t_min) & (t < t_max));
}

// Mitsuba's uv parametrisation of sphere i at the point whose outward unit normal is n: the
// spherical angles of n in the sphere's object axes, u = phi / (2 pi) in [0, 1), v = theta / pi.
fn sphere_uv(i: u32, n: vec3f) -> vec2f {
    let a = sphere_axes[i];
    let l = vec3f(dot(n, a.x), dot(n, a.y), dot(n, a.z));
    var phi = atan2(l.y, l.x);
    phi = select(phi, phi + 2.0 * PI, phi < 0.0);
    return vec2f(phi * INV_2PI, acos(clamp(l.z, -1.0, 1.0)) * INV_PI);
}

// The direction of dp/du of sphere i at the point whose outward unit normal is n (Mitsuba's
// sphere.cpp: to_world 2 pi (-y, x, 0) of the object-space point): around the sphere's z axis; 0
// at its poles.
fn sphere_tangent(i: u32, n: vec3f) -> vec3f {
    let a = sphere_axes[i];
    return a.y * dot(n, a.x) - a.x * dot(n, a.y);
}

// The direction of dp/du of a plane: the first axis of its uv parametrisation (plane_uv).
fn plane_tangent(normal: vec3f) -> vec3f {
    return frame_from_normal(normal).t;
}

// The uv parametrisation of a plane (pathlab's own shape: Mitsuba has no infinite plane): the
// world coordinates of the point along the plane's tangent frame (frame_from_normal).
fn plane_uv(normal: vec3f, x: vec3f) -> vec2f {
    let f = frame_from_normal(normal);
    return vec2f(dot(x, f.t), dot(x, f.b));
}

// dp/du and dp/dv of sphere i at the point whose outward unit normal is n, l = n in its object
// axes (Mitsuba's sphere.cpp: to_world of 2 pi (-l.y, l.x, 0) and of pi (l.z cos phi, l.z sin
// phi, -r_xy), r_xy = sqrt(l.x^2 + l.y^2); to_world scales by the radius; at the poles dp/dv is
// pi to_world (1, 0, 0)).
fn sphere_partials(i: u32, n: vec3f) -> Partials {
    let a = sphere_axes[i];
    let r = sphere_of(i).radius;
    let l = vec3f(dot(n, a.x), dot(n, a.y), dot(n, a.z));
    let rd = sqrt(l.x * l.x + l.y * l.y);
    let dv_l = select(vec3f(1.0, 0.0, 0.0), vec3f(l.z * (l.x / rd), l.z * (l.y / rd), -rd), rd != 0.0);
    let du = (2.0 * PI * r) * (a.y * l.x - a.x * l.y);
    let dv = (PI * r) * (a.x * dv_l.x + a.y * dv_l.y + a.z * dv_l.z);
    return Partials(du, dv);
}

// dp/du and dp/dv of quadric k at world point p of it: a disk's (disk.cpp) to_world (cos phi,
// sin phi, 0) and 2 pi r to_world (-sin phi, cos phi, 0) (both of (0, 0, 0)'s direction at the
// centre); a cylinder's (cylinder.cpp) to_world 2 pi (-l.y, l.x, 0) and to_world (0, 0, 1).
fn quadric_partials(k: u32, q: Quadric, p: vec3f) -> Partials {
    if ((NUM_SDF_GRIDS > 0u && k >= first_sdf_grid()) || is_bspline_segment(k)) {
        // None kept (validation refuses bump maps on SDF grids and B-spline curves).
        return Partials(vec3f(0.0), vec3f(0.0));
    }
    if (NUM_CURVE_SEGMENTS > 0u && k >= NUM_DISKS + NUM_CYLINDERS) {
        return linear_curve_partials(q, p);
    }
    let l = quadric_point_to_object(q, p);
    if (k < NUM_DISKS) {
        let r2 = dot(l.xy, l.xy);
        let inv_r = select(0.0, inverseSqrt(r2), r2 != 0.0);
        let c = l.xy * inv_r;
        return Partials(quadric_vector_to_world(q, vec3f(c.x, c.y, 0.0)),
                        quadric_vector_to_world(q, vec3f(-c.y, c.x, 0.0)) * (2.0 * PI * (r2 * inv_r)));
    }
    return Partials(quadric_vector_to_world(q, 2.0 * PI * vec3f(-l.y, l.x, 0.0)), quadric_vector_to_world(q, vec3f(0.0, 0.0, 1.0)));
}

// dp/du and dp/dv at a hit at point x (bump maps): the sphere's, the plane's (the axes of its
// uv, plane_uv), the quadric's, or the triangle's (triangle_partials).
fn surface_partials(hit: Hit, x: vec3f) -> Partials {
    if (hit.object < NUM_SPHERES) {
        return sphere_partials(hit.object, hit.normal);
    }
    if (hit.object < NUM_SPHERES + NUM_PLANES) {
        let f = frame_from_normal(hit.normal);
        return Partials(f.t, f.b);
    }
    if (is_quadric(hit.object)) {
        let k = hit.object - first_quadric_object();
        return quadric_partials(k, quadric_of(k), x);
    }
    let i = hit.object - first_triangle_object();
    return triangle_partials(i, triangle_record(i), hit.normal);
}

// Closest hit along (o, d). The candidate's normal data and material are carried along by
// selects as closer hits are found, rather than looked up afterwards at the hit's index,
// which differs per lane (a gather on SIMD CPU drivers and a serialised constant-cache read on
// GPUs, where these loops only read at lane-uniform indices).
fn intersect_scene(o: vec3f, d: vec3f) -> Hit {
    rays_traced += 1u;
    var t_hit = INFINITY;
    var object = INVALID;
    var material = 0u;
    // Of the closest sphere so far: centre and radius; of the closest plane: its normal.
    var center = vec3f(0.0);
    var radius = 1.0;
    var plane_normal = vec3f(0.0);
    for (var i = 0u; i < NUM_SPHERES; i++) {
        let s = sphere_at(i);
        let t = intersect_sphere(o, d, s.center, s.radius, 0.0, t_hit);
        let closer = t > 0.0;
        t_hit = select(t_hit, t, closer);
        object = select(object, i, closer);
        material = select(material, s.material, closer);
        center = select(center, s.center, closer);
        radius = select(radius, s.radius, closer);
    }
    for (var j = 0u; j < NUM_PLANES; j++) {
        let p = plane_at(j);
        let t = intersect_plane(o, d, p.normal, p.offset, 0.0, t_hit);
        let closer = t > 0.0;
        t_hit = select(t_hit, t, closer);
        object = select(object, NUM_SPHERES + j, closer);
        material = select(material, p.material, closer);
        plane_normal = select(plane_normal, p.normal, closer);
    }
    let sphere_normal = (o + d * t_hit - center) / radius;
    let normal = select(plane_normal, sphere_normal, object < NUM_SPHERES);
    var uv = vec2f(0.0);
    if (HAS_UVS && object != INVALID) {
        uv = select(plane_uv(plane_normal, o + d * t_hit), sphere_uv(object, sphere_normal), object < NUM_SPHERES);
    }
    var tangent = vec3f(0.0);
    if (HAS_TANGENT_FRAMES && object != INVALID) {
        tangent = select(plane_tangent(plane_normal), sphere_tangent(object, sphere_normal), object < NUM_SPHERES);
    }
    var hit = Hit(t_hit, normal, material, object, normal, uv, tangent, 0.0, vec2f(0.0));
    if (num_quadrics() > 0u) {
        // Quadrics in loops of their own, as spheres: a lane-uniform index, read as broadcasts.
        // Each kind's loop is inside a test of its count, which the specialiser removes where the
        // count is 0: without it lavapipe ran a kind's test once, masked, where the scene had
        // none (an SDF grid's walk cost the quadrics fixture a third of its speed).
        var quadric = INVALID;
        if (NUM_DISKS > 0u) {
            for (var k = 0u; k < NUM_DISKS; k++) {
                let t = intersect_disk(quadric_at(k), o, d, 0.0, hit.t);
                let closer = t > 0.0;
                hit.t = select(hit.t, t, closer);
                quadric = select(quadric, k, closer);
            }
        }
        if (NUM_CYLINDERS > 0u) {
            for (var k = NUM_DISKS; k < NUM_DISKS + NUM_CYLINDERS; k++) {
                let t = intersect_cylinder(quadric_at(k), o, d, 0.0, hit.t);
                let closer = t > 0.0;
                hit.t = select(hit.t, t, closer);
                quadric = select(quadric, k, closer);
            }
        }
        if (NUM_CURVE_SEGMENTS > 0u) {
            for (var k = NUM_DISKS + NUM_CYLINDERS; k < first_bspline_segment(); k++) {
                let t = intersect_linear_curve(quadric_at(k), o, d, 0.0, hit.t);
                let closer = t > 0.0;
                hit.t = select(hit.t, t, closer);
                quadric = select(quadric, k, closer);
            }
        }
        // A B-spline segment's hit comes with its parameter v (Mitsuba's prim_uv).
        var curve_v = 0.0;
        if (NUM_BSPLINE_SEGMENTS > 0u) {
            let range = bspline_candidates(o, d, hit.t);
            for (var k = range.x; k <= range.y; k++) {
                let h = intersect_bspline_curve(quadric_at(k), o, d, 0.0, hit.t);
                let closer = h.x > 0.0;
                hit.t = select(hit.t, h.x, closer);
                quadric = select(quadric, k, closer);
                curve_v = select(curve_v, h.y, closer);
            }
        }
        if (NUM_SDF_GRIDS > 0u) {
            for (var k = first_sdf_grid(); k < num_quadrics(); k++) {
                let t = intersect_sdf_grid(quadric_at(k), o, d, hit.t);
                let closer = t > 0.0;
                hit.t = select(hit.t, t, closer);
                quadric = select(quadric, k, closer);
            }
        }
        if (quadric != INVALID) {
            let q = quadric_of(quadric);
            let x = o + d * hit.t;
            let n = quadric_normal(quadric, q, x, curve_v);
            var q_uv = vec2f(0.0);
            if (HAS_UVS) {
                q_uv = quadric_uv(quadric, q, x, curve_v);
            }
            var q_tangent = vec3f(0.0);
            if (HAS_TANGENT_FRAMES) {
                q_tangent = quadric_tangent(quadric, q, x, curve_v);
            }
            var shading_normal = n;
            if (NUM_SDF_GRIDS > 0u && quadric >= first_sdf_grid()) {
                shading_normal = sdf_grid_shading_normal(q, x, n);
            }
            hit = Hit(hit.t, n, q.material, first_quadric_object() + quadric, shading_normal, q_uv, q_tangent, 0.0, vec2f(0.0));
        }
    }
    if (NUM_TRIANGLES > 0u) {
        let th = triangles_closest(o, d, hit.t);
        if (th.index != INVALID) {
            let tri = triangle_record(th.index);
            let n = normalize(cross(tri.p1 - tri.p0, tri.p2 - tri.p0));
            let shading_normal = triangle_shading_normal(th.index, tri, n, th.bary);
            var tri_uv = vec2f(0.0);
            if (HAS_UVS) {
                tri_uv = triangle_uv(th.index, tri, th.bary);
            }
            var tri_tangent = vec3f(0.0);
            if (HAS_TANGENT_FRAMES) {
                tri_tangent = triangle_tangent(th.index, tri, n);
            }
            let p_error = GAMMA_7 * max(max3(abs(tri.p0)), max(max3(abs(tri.p1)), max3(abs(tri.p2))));
            hit = Hit(th.t, n, tri.material, first_triangle_object() + th.index, shading_normal, tri_uv, tri_tangent, p_error, th.bary);
        }
    }
    return hit;
}

// True when something other than sphere `skip` lies on the segment (o, o + t_max d), a
// shadow ray towards a light: planes that cannot separate a path vertex from a light are not
// tested.
fn occluded(o: vec3f, d: vec3f, t_max: f32, skip: u32) -> bool {
    rays_traced += 1u;
    var blocked = false;
    for (var i = 0u; i < NUM_SPHERES; i++) {
        let s = sphere_at(i);
        let t = intersect_sphere(o, d, s.center, s.radius, 0.0, t_max);
        blocked = blocked | ((t > 0.0) & (i != skip));
    }
    for (var j = 0u; j < NUM_OCCLUDING_PLANES; j++) {
        let p = plane_at(j);
        blocked = blocked | (intersect_plane(o, d, p.normal, p.offset, 0.0, t_max) > 0.0);
    }
    if (NUM_DISKS > 0u) {
        for (var k = 0u; k < NUM_DISKS; k++) {
            blocked = blocked | (intersect_disk(quadric_at(k), o, d, 0.0, t_max) > 0.0);
        }
    }
    if (NUM_CYLINDERS > 0u) {
        for (var k = NUM_DISKS; k < NUM_DISKS + NUM_CYLINDERS; k++) {
            blocked = blocked | (intersect_cylinder(quadric_at(k), o, d, 0.0, t_max) > 0.0);
        }
    }
    if (NUM_CURVE_SEGMENTS > 0u) {
        for (var k = NUM_DISKS + NUM_CYLINDERS; k < first_bspline_segment(); k++) {
            blocked = blocked | (intersect_linear_curve(quadric_at(k), o, d, 0.0, t_max) > 0.0);
        }
    }
    if (NUM_BSPLINE_SEGMENTS > 0u) {
        let range = bspline_candidates(o, d, t_max);
        for (var k = range.x; k <= range.y; k++) {
            blocked = blocked | (intersect_bspline_curve(quadric_at(k), o, d, 0.0, t_max).x > 0.0);
        }
    }
    if (NUM_SDF_GRIDS > 0u) {
        for (var k = first_sdf_grid(); k < num_quadrics(); k++) {
            blocked = blocked | (intersect_sdf_grid(quadric_at(k), o, d, t_max) > 0.0);
        }
    }
    if (NUM_TRIANGLES > 0u && !blocked) {
        blocked = triangles_any(o, d, t_max).index != INVALID;
    }
    return blocked;
}

// gamma(7) = 7 u / (1 - 7 u), u = 2^-24 the f32 unit roundoff (pbrt-v4's error bounds).
const GAMMA_7: f32 = 4.1723e-7;

// Origin for a ray leaving surface point p on the side of unit normal n_side: offset by a
// distance proportional to the point's magnitude, above the f32 error of p and of the hit,
// or by four times p_error (Hit.p_error) where that is more: the error of a triangle's hit
// and of later tests against it grow with its vertices' magnitude, not the point's.
fn offset_ray_origin(p: vec3f, n_side: vec3f, p_error: f32) -> vec3f {
    let scale = max(max3(abs(p)), 1.0);
    return p + n_side * max(scale * 2e-5, 4.0 * p_error);
}
