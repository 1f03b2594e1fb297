// volpath.wgsl — the path tracer in scenes with participating media (NUM_MEDIA > 0; host:
// src/scene/media/), Mitsuba's `volpath` in expectation (src/integrators/volpath.cpp).
//
// A path alternates segments and vertices. Along a segment in a medium, free-flight sampling
// (medium.wgsl) decides whether light scatters in the medium before the surface the ray meets;
// a scattering vertex in a medium samples its phase function (phase.wgsl) and, with next event
// estimation, the lights. A vertex on a surface is integrator.wgsl's (surface_vertex). Emission
// found by a segment is weighted against light sampling from the last real scattering vertex
// (emitter_hit_weight, with the phase function's density where that vertex was in a medium).
//
// As in Mitsuba's volpath:
// - depth counts real scattering events, in media and on surfaces; a thin dielectric's
//   transmission (and `null`, the thin dielectric of index 1) is a null interaction: the ray
//   goes on straight, neither a vertex of depth nor one that light sampling starts from
//   (its weight is the pane's transmission), and so is a mask's pass;
// - a vertex may scatter (and sample lights) only while depth + 1 < max_depth, so a path of k
//   scattering events contributes only if k < max_depth, through however many null surfaces;
// - shadow rays pass through null surfaces and masks, times Mitsuba's eval_null_transmission, and
//   through media, times the Beer-Lambert transmittance (a ratio-tracking estimate of it in a
//   heterogeneous medium); any other surface blocks them;
// - a ray crossing a surface that bounds media takes the medium of the side it enters
//   (medium_after, Mitsuba's target_medium); across other surfaces it keeps its medium;
// - under hide_emitters no emission counts before the first scattering event, and a segment
//   whose surface is found outside a medium passes through area emitters until then.
// In homogeneous media free-flight sampling balances the three channels where Mitsuba's volpath
// samples one per path, and shadow rays use the exact transmittance where it tracks: the
// expectation is the same, the variance lower. In heterogeneous media both track, as Mitsuba's
// (medium.wgsl: delta tracking, ratio tracking).
//
// Sample dimensions: the pixel's and the lens's, then one block per segment s = 0, 1, ...
// starting at first_vertex_dim() + s (dims_per_vertex() + 2): the vertex at the segment's end
// takes the block's first dims_per_vertex() as integrator.wgsl lays them out (a phase
// function's direction in +0, +1), and the segment's free flight the last two (channel, then
// distance). Null interactions take a block of their own.

// Where a shadow ray starts: the medium the path is in, and the surface the vertex lies on
// (INVALID for a vertex in a medium), whose media decide it by the ray's direction.
struct ShadowMedia {
    current: u32,
    material: u32,
    normal: vec3f,
}

// The shadow media of a path without media (integrator.wgsl's trace_path).
const NO_SHADOW_MEDIA: ShadowMedia = ShadowMedia(NO_MEDIUM, INVALID, vec3f(0.0, 0.0, 0.0));

fn shadow_start_medium(media: ShadowMedia, d: vec3f) -> u32 {
    if (media.material == INVALID) {
        return media.current;
    }
    return medium_after(media.material, media.normal, d, media.current);
}

// MAX_SHADOW_CROSSINGS (generated from src/scene/media/mod.rs): the most surfaces one shadow
// ray passes through; a light behind more counts as shadowed.

