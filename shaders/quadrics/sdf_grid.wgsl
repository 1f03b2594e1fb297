// quadrics/sdf_grid.wgsl — Mitsuba's sdfgrid (src/shapes/sdfgrid.cpp; the host's is
// src/scene/quadrics/sdf_grid.rs): the zero set of the trilinear interpolant of signed distances
// at the nodes of a grid on the unit cube of its object space. Its record (a Quadric,
// src/gpu/scene_buffers.rs): object_* and world_* the maps between the world and that cube;
// normal.x the bits of where its values start in bsdf_data (the node counts nx, ny, nz, then
// the values, x fastest), normal.y 1 for smooth shading normals. Grid coordinates g are object
// coordinates times the cell counts: node (i, j, k) at g = (i, j, k), cell v between v and v + 1.

// Where grid q's record starts in bsdf_data.
fn sdf_grid_record(q: Quadric) -> u32 {
    return bitcast<u32>(q.normal.x);
}

// The node counts of the grid whose record starts at `at`.
fn sdf_grid_nodes(at: u32) -> vec3i {
    return vec3i(i32(bsdf_data[at]), i32(bsdf_data[at + 1u]), i32(bsdf_data[at + 2u]));
}

// The value at node v, each index clamped to the grid (Dr.Jit's clamp mode).
fn sdf_grid_value(at: u32, n: vec3i, v: vec3i) -> f32 {
    let c = clamp(v, vec3i(0), n - vec3i(1));
    return bsdf_data[at + 3u + u32((c.z * n.y + c.y) * n.x + c.x)];
}

// The cubic c.x + c.y t + c.z t^2 + c.w t^3 that is minus the trilinear interpolant of cell v
// along o + t d in the cell's own coordinates (its corners at 0 and 1): Hansson-Söderlund et
// al. (JCGT 2022) as Mitsuba writes it (`cubic` in the host's).
fn sdf_grid_cubic(at: u32, n: vec3i, v: vec3i, o: vec3f, d: vec3f) -> vec4f {
    let s000 = sdf_grid_value(at, n, v);
    let s100 = sdf_grid_value(at, n, v + vec3i(1, 0, 0));
    let s010 = sdf_grid_value(at, n, v + vec3i(0, 1, 0));
    let s110 = sdf_grid_value(at, n, v + vec3i(1, 1, 0));
    let s001 = sdf_grid_value(at, n, v + vec3i(0, 0, 1));
    let s101 = sdf_grid_value(at, n, v + vec3i(1, 0, 1));
    let s011 = sdf_grid_value(at, n, v + vec3i(0, 1, 1));
    let s111 = sdf_grid_value(at, n, v + vec3i(1, 1, 1));
    let a = s101 - s001;
    let k0 = s000;
    let k1 = s100 - s000;
    let k2 = s010 - s000;
    let k3 = s110 - s010 - k1;
    let k4 = k0 - s001;
    let k5 = k1 - a;
    let k6 = k2 - (s011 - s001);
    let k7 = k3 - (s111 - s011 - a);
    let m0 = o.x * o.y;
    let m1 = d.x * d.y;
    let m2 = o.x * d.y + o.y * d.x;
    let m3 = k5 * o.z - k1;
    let m4 = k6 * o.z - k2;
    let m5 = k7 * o.z - k3;
    let c0 = (k4 * o.z - k0) + o.x * m3 + o.y * m4 + m0 * m5;
    let c1 = d.x * m3 + d.y * m4 + m2 * m5 + d.z * (k4 + k5 * o.x + k6 * o.y + k7 * m0);
    let c2 = m1 * m5 + d.z * (k5 * d.x + k6 * d.y + k7 * m2);
    let c3 = k7 * m1 * d.z;
    return vec4f(c0, c1, c2, c3);
}

// The interpolant (minus the cubic c) at t.
fn sdf_grid_eval_cubic(c: vec4f, t: f32) -> f32 {
    return -(((c.w * t + c.z) * t + c.y) * t + c.x);
}

