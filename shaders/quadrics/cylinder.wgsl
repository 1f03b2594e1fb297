// quadrics/cylinder.wgsl — Mitsuba's cylinder (src/shapes/cylinder.cpp; the host's is
// src/scene/quadrics/cylinder.rs): the open unit cylinder x^2 + y^2 = 1, 0 <= z <= 1, of its
// object space, without end caps, its normals outwards (flip_normals: inwards).

// t where the ray meets cylinder q in (t_min, t_max), or -1: the nearer root of
// |ol.xy + t dl.xy|^2 = 1 whose point lies between z = 0 and z = 1, else the farther one
// (Mitsuba's test). The roots of a t^2 + 2 h t + c = 0 in the stable form: the discriminant
// h^2 - a c equals a - (dl.xy x ol.xy)^2 (Lagrange's identity), free of the cancellation of
// h^2 - a c for far-away rays; the second root comes from Vieta's formula (c / q).
fn intersect_cylinder(q: Quadric, o: vec3f, d: vec3f, t_min: f32, t_max: f32) -> f32 {
    let ol = quadric_point_to_object(q, o);
    let dl = quadric_vector_to_object(q, d);
    let a = dot(dl.xy, dl.xy);
    let h = dot(dl.xy, ol.xy);
    let c = dot(ol.xy, ol.xy) - 1.0;
    let cross_z = dl.x * ol.y - dl.y * ol.x;
    let disc = a - cross_z * cross_z;
    let root = -h - select(-1.0, 1.0, h >= 0.0) * safe_sqrt(disc);
    let t_near = min(root / a, c / root);
    let t_far = max(root / a, c / root);
    let z_near = ol.z + dl.z * t_near;
    let z_far = ol.z + dl.z * t_far;
    let near_ok = (disc >= 0.0) & (t_near > t_min) & (t_near < t_max) & (z_near >= 0.0) & (z_near <= 1.0);
    let far_ok = (disc >= 0.0) & (t_far > t_min) & (t_far < t_max) & (z_far >= 0.0) & (z_far <= 1.0);
    return select(select(-1.0, t_far, far_ok), t_near, near_ok);
}

// The cylinder's unit normal at world point p: the object-space normal (x, y, 0) at its
// object-space point l mapped by the inverse transpose, A^T (x, y, 0) with A the world-to-object
// rows, turned by flip_normals.
fn cylinder_normal(q: Quadric, p: vec3f) -> vec3f {
    return cylinder_normal_local(q, quadric_point_to_object(q, p));
}

fn cylinder_normal_local(q: Quadric, l: vec3f) -> vec3f {
    return q.normal_sign * normalize(l.x * q.object_x.xyz + l.y * q.object_y.xyz);
}

// A direction from x towards a point uniform in the area of cylinder q (Mitsuba's
// Cylinder::sample_position: (cos 2 pi u1, sin 2 pi u1, u0) in object space), with its
// solid-angle density, and the unit normal there.
fn sample_cylinder_light(q: Quadric, x: vec3f, u: vec2f) -> CylinderLightSample {
    let phi = 2.0 * PI * u.y;
    let local = vec3f(cos(phi), sin(phi), u.x);
    let to_p = quadric_point_to_world(q, local) - x;
    let n = cylinder_normal_local(q, local);
    let dist = length(to_p);
    let wi = to_p / dist;
    return CylinderLightSample(LightSample(wi, dist, pdf_area_point(q.area, n, dist, wi)), n);
}

struct CylinderLightSample {
    ls: LightSample,
    n: vec3f,
}

// Solid-angle density with which sample_cylinder_light gives wi from x, for the first point
// beyond t_min where the ray (x, wi) meets the cylinder (the point light sampling must have
// drawn for the direction to carry light): its area density converted to solid angle, 0 where
// the ray misses. t_min > 0 skips the root at x where x lies on the cylinder itself.
fn pdf_cylinder_light(q: Quadric, x: vec3f, wi: vec3f, t_min: f32) -> f32 {
    let t = intersect_cylinder(q, x, wi, t_min, INFINITY);
    let n = cylinder_normal(q, x + wi * t);
    return select(0.0, pdf_area_point(q.area, n, t, wi), t > 0.0);
}

// Mitsuba's uv of the cylinder at world point p: (phi / 2 pi, z), phi in [0, 2 pi).
fn cylinder_uv(q: Quadric, p: vec3f) -> vec2f {
    let l = quadric_point_to_object(q, p);
    var u = atan2(l.y, l.x) * INV_2PI;
    u = select(u, u + 1.0, u < 0.0);
    return vec2f(u, l.z);
}

// The direction of dp/du of cylinder q at world point p of it (Mitsuba's cylinder.cpp:
// to_world 2 pi (-y, x, 0), around the axis).
fn cylinder_tangent(q: Quadric, p: vec3f) -> vec3f {
    let l = quadric_point_to_object(q, p);
    return quadric_vector_to_world(q, vec3f(-l.y, l.x, 0.0));
}