// The fraction of light a surface passes straight along d (Mitsuba's eval_null_transmission):
// a thin dielectric's 1 - R' at the incidence, times its transmittance (1 for `null`); 0 for
// every other BSDF, which blocks a shadow ray; and a mask's 1 - opacity (1 - that of its BSDF)
// (mask.cpp).
fn null_transmission(hit: Hit, x: vec3f, d: vec3f) -> vec3f {
    if (!HAS_THIN_DIELECTRIC && !HAS_MASKS) {
        return vec3f(0.0);
    }
    let from_inside = dot(hit.normal, d) > 0.0;
    let m = material_bsdf(hit.material, hit.material, from_inside, texture_context(hit, x));
    var nested = vec3f(0.0);
    if (HAS_THIN_DIELECTRIC && m.kind == BSDF_KIND_THIN_DIELECTRIC) {
        let pane = thin_dielectric_of(m);
        nested = (1.0 - thin_dielectric_reflectance(pane, dot(d, hit.shading_normal))) * pane.transmittance;
    }
    if (HAS_MASKS) {
        // m.opacity is 1 where the material has no mask.
        return 1.0 - m.opacity * (1.0 - nested);
    }
    return nested;
}

// Transmittance of the shadow ray from o along d over t_max, starting in medium `start`:
// the medium's transmittance over each stretch in a medium, times the null transmission of each surface
// crossed; 0 where a surface that is not null blocks it. Sphere `skip` (the light sampled)
// ends it, as in `occluded`.
fn shadow_transmittance(o: vec3f, d: vec3f, t_max: f32, skip: u32, start: u32) -> vec3f {
    var tr = vec3f(1.0);
    var medium = start;
    var origin = o;
    var remaining = t_max;
    var reached = false;
    // Null collisions left to ratio tracking in heterogeneous media (medium.wgsl).
    var budget = MAX_NULL_COLLISIONS;
    for (var i = 0u; i < MAX_SHADOW_CROSSINGS; i++) {
        let hit = intersect_scene(origin, d);
        let reaches = hit.object == INVALID || hit.t >= remaining || (skip != INVALID && hit.object == skip);
        let stretch = select(hit.t, remaining, reaches);
        if (medium != NO_MEDIUM) {
            tr *= medium_segment_transmittance(medium_at(medium), origin, d, stretch, &budget);
        }
        if (reaches) {
            reached = true;
            break;
        }
        let x = origin + d * hit.t;
        tr *= null_transmission(hit, x, d);
        if (max3(tr) <= 0.0) {
            break;
        }
        medium = medium_after(hit.material, hit.normal, d, medium);
        let next = offset_ray_origin(x, select(-hit.normal, hit.normal, dot(hit.normal, d) > 0.0), hit.p_error);
        remaining -= dot(next - origin, d);
        origin = next;
    }
    return select(vec3f(0.0), tr, reached);
}

// One light sample seen from a point x in a medium, light having travelled along d: the phase
// function for f (no cosine: a medium has no surface), the shadow ray's transmittance, weighted
// against phase-function sampling under MIS. The counterpart of integrator.wgsl's direct_light.
fn medium_direct_light(es: EmitterSample, prob: f32, x: vec3f, d: vec3f, g: f32, medium: u32) -> vec3f {
    let pdf = prob * es.pdf;
    if (!(pdf > 0.0 && max3(es.emission) > 0.0)) {
        return vec3f(0.0);
    }
    let phase = pdf_hg_phase(g, d, es.wi);
    // From x itself: a point in a medium has no surface to leave.
    let shadow = shadow_ray_to(es, x, x);
    let tr = shadow_transmittance(x, shadow.d, shadow.t_max, es.skip, medium);
    return es.emission * tr * (phase / pdf) * mis_weight(pdf, select(phase, 0.0, es.delta));
}

// Light l's sample at a point in a medium (ctx.x), for next event estimation towards every
// light, in surface_light's sample dimensions (each_light_u).
fn medium_light(id: SampleId, dim_base: u32, l: u32, ctx: LightSampleContext, d: vec3f, g: f32, medium: u32) -> vec3f {
    return medium_direct_light(sample_emitter(l, ctx, each_light_u(id, dim_base, l)), 1.0, ctx.x, d, g, medium);
}

