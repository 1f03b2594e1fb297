// integrator.wgsl — the unidirectional path tracer.
//
// Estimates, per pixel, the sum over light paths of at most frame.max_depth segments of the
// emission collected at every vertex (plus the environment for escaping rays). The choice of
// BSDF sampling and light sampling changes the variance, never this expectation.
//
// Sample dimension layout (fixed, so that the samplers can be addressed by dimension):
//   0, 1                     pixel jitter
//   then per scattering vertex k = 1, 2, ... a block of 4 + 2 * NUM_LIGHTS dimensions
//   starting at 2 + (k - 1) * (4 + 2 * NUM_LIGHTS):
//     +0, +1                 BSDF direction
//     +2                     BSDF lobe choice
//     +3                     reserved (Russian roulette)
//     +4 + 2l, +5 + 2l       direction towards light l

const LIGHTS_NONE: u32 = 0u;
const LIGHTS_NEE: u32 = 1u;
const LIGHTS_MIS: u32 = 2u;
// Biased, for demonstration (the study's extra reflections): NEE, and also the full emission of
// lights found by BSDF-sampled rays, so direct light is counted twice.
const LIGHTS_NEE_DOUBLE_COUNT: u32 = 3u;

// Light sampling strategy (set through pipeline constants).
override LIGHT_SAMPLING: u32 = LIGHTS_MIS;

const DIM_PIXEL: u32 = 0u;
const DIM_FIRST_VERTEX: u32 = 2u;

fn dims_per_vertex() -> u32 {
    return 4u + 2u * NUM_LIGHTS;
}

struct SampleId {
    pixel: u32,
    index: u32,
    seed: u32,
}

fn camera_ray_direction(px: u32, py: u32, jitter: vec2f) -> vec3f {
    let sx = 2.0 * (f32(px) + jitter.x) / f32(frame.width) - 1.0;
    let sy = 1.0 - 2.0 * (f32(py) + jitter.y) / f32(frame.height);
    return normalize(frame.camera_forward + sx * frame.camera_right + sy * frame.camera_up);
}

// True when x is on the inner side of light sphere `s`: inside it, or on its surface reached
// from inside (the vertex lies on the sphere itself and `from_inside` says which side).
fn inside_light(s: u32, sphere: Sphere, x: vec3f, vertex_object: u32, from_inside: bool) -> bool {
    if (!LIGHT_INTERIORS_REACHABLE) {
        return false;
    }
    if (s == vertex_object) {
        return from_inside;
    }
    let d = x - sphere.center;
    return dot(d, d) < sphere.radius * sphere.radius;
}

// Next event estimation at vertex x: one shadow ray to each light. With MIS the light sample
// is weighted by the power heuristic against the BSDF sampling density.
fn estimate_direct(id: SampleId, dim_base: u32, x: vec3f, n_s: vec3f, wo: vec3f, m: Phong,
                   vertex_object: u32, from_inside: bool) -> vec3f {
    var radiance = vec3f(0.0);
    let origin = offset_ray_origin(x, n_s);
    // Light l is sphere l: with the loop unrolled, the shadow ray's test of the light itself
    // folds away. No `continue`: the loop stays a simple counted one that compilers unroll.
    for (var l = 0u; l < NUM_LIGHTS; l++) {
        let sphere = spheres[l];
        let u = sample_2d(id.pixel, id.index, dim_base + 4u + 2u * l, id.seed);
        var ls: LightSample;
        if (inside_light(l, sphere, x, vertex_object, from_inside)) {
            ls = sample_sphere_light_area(sphere.center, sphere.radius, x, u);
        } else {
            ls = sample_sphere_light_cone(sphere.center, sphere.radius, x, u);
        }
        let cos_i = dot(ls.wi, n_s);
        let e = eval_pdf_bsdf(m, n_s, wo, ls.wi);
        // A point on a light's outer surface sees none of that light.
        let on_outer_surface = l == vertex_object && !from_inside;
        let contributes = !on_outer_surface && ls.pdf > 0.0 && cos_i > 0.0 && max3(e.f) > 0.0;
        // The branch spares GPUs the shadow ray of samples that cannot contribute.
        if (contributes && !occluded(origin, ls.wi, ls.dist * (1.0 - 1e-4), l)) {
            var mis = 1.0;
            if (LIGHT_SAMPLING == LIGHTS_MIS) {
                mis = power_heuristic(ls.pdf, e.pdf);
            }
            radiance += path_weight(e.f, cos_i, ls.pdf) * materials[sphere.material].emission * mis;
        }
    }
    return radiance;
}

// The vertex a BSDF-sampled ray left from, needed to weight emission found by that ray.
struct PrevVertex {
    position: vec3f,
    object: u32,
    from_inside: bool,
    bsdf_pdf: f32,
}

