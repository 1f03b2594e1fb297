// emitters/environment.wgsl — the environment: radiance from every direction at infinity
// (src/scene/emitters/environment.rs), constant (Mitsuba's `constant`, frame.environment) or
// from a latitude-longitude image (Mitsuba's `envmap`, HAS_ENVIRONMENT_MAP: `environment_map`,
// as `EnvironmentMap::pack` lays it out: width, height, scale, the world-to-map rotation (9,
// rows), whether it can be importance-sampled, then the texels' RGB, rows from the top, and its
// luminance distribution). Escaped rays always find it; next event estimation samples it only
// where the method asks (NUM_ENVIRONMENT_LIGHTS = 1), drawing directions uniformly over the
// sphere as Mitsuba's ConstantBackgroundEmitter does (density 1 / (4 pi)) or, for a map, by its
// luminance or by its MIS-compensated luminance (ENV_SAMPLING).

@group(0) @binding(BINDING_ENVIRONMENT_MAP) var<storage, read> environment_map: array<f32>;

// How next event estimation draws directions towards a map (src/method.rs `EnvSampling`).
override ENV_SAMPLING: u32 = ENV_SAMPLING_ENV_LUMINANCE;

// Where the record's parts start: texels, then per sampling distribution (luminance, then
// compensated: EnvironmentMap::pack) the density per cell, the rows' and the cells' cumulative
// distributions.
fn environment_map_texels() -> u32 {
    return ENVIRONMENT_MAP_HEADER;
}
// The table of the distribution ENV_SAMPLING draws from: the luminance one's right after the
// texels, the compensated one's after it (W H + H + 1 + H (W + 1) numbers each).
fn environment_map_table() -> u32 {
    let w = u32(environment_map[0]);
    let h = u32(environment_map[1]);
    let luminance = ENVIRONMENT_MAP_HEADER + 3u * w * h;
    return select(luminance, luminance + w * h + h + 1u + h * (w + 1u), ENV_SAMPLING == ENV_SAMPLING_ENV_COMPENSATED);
}
fn environment_map_density() -> u32 {
    return environment_map_table();
}
fn environment_map_row_cdf() -> u32 {
    return environment_map_density() + u32(environment_map[0]) * u32(environment_map[1]);
}
fn environment_map_cell_cdf(y: u32) -> u32 {
    return environment_map_row_cdf() + u32(environment_map[1]) + 1u + y * (u32(environment_map[0]) + 1u);
}

// Whether next event estimation draws from one of the map's distributions: the method asks
// for luminance (some texel is bright) or compensated sampling (some texel is brighter than
// the mean, else the table is uniform over the sphere); else uniform directions.
fn environment_map_sampled() -> bool {
    return HAS_ENVIRONMENT_MAP && ((ENV_SAMPLING == ENV_SAMPLING_ENV_LUMINANCE && environment_map[12] > 0.0)
        || (ENV_SAMPLING == ENV_SAMPLING_ENV_COMPENSATED && environment_map[13] > 0.0));
}

// The map's (u, t) of world direction d: v = R^T d, u = atan2(v.x, -v.z) / 2 pi in [0, 1),
// t = acos(v.y) / pi.
fn environment_map_uv(d: vec3f) -> vec2f {
    let v = vec3f(environment_map[3] * d.x + environment_map[4] * d.y + environment_map[5] * d.z,
                  environment_map[6] * d.x + environment_map[7] * d.y + environment_map[8] * d.z,
                  environment_map[9] * d.x + environment_map[10] * d.y + environment_map[11] * d.z);
    // The accurate arctangent (common.wgsl): llvmpipe's atan2 and acos err by up to 1e-4 rad,
    // which would put directions near a cell's edge in the neighbouring cell of the pdf.
    var u = atan2_accurate(v.x, -v.z) * (0.5 * INV_PI);
    u = u - floor(u);
    return vec2f(u, clamp(atan2_accurate(length(v.xz), v.y) * INV_PI, 0.0, 1.0));
}

// The world direction of (u, t): theta = pi t from the map's +y, phi = 2 pi u, the map's
// direction (sin phi sin theta, cos theta, -cos phi sin theta) turned by R (Mitsuba's
// uv_to_direction).
fn environment_map_direction(uv: vec2f) -> vec3f {
    let theta = uv.y * PI;
    let phi = uv.x * 2.0 * PI;
    let v = vec3f(sin(phi) * sin(theta), cos(theta), -cos(phi) * sin(theta));
    // d = R v: R's columns are the rows of R^T, stored at 3, 6, 9.
    return normalize(v.x * vec3f(environment_map[3], environment_map[4], environment_map[5])
        + v.y * vec3f(environment_map[6], environment_map[7], environment_map[8])
        + v.z * vec3f(environment_map[9], environment_map[10], environment_map[11]));
}