// Next event estimation at a point x in a medium: the lights as estimate_direct picks them, in
// the same sample dimensions.
fn estimate_direct_medium(id: SampleId, dim_base: u32, x: vec3f, d: vec3f, g: f32, medium: u32) -> vec3f {
    let ctx = LightSampleContext(x, INVALID, false, vec3f(0.0));
    var radiance = vec3f(0.0);
    if (LIGHT_SELECT == LIGHT_SELECT_ALL) {
        // Each light at a constant index where the host unrolls the visits (as estimate_direct).
        radiance = each_light_in_medium(id, dim_base, ctx, d, g, medium);
    } else {
        let chosen = select_light(sample_1d(id.pixel, id.index, dim_base + 4u, id.seed));
        let u = sample_2d(id.pixel, id.index, dim_base + 5u, id.seed);
        radiance += medium_direct_light(sample_emitter(chosen.index, ctx, u), chosen.prob, x, d, g, medium);
    }
    return radiance;
}

// Sample dimensions per segment: a vertex's block, then the free flight's two.
fn dims_per_segment() -> u32 {
    return dims_per_vertex() + 2u;
}

// The most segments a path traces: its max_depth scattering events and up to max_depth +
// EXTRA_NULL_SEGMENTS null interactions between them (src/scene/media/mod.rs, max_segments);
// a path that would cross more null surfaces ends there.
fn max_segments() -> u32 {
    return 2u * frame.max_depth + EXTRA_NULL_SEGMENTS;
}

// Russian roulette after a scattering event (integrator.wgsl's rule): false where the path ends.
fn volumetric_roulette(id: SampleId, dim_base: u32, depth: u32, throughput: ptr<function, vec3f>, eta: f32) -> bool {
    if (RR_DEPTH == 0u || depth < RR_DEPTH) {
        return true;
    }
    let q = min(max3(*throughput) * (eta * eta), 0.95);
    if (sample_1d(id.pixel, id.index, dim_base + 3u, id.seed) < q) {
        *throughput /= q;
        return true;
    }
    return false;
}

