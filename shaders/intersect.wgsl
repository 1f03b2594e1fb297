// intersect.wgsl — ray/sphere and ray/plane intersection, closest hit and shadow queries.

struct Hit {
    t: f32,
    // Geometric normal, outward for spheres, the plane's normal for planes.
    normal: vec3f,
    material: u32,
    // Sphere index, or NUM_SPHERES + plane index; INVALID on a miss.
    object: u32,
}

// Smallest root t of |o + t d - c|^2 = r^2 in (t_min, t_max), or -1.
// Numerically robust form (Haines et al., Ray Tracing Gems ch. 7): the discriminant is taken
// from the squared distance between the centre and the ray, so far-away or tiny spheres keep
// their precision; the second root comes from Vieta's formula (c / q), not a subtraction.
fn intersect_sphere(o: vec3f, d: vec3f, center: vec3f, radius: f32, t_min: f32, t_max: f32) -> f32 {
    let f = o - center;
    let b = dot(f, d);
    let perp = f - b * d;
    let disc = radius * radius - dot(perp, perp);
    if (disc < 0.0) {
        return -1.0;
    }
    let c = dot(f, f) - radius * radius;
    let q = -b - select(-1.0, 1.0, b >= 0.0) * sqrt(disc);
    var t0 = c / q;
    var t1 = q;
    if (t0 > t1) {
        let tmp = t0;
        t0 = t1;
        t1 = tmp;
    }
    if (t0 > t_min && t0 < t_max) {
        return t0;
    }
    if (t1 > t_min && t1 < t_max) {
        return t1;
    }
    return -1.0;
}

// t of the ray's crossing of the plane dot(n, x) = offset, or -1 when parallel or out of range.
fn intersect_plane(o: vec3f, d: vec3f, normal: vec3f, offset: f32, t_min: f32, t_max: f32) -> f32 {
    let denom = dot(normal, d);
    if (denom == 0.0) {
        return -1.0;
    }
    let t = (offset - dot(normal, o)) / denom;
    return select(-1.0, t, t > t_min && t < t_max);
}

fn intersect_scene(o: vec3f, d: vec3f) -> Hit {
    var hit = Hit(INFINITY, vec3f(0.0), 0u, INVALID);
    for (var i = 0u; i < NUM_SPHERES; i++) {
        let s = spheres[i];
        let t = intersect_sphere(o, d, s.center, s.radius, 0.0, hit.t);
        if (t > 0.0) {
            hit.t = t;
            hit.object = i;
        }
    }
    for (var j = 0u; j < NUM_PLANES; j++) {
        let p = planes[j];
        let t = intersect_plane(o, d, p.normal, p.offset, 0.0, hit.t);
        if (t > 0.0) {
            hit.t = t;
            hit.object = NUM_SPHERES + j;
        }
    }
    // Normal and material of the closest object only (not of every candidate).
    if (hit.object < NUM_SPHERES) {
        let s = spheres[hit.object];
        hit.normal = (o + d * hit.t - s.center) / s.radius;
        hit.material = s.material;
    } else if (hit.object != INVALID) {
        let p = planes[hit.object - NUM_SPHERES];
        hit.normal = p.normal;
        hit.material = p.material;
    }
    return hit;
}

// True when something other than sphere `skip` lies on the segment (o, o + t_max d).
fn occluded(o: vec3f, d: vec3f, t_max: f32, skip: u32) -> bool {
    for (var i = 0u; i < NUM_SPHERES; i++) {
        if (i == skip) {
            continue;
        }
        let s = spheres[i];
        if (intersect_sphere(o, d, s.center, s.radius, 0.0, t_max) > 0.0) {
            return true;
        }
    }
    for (var j = 0u; j < NUM_PLANES; j++) {
        let p = planes[j];
        if (intersect_plane(o, d, p.normal, p.offset, 0.0, t_max) > 0.0) {
            return true;
        }
    }
    return false;
}

// Origin for a ray leaving surface point p on the side of unit normal n_side: offset by a
// distance proportional to the point's magnitude, above the f32 error of p and of the hit.
fn offset_ray_origin(p: vec3f, n_side: vec3f) -> vec3f {
    let scale = max(max3(abs(p)), 1.0);
    return p + n_side * (scale * 2e-5);
}