// The interval i < n of the cumulative distribution of n + 1 entries at `start` that holds u:
// the largest i with cdf[i] <= u (so never an interval of zero probability; cdf[n] = 1 > u).
// A bisection: log2(n) steps.
fn environment_cdf_search(start: u32, n: u32, u: f32) -> u32 {
    var lo = 0u;
    var hi = n;
    while (hi - lo > 1u) {
        let mid = (lo + hi) / 2u;
        if (environment_map[start + mid] <= u) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// Solid-angle density of a uv density p(u, t) at polar angle theta: the map's (u, t) square
// covers the sphere with dA = 2 pi^2 sin(theta) du dt.
fn environment_map_solid_angle_pdf(uv_pdf: f32, theta: f32) -> f32 {
    return uv_pdf / (2.0 * PI * PI * max(sin(theta), 1e-7));
}

// A direction by the map's distribution (ENV_SAMPLING's), piecewise constant over its W x H cells
// of the uv square: a row by the rows' distribution, a cell by that row's, a point uniform in
// the cell (the fractions of u left over); its solid-angle density in w.
fn sample_environment_map(u: vec2f) -> vec4f {
    let w = u32(environment_map[0]);
    let h = u32(environment_map[1]);
    let rows = environment_map_row_cdf();
    let y = environment_cdf_search(rows, h, u.y);
    let r0 = environment_map[rows + y];
    let dv = clamp((u.y - r0) / (environment_map[rows + y + 1u] - r0), 0.0, 0.99999994);
    let cells = environment_map_cell_cdf(y);
    let x = environment_cdf_search(cells, w, u.x);
    let c0 = environment_map[cells + x];
    let du = clamp((u.x - c0) / (environment_map[cells + x + 1u] - c0), 0.0, 0.99999994);
    let uv = vec2f((f32(x) + du) / f32(w), (f32(y) + dv) / f32(h));
    let density = environment_map[environment_map_density() + y * w + x];
    return vec4f(environment_map_direction(uv), environment_map_solid_angle_pdf(density, uv.y * PI));
}

// Solid-angle density with which sample_environment_map gives world direction d.
fn pdf_environment_map(d: vec3f) -> f32 {
    let w = u32(environment_map[0]);
    let h = u32(environment_map[1]);
    let uv = environment_map_uv(d);
    let x = min(u32(uv.x * f32(w)), w - 1u);
    let y = min(u32(uv.y * f32(h)), h - 1u);
    return environment_map_solid_angle_pdf(environment_map[environment_map_density() + y * w + x], uv.y * PI);
}

// A direction from ctx towards the environment, at infinite distance: uniform on the sphere
// (density 1 / (4 pi)), as Mitsuba's ConstantBackgroundEmitter, or for a map under
// ENV_SAMPLING_ENV_LUMINANCE or _COMPENSATED by that distribution (sample_environment_map).
fn sample_environment_emitter(l: u32, ctx: LightSampleContext, u: vec2f) -> EmitterSample {
    if (ENV_TECHNIQUE && HAS_ENVIRONMENT_MAP) {
        // A researcher's technique (technique.wgsl).
        let s = sample_environment_technique(ctx.n, u);
        return EmitterSample(s.xyz, INFINITY, s.w, eval_environment_emitter(s.xyz), INVALID, false);
    }
    if (environment_map_sampled()) {
        let s = sample_environment_map(u);
        return EmitterSample(s.xyz, INFINITY, s.w, eval_environment_emitter(s.xyz), INVALID, false);
    }
    let wi = square_to_uniform_sphere(u);
    return EmitterSample(wi, INFINITY, pdf_uniform_sphere(), eval_environment_emitter(wi), INVALID, false);
}

// Solid-angle density with which sample_environment_emitter gives wi.
fn pdf_environment_emitter(l: u32, ctx: LightSampleContext, wi: vec3f) -> f32 {
    if (ENV_TECHNIQUE && HAS_ENVIRONMENT_MAP) {
        return pdf_environment_technique(ctx.n, wi);
    }
    if (environment_map_sampled()) {
        return pdf_environment_map(wi);
    }
    return pdf_uniform_sphere();
}

// Texel (x, y) of the map, x periodic (longitude), y clamped (latitude).
fn environment_map_texel(x: i32, y: i32) -> vec3f {
    let w = i32(environment_map[0]);
    let h = i32(environment_map[1]);
    let xx = ((x % w) + w) % w;
    let yy = clamp(y, 0, h - 1);
    let t = environment_map_texels() + 3u * u32(yy * w + xx);
    return vec3f(environment_map[t], environment_map[t + 1u], environment_map[t + 2u]);
}

// The map's radiance towards world direction d (unit), as Mitsuba 3.9.1's envmap: v = R^T d;
// u = atan2(v.x, -v.z) / 2 pi wrapped into [0, 1), t = acos(v.y) / pi; bilinear with texel
// centres at x = u W - 1/2 (periodic) and rows at y = t (H - 1); times the scale. Host twin:
// EnvironmentMap::radiance.
fn environment_map_radiance(d: vec3f) -> vec3f {
    let uv = environment_map_uv(d);
    let p = vec2f(uv.x * environment_map[0] - 0.5, uv.y * (environment_map[1] - 1.0));
    let base = floor(p);
    let f = p - base;
    let x0 = i32(base.x);
    let y0 = i32(base.y);
    let t00 = environment_map_texel(x0, y0);
    let t10 = environment_map_texel(x0 + 1, y0);
    let t01 = environment_map_texel(x0, y0 + 1);
    let t11 = environment_map_texel(x0 + 1, y0 + 1);
    let top = t00 + f.x * (t10 - t00);
    let bottom = t01 + f.x * (t11 - t01);
    return (top + f.y * (bottom - top)) * environment_map[2];
}

// Radiance an escaped ray receives (none where the environment is black).
fn eval_environment_emitter(ray_d: vec3f) -> vec3f {
    if (HAS_ENVIRONMENT_MAP) {
        return environment_map_radiance(ray_d);
    }
    return select(vec3f(0.0), frame.environment, HAS_ENVIRONMENT);
}