// The sub-interval (x, y) of [0, t_end] holding the first sign change of the interpolant, split
// at the roots of its derivative 3 c3 t^2 + 2 c2 t + c1 (Marmitt et al. 2004, Mitsuba's
// sdf_solve_cubic), and z 1 where it has one (its ends of opposite signs, or one of them 0).
fn sdf_grid_bracket(c: vec4f, t_end: f32) -> vec3f {
    var t_near = 0.0;
    var t_far = t_end;
    // The derivative's roots in the stable form (Mitsuba's solve_quadratic; a = 0: linear).
    let qa = 3.0 * c.w;
    let qb = 2.0 * c.z;
    let disc = qb * qb - 4.0 * qa * c.y;
    let linear = qa == 0.0;
    let temp = -0.5 * (qb + select(-1.0, 1.0, qb >= 0.0) * sqrt(max(disc, 0.0)));
    let x0 = select(temp / qa, -c.y / qb, linear);
    let x1 = select(c.y / temp, x0, linear);
    let has = select(disc >= 0.0, qb != 0.0, linear);
    let r0 = min(x0, x1);
    let r1 = max(x0, x1);
    if (has && t_near <= r0 && r0 <= t_far) {
        if (sdf_grid_eval_cubic(c, t_near) * sdf_grid_eval_cubic(c, r0) <= 0.0) {
            t_far = r0;
        } else {
            t_near = r0;
        }
    }
    if (has && t_near <= r1 && r1 <= t_far) {
        if (sdf_grid_eval_cubic(c, t_near) * sdf_grid_eval_cubic(c, r1) <= 0.0) {
            t_far = r1;
        } else {
            t_near = r1;
        }
    }
    let f_near = sdf_grid_eval_cubic(c, t_near);
    let f_far = sdf_grid_eval_cubic(c, t_far);
    let found = f_near * f_far <= 0.0 && (f_near != 0.0 || f_far != 0.0);
    return vec3f(t_near, t_far, select(0.0, 1.0, found));
}

// t where the ray o + t d first meets grid q's surface, in (0, t_max), or -1. The cells the ray
// crosses are walked front to back (3D-DDA in grid coordinates, each cell's interval from its
// planes, so that no error accumulates), up to the first whose interval brackets a sign change;
// there Mitsuba's regula falsi (at most REGULA_FALSI_STEPS steps, until the bracket is under
// 1e-5) finds the root, its last iterate the hit. Cells are tested whole, as Mitsuba does (a
// root past t_max is a miss), and the walk stops at t_max.
fn intersect_sdf_grid(q: Quadric, o: vec3f, d: vec3f, t_max: f32) -> f32 {
    let at = sdf_grid_record(q);
    let n = sdf_grid_nodes(at);
    let cells = vec3f(n - vec3i(1));
    let og = quadric_point_to_object(q, o) * cells;
    let dg = quadric_vector_to_object(q, d) * cells;
    // The grid's box [0, cells] (the slab test; an axis the ray runs along keeps it where its
    // origin lies between the two planes).
    let along = dg == vec3f(0.0);
    let safe = select(dg, vec3f(1.0), along);
    let ta = -og / safe;
    let tb = (cells - og) / safe;
    let lo = select(min(ta, tb), vec3f(-INFINITY), along);
    let hi = select(max(ta, tb), vec3f(INFINITY), along);
    let outside = any(along & ((og < vec3f(0.0)) | (og > cells)));
    let t_enter = max(max(max(lo.x, lo.y), lo.z), 0.0);
    let t_leave = min(min(hi.x, hi.y), hi.z);
    let forward = dg > vec3f(0.0);
    let step = select(vec3i(-1), vec3i(1), forward);
    var cell = clamp(vec3i(floor(og + dg * t_enter)), vec3i(0), n - vec3i(2));
    var t0 = t_enter;
    var walking = !outside && t_enter < t_leave && t_enter < t_max;
    var found = false;
    var c = vec4f(0.0);
    var bracket = vec3f(0.0);
    var cell_t0 = 0.0;
    let max_steps = n.x + n.y + n.z - 2;
    var i = 0;
    loop {
        // The cell's exit: its nearest plane ahead along each axis, or the box's.
        let planes = (vec3f(cell + select(vec3i(0), vec3i(1), forward)) - og) / safe;
        let t_next = select(planes, vec3f(INFINITY), along);
        let t1 = min(min(min(t_next.x, t_next.y), t_next.z), t_leave);
        let cubic = sdf_grid_cubic(at, n, cell, og + dg * t0 - vec3f(cell), dg);
        let b = sdf_grid_bracket(cubic, max(t1 - t0, 0.0));
        if (walking && b.z > 0.0) {
            found = true;
            c = cubic;
            bracket = b;
            cell_t0 = t0;
            walking = false;
        }
        // On to the neighbour across the nearest plane.
        let x = t_next.x <= t_next.y && t_next.x <= t_next.z;
        let y = !x && t_next.y <= t_next.z;
        cell += select(vec3i(0), step, vec3<bool>(x, y, !x && !y));
        t0 = t1;
        walking = walking && t0 < t_max && t0 < t_leave && all(cell >= vec3i(0)) && all(cell < n - vec3i(1));
        i++;
        continuing {
            break if !walking || i >= max_steps;
        }
    }
    if (!found) {
        return -1.0;
    }
    // Regula falsi on the bracket (Mitsuba's: the last iterate is the root).
    var t_near = bracket.x;
    var t_far = bracket.y;
    var f_near = sdf_grid_eval_cubic(c, t_near);
    var f_far = sdf_grid_eval_cubic(c, t_far);
    var t = t_near;
    var k = 0u;
    loop {
        t = t_near + (t_far - t_near) * (-f_near / (f_far - f_near));
        let f = sdf_grid_eval_cubic(c, t);
        if (f * f_near <= 0.0) {
            t_far = t;
            f_far = f;
        } else {
            t_near = t;
            f_near = f;
        }
        k++;
        continuing {
            break if abs(t_near - t_far) < 1e-5 || k >= REGULA_FALSI_STEPS;
        }
    }
    let t_hit = cell_t0 + t;
    return select(-1.0, t_hit, t_hit > 0.0 && t_hit < t_max);
}