// Weight of emission found by a BSDF-sampled ray. With NEE, lights were already sampled
// from the previous vertex, so their emission counts 0; with MIS it gets the power heuristic.
fn emitter_hit_weight(hit: Hit, ray_dir: vec3f, prev: PrevVertex) -> f32 {
    // Not a light (lights are the first spheres; planes and misses have larger indices).
    if (LIGHT_SAMPLING == LIGHTS_NONE || LIGHT_SAMPLING == LIGHTS_NEE_DOUBLE_COUNT || hit.object >= NUM_LIGHTS) {
        return 1.0;
    }
    let sphere = spheres[hit.object];
    if (LIGHT_SAMPLING == LIGHTS_NEE) {
        return 0.0;
    }
    let inside = inside_light(hit.object, sphere, prev.position, prev.object, prev.from_inside);
    let light_pdf = pdf_sphere_light(sphere.center, sphere.radius, prev.position, inside, ray_dir);
    return power_heuristic(prev.bsdf_pdf, light_pdf);
}

// Radiance arriving along a ray that found `hit`: the environment when it escaped, else the
// emission of what it hit (zero for non-emitters).
fn radiance_along(hit: Hit) -> vec3f {
    if (hit.object == INVALID) {
        return select(vec3f(0.0), frame.environment, HAS_ENVIRONMENT);
    }
    return materials[hit.material].emission;
}

// Structure for SIMD CPU drivers as much as for GPUs: lavapipe runs 8 lanes in lockstep and
// executes both sides of every branch under a mask, but leaves a loop as soon as no lane is
// left in it. So the camera segment is traced before the loop, and each iteration scatters at
// the current hit and traces the next segment, with the exit test at the end of the body: no
// iteration runs only to find that every lane is done.
fn trace_path(id: SampleId, px: u32, py: u32) -> vec3f {
    var ray_o = frame.camera_origin;
    var ray_d = camera_ray_direction(px, py, sample_2d(id.pixel, id.index, DIM_PIXEL, id.seed));
    var hit = intersect_scene(ray_o, ray_d);
    var radiance = radiance_along(hit);
    if (frame.max_depth <= 1u || hit.object == INVALID) {
        return radiance;
    }

    var throughput = vec3f(1.0);
    // Segments of the path so far.
    var depth = 1u;
    loop {
        // Scattering vertex: shading normal turned towards the viewer (two-sided surfaces).
        let x = ray_o + ray_d * hit.t;
        let wo = -ray_d;
        let from_inside = dot(hit.normal, wo) < 0.0;
        let n_s = select(hit.normal, -hit.normal, from_inside);
        let m = material_phong(materials[hit.material]);
        let dim_base = DIM_FIRST_VERTEX + (depth - 1u) * dims_per_vertex();

        if (LIGHT_SAMPLING != LIGHTS_NONE && NUM_LIGHTS > 0u) {
            radiance += throughput * estimate_direct(id, dim_base, x, n_s, wo, m, hit.object, from_inside);
        }

        let u_dir = sample_2d(id.pixel, id.index, dim_base, id.seed);
        let u_lobe = sample_1d(id.pixel, id.index, dim_base + 2u, id.seed);
        let bs = sample_bsdf(m, n_s, wo, u_dir, u_lobe);
        let scattered = max3(bs.weight) > 0.0;
        throughput *= bs.weight;
        let prev = PrevVertex(x, hit.object, from_inside, bs.pdf);
        ray_o = offset_ray_origin(x, n_s);
        ray_d = bs.wi;
        // A sample that cannot scatter (below the surface) ends the path untraced.
        hit = Hit(0.0, vec3f(0.0, 0.0, 1.0), 0u, INVALID);
        if (scattered) {
            hit = intersect_scene(ray_o, ray_d);
        }
        depth++;
        if (scattered) {
            var w = 1.0;
            if (hit.object != INVALID) {
                w = emitter_hit_weight(hit, ray_d, prev);
            }
            radiance += throughput * radiance_along(hit) * w;
        }
        continuing {
            break if depth >= frame.max_depth || !scattered || hit.object == INVALID;
        }
    }
    return radiance;
}

@compute @workgroup_size(8, 8, 1)
fn render_main(@builtin(global_invocation_id) gid: vec3u) {
    if (gid.x >= frame.tile_width || gid.y >= frame.tile_height) {
        return;
    }
    let px = frame.tile_x + gid.x;
    let py = frame.tile_y + gid.y;
    let pixel = py * frame.width + px;
    // The accumulator holds rows from accum_row on; the sampler is addressed by the image pixel.
    let slot = (frame.accum_row + gid.y) * frame.tile_width + gid.x;
    var acc = accum[slot];
    // Do-while: the host never dispatches zero samples, and the test at the end spares SIMD
    // CPU drivers a last iteration with every lane done.
    var s = 0u;
    loop {
        let id = SampleId(pixel, frame.sample_start + s, frame.seed);
        accum_add_sample(&acc, trace_path(id, px, py));
        continuing {
            s++;
            break if s >= frame.sample_count;
        }
    }
    accum_add_rays(&acc, rays_traced);
    accum[slot] = acc;
}