fn trace_volumetric_path(id: SampleId, px: u32, py: u32) -> vec3f {
    let camera = sample_camera_ray(id, px, py);
    var ray_o = camera.o;
    var ray_d = camera.d;
    var medium = CAMERA_MEDIUM;
    var radiance = vec3f(0.0);
    var throughput = vec3f(1.0);
    var eta = 1.0;
    // Scattering events so far (Mitsuba's depth), and segments traced (sample blocks used).
    var depth = 0u;
    var segment = 0u;
    // The last scattering vertex; the camera's stands as a delta: what its rays find counts 1.
    var prev = PrevVertex(ray_o, INVALID, false, 0.0, true, vec3f(0.0));
    loop {
        let dim_base = first_vertex_dim() + segment * dims_per_segment();
        var hit = intersect_scene(ray_o, ray_d);
        if (HIDE_EMITTERS && depth == 0u && medium == NO_MEDIUM) {
            // Mitsuba's volpath under hide_emitters: before the first scattering event, a segment
            // whose surface is found outside a medium passes through every area emitter on it
            // (skip_area_emitters; in a medium it does not, and meets the emitter's surface);
            // one that would cross more than EMITTER_SKIPS of them ends the path.
            hit = skip_area_emitters(&ray_o, ray_d, hit);
            if (hit.object != INVALID && light_of(hit.object) != INVALID) {
                break;
            }
        }
        var in_medium = false;
        var t_event = hit.t;
        if (medium != NO_MEDIUM) {
            let u = sample_2d(id.pixel, id.index, dim_base + dims_per_vertex(), id.seed);
            // Delta tracking's further numbers: a stream of this sample and segment.
            var key = 0u;
            if (MAX_NULL_COLLISIONS > 0u) {
                key = hash4(id.seed, id.pixel, id.index, 0x6d656400u + segment);
            }
            let flight = sample_free_flight(medium_at(medium), ray_o, ray_d, select(hit.t, INFINITY, hit.object == INVALID), u.x, u.y, key);
            throughput *= flight.weight;
            in_medium = flight.scattered;
            t_event = flight.t;
        }
        if (!in_medium) {
            // The segment reached a surface (or escaped): its emission, weighted against light
            // sampling from the last scattering vertex; none before the first scattering event
            // under hide_emitters (Mitsuba's volpath: not at depth 0, the environment included).
            if (!(HIDE_EMITTERS && depth == 0u)) {
                var w = 1.0;
                if (hit.object != INVALID || NUM_ENVIRONMENT_LIGHTS > 0u) {
                    w = emitter_hit_weight(hit, ray_d, prev);
                }
                radiance += throughput * radiance_along(hit, ray_d) * w;
            }
            if (hit.object == INVALID) {
                break;
            }
        }
        if (in_medium) {
            // A scattering event in the medium.
            if (depth + 1u >= frame.max_depth) {
                break;
            }
            let x = ray_o + ray_d * t_event;
            let g = medium_at(medium).g;
            if (LIGHT_SAMPLING != LIGHTS_NONE && NUM_LIGHTS > 0u) {
                radiance += throughput * estimate_direct_medium(id, dim_base, x, ray_d, g, medium);
            }
            // The phase function is its own density: the sample's weight is 1.
            let ps = sample_hg_phase(g, ray_d, sample_2d(id.pixel, id.index, dim_base, id.seed));
            depth += 1u;
            prev = PrevVertex(x, INVALID, false, ps.pdf, false, vec3f(0.0));
            ray_o = x;
            ray_d = ps.wi;
            if (!volumetric_roulette(id, dim_base, depth, &throughput, eta)) {
                break;
            }
        } else {
            let v = surface_vertex(id, hit, ray_o, ray_d, dim_base);
            let bs = sample_bsdf(v.m, v.n_s, v.wo, sample_2d(id.pixel, id.index, dim_base, id.seed), v.u_lobe);
            // A thin dielectric's transmission (straight through, to the surface's other side)
            // is a null interaction, its reflection a scattering event; so is a mask's pass
            // (Mitsuba's Null lobe), from either side of a one-sided material.
            let passes = bsdf_passes_through(v.m, v.u_lobe);
            let null_crossing = passes || (HAS_THIN_DIELECTRIC && v.m.kind == BSDF_KIND_THIN_DIELECTRIC && dot(bs.wi, v.n_g) < 0.0);
            var scattered = v.scatters && max3(bs.weight) > 0.0;
            if (HAS_SHADING_NORMALS) {
                scattered = scattered && same_side_of_both(bs.wi, v.n_s, v.n_g, v.m);
            }
            if (passes) {
                scattered = true;
            }
            if (!null_crossing) {
                if (depth + 1u >= frame.max_depth) {
                    break;
                }
                if (LIGHT_SAMPLING != LIGHTS_NONE && NUM_LIGHTS > 0u && v.scatters && !bsdf_is_delta(v.m)) {
                    let ctx = LightSampleContext(v.x, hit.object, v.from_inside, v.n_s);
                    radiance += throughput * estimate_direct(id, dim_base, ctx, hit.p_error, v.n_s, v.n_g, v.wo, v.m, ShadowMedia(medium, hit.material, hit.normal));
                }
                depth += 1u;
                prev = PrevVertex(v.x, hit.object, v.from_inside, bs.pdf, bs.delta, v.n_s);
            }
            if (!scattered) {
                break;
            }
            throughput *= bs.weight;
            if (bsdf_may_transmit()) {
                eta *= bs.eta;
            }
            medium = medium_after(hit.material, hit.normal, bs.wi, medium);
            ray_o = offset_ray_origin(v.x, transmission_side(v.n_g, bs.wi), hit.p_error);
            ray_d = bs.wi;
            if (!null_crossing && !volumetric_roulette(id, dim_base, depth, &throughput, eta)) {
                break;
            }
        }
        segment += 1u;
        continuing {
            break if segment >= max_segments();
        }
    }
    return radiance;
}