// The partial derivative along `axis` of the interpolant in the slab of cells from node a to
// a + 1 along it, at grid point g's position across it: the difference of the bilinear values
// on the slab's two faces (Mitsuba's voxel_grad), per unit of object space.
fn sdf_grid_slab_derivative(at: u32, n: vec3i, axis: u32, a: i32, g: vec3f) -> f32 {
    let u = (axis + 1u) % 3u;
    let v = (axis + 2u) % 3u;
    let iu = floor(g[u]);
    let iv = floor(g[v]);
    let wu = g[u] - iu;
    let wv = g[v] - iv;
    var faces = vec2f(0.0);
    for (var side = 0; side < 2; side++) {
        var node = vec3i(0);
        node[axis] = a + side;
        node[u] = i32(iu);
        node[v] = i32(iv);
        let c00 = sdf_grid_value(at, n, node);
        node[u] = i32(iu) + 1;
        let c10 = sdf_grid_value(at, n, node);
        node[v] = i32(iv) + 1;
        let c11 = sdf_grid_value(at, n, node);
        node[u] = i32(iu);
        let c01 = sdf_grid_value(at, n, node);
        let bottom = c00 + wu * (c10 - c00);
        let top = c01 + wu * (c11 - c01);
        faces[side] = bottom + wv * (top - bottom);
    }
    return (faces.y - faces.x) * f32(n[axis] - 1);
}

// The gradient of cell v's interpolant at grid point g.
fn sdf_grid_cell_gradient(at: u32, n: vec3i, v: vec3i, g: vec3f) -> vec3f {
    return vec3f(sdf_grid_slab_derivative(at, n, 0u, v.x, g), sdf_grid_slab_derivative(at, n, 1u, v.y, g), sdf_grid_slab_derivative(at, n, 2u, v.z, g));
}

// An object-space normal of grid q in the world, normalised: A^T n with A the world-to-object
// rows (the inverse transpose of to_world).
fn sdf_grid_normal_to_world(q: Quadric, n: vec3f) -> vec3f {
    return normalize(n.x * q.object_x.xyz + n.y * q.object_y.xyz + n.z * q.object_z.xyz);
}

// The geometric normal at world point p of grid q: the interpolant's gradient in the cell p
// truncates to (the upper cell on a face; Mitsuba's sdf_grad).
fn sdf_grid_normal(q: Quadric, p: vec3f) -> vec3f {
    let at = sdf_grid_record(q);
    let n = sdf_grid_nodes(at);
    let g = quadric_point_to_object(q, p) * vec3f(n - vec3i(1));
    return sdf_grid_normal_to_world(q, sdf_grid_cell_gradient(at, n, vec3i(g), g));
}

// The shading normal at world point p of grid q, given its geometric normal: where the grid
// has smooth normals, the normalised gradients of the eight cells around p's nearest node r
// (cells r - 1 + (i, j, k); those with a negative index count 0) blended trilinearly by p's
// position from r - 1/2, an axis whose lower (upper) cells all lie outside the grid taking its
// upper (lower) ones alone (Mitsuba's smooth normals); the geometric normal where the blend
// cancels.
fn sdf_grid_shading_normal(q: Quadric, p: vec3f, geometric: vec3f) -> vec3f {
    if (q.normal.y == 0.0) {
        return geometric;
    }
    let at = sdf_grid_record(q);
    let n = sdf_grid_nodes(at);
    let g = quadric_point_to_object(q, p) * vec3f(n - vec3i(1));
    let r = round(g);
    let ri = vec3i(r);
    // A side of an axis has all four of its cells outside where its own index is negative (the
    // lower side's r - 1), or another axis's upper index is.
    let negative = ri < vec3i(0);
    let lower_out = (ri < vec3i(1)) | negative.yzx | negative.zxy;
    var w = select(g - r + vec3f(0.5), vec3f(1.0), lower_out);
    w = select(w, vec3f(0.0), vec3<bool>(any(negative)));
    var blend = vec3f(0.0);
    for (var c = 0; c < 8; c++) {
        let corner = vec3i(c & 1, (c >> 1u) & 1, (c >> 2u) & 1);
        let v = ri - vec3i(1) + corner;
        let gradient = sdf_grid_cell_gradient(at, n, v, g);
        let len = length(gradient);
        let unit = select(vec3f(0.0), gradient / len, all(v >= vec3i(0)) && len > 0.0);
        let wc = select(vec3f(1.0) - w, w, corner == vec3i(1));
        blend += unit * (wc.x * wc.y * wc.z);
    }
    let l = length(blend);
    return select(geometric, sdf_grid_normal_to_world(q, blend), l > 0.0);
}
