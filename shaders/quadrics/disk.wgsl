// quadrics/disk.wgsl — Mitsuba's disk (src/shapes/disk.cpp; the host's is
// src/scene/quadrics/disk.rs): the unit disk x^2 + y^2 <= 1 at z = 0 of its object space, its
// normal +z (Quadric.normal in world space).

// t of the ray's crossing of disk q in (t_min, t_max), or -1: the crossing of z = 0 in object
// space (t is the same in both spaces: the ray's direction is mapped unnormalised), within the
// unit circle. A ray parallel to the disk divides by zero and fails the range test.
fn intersect_disk(q: Quadric, o: vec3f, d: vec3f, t_min: f32, t_max: f32) -> f32 {
    let ol = quadric_point_to_object(q, o);
    let dl = quadric_vector_to_object(q, d);
    let t = -ol.z / dl.z;
    let l = ol.xy + dl.xy * t;
    return select(-1.0, t, (t > t_min) & (t < t_max) & (dot(l, l) <= 1.0));
}

// Mitsuba's uv of the disk at world point p: (r, phi / 2 pi) of its object-space polar
// coordinates, phi in [0, 2 pi).
fn disk_uv(q: Quadric, p: vec3f) -> vec2f {
    let l = quadric_point_to_object(q, p);
    var v = atan2(l.y, l.x) * INV_2PI;
    v = select(v, v + 1.0, v < 0.0);
    return vec2f(length(l.xy), v);
}

// The direction of dp/du of disk q at world point p of it (Mitsuba's disk.cpp: to_world (cos phi,
// sin phi, 0), away from the centre); 0 at the centre.
fn disk_tangent(q: Quadric, p: vec3f) -> vec3f {
    let l = quadric_point_to_object(q, p);
    return quadric_vector_to_world(q, vec3f(l.x, l.y, 0.0));
}

// A direction from x towards a point uniform in the area of disk q, with its solid-angle
// density (Mitsuba's Disk::sample_position, converted at x).
fn sample_disk_light(q: Quadric, x: vec3f, u: vec2f) -> LightSample {
    let to_p = sample_disk_point(q, u) - x;
    let dist = length(to_p);
    let wi = to_p / dist;
    return LightSample(wi, dist, pdf_area_point(q.area, q.normal, dist, wi));
}

// Solid-angle density with which sample_disk_light gives wi from x: the area density at the
// point where the ray (x, wi) meets the disk, converted to solid angle (0 where it misses).
fn pdf_disk_light(q: Quadric, x: vec3f, wi: vec3f) -> f32 {
    let t = intersect_disk(q, x, wi, 0.0, INFINITY);
    return select(0.0, pdf_area_point(q.area, q.normal, t, wi), t > 0.0);
}

// A point uniform in the area of disk q (Mitsuba's Disk::sample_position: the concentric map,
// warp.wgsl).
fn sample_disk_point(q: Quadric, u: vec2f) -> vec3f {
    return quadric_point_to_world(q, vec3f(square_to_uniform_disk_concentric(u), 0.0));
}
