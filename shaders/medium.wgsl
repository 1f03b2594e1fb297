// medium.wgsl — participating media (host: src/scene/media/mod.rs; Mitsuba's `homogeneous`
// and `heterogeneous`, src/media/): their records, free-flight sampling and transmittance, and
// which medium a ray is in after crossing a surface.

// Media in the scene (SceneFeatures::num_media): 0 compiles every volumetric step out, and the
// path tracer is integrator.wgsl's trace_path alone.
override NUM_MEDIA: u32 = 0u;
// The medium the camera sits in (Scene::camera_medium), NO_MEDIUM for none.
override CAMERA_MEDIUM: u32 = NO_MEDIUM;
// The most null collisions tracked along one path segment or one shadow ray in heterogeneous
// media (media::null_collision_bound: exceeded with probability below 1e-15, where the path or
// shadow ray ends); 0 without heterogeneous media, which compiles tracking out.
override MAX_NULL_COLLISIONS: u32 = 0u;

// A medium's record (`Medium::pack`). σ_t and albedo are texture slots (texture.wgsl): a
// value, or a grid volume's record looked up at the point.
// - homogeneous (majorant 0): σ_t (times scale) constant; σ_s = albedo σ_t, constant where the
//   albedo is (`sigma_s`);
// - heterogeneous: σ_t(p) = scale × the slot's value, inside the box [lo, hi] alone, and the
//   majorant, scale × its largest value (Mitsuba's m_max_density).
struct Medium {
    sigma_t: vec3f,
    g: f32,
    albedo: vec3f,
    scale: f32,
    sigma_s: vec3f,
    majorant: f32,
    lo: vec3f,
    hi: vec3f,
}

// Medium k's record: the first MEDIUM_RECORD_FLOATS * NUM_MEDIA numbers of bsdf_data hold the
// media, before their grids and every BSDF's data.
fn medium_at(k: u32) -> Medium {
    let b = k * MEDIUM_RECORD_FLOATS;
    return Medium(
        vec3f(bsdf_data[b], bsdf_data[b + 1u], bsdf_data[b + 2u]),
        bsdf_data[b + 3u],
        vec3f(bsdf_data[b + 4u], bsdf_data[b + 5u], bsdf_data[b + 6u]),
        bsdf_data[b + 7u],
        vec3f(bsdf_data[b + 8u], bsdf_data[b + 9u], bsdf_data[b + 10u]),
        bsdf_data[b + 11u],
        vec3f(bsdf_data[b + 12u], bsdf_data[b + 13u], bsdf_data[b + 14u]),
        vec3f(bsdf_data[b + 16u], bsdf_data[b + 17u], bsdf_data[b + 18u]),
    );
}

fn is_heterogeneous(m: Medium) -> bool {
    return MAX_NULL_COLLISIONS > 0u && m.majorant > 0.0;
}

// A grid's lookup context: the world position alone (Mitsuba evaluates a volume at mi.p).
fn volume_context(p: vec3f) -> TextureEvalContext {
    return TextureEvalContext(vec2f(0.0), p, INVALID, vec2f(0.0));
}

// σ_t at p of a heterogeneous medium: scale × its volume's value (Mitsuba's
// get_scattering_coefficients).
fn medium_sigma_t_at(m: Medium, p: vec3f) -> vec3f {
    return m.scale * texture_slot(m.sigma_t, volume_context(p));
}

// σ_s at p, given σ_t there: a homogeneous medium's constant, else albedo(p) σ_t.
fn medium_sigma_s_at(m: Medium, p: vec3f, sigma_t: vec3f) -> vec3f {
    if (!is_heterogeneous(m) && m.albedo.x >= 0.0) {
        return m.sigma_s;
    }
    return sigma_t * texture_slot(m.albedo, volume_context(p));
}

// Beer-Lambert transmittance exp(-σ_t t) per channel over a distance t, which may be infinite:
// a channel that does not attenuate (σ_t = 0) transmits 1 there, not exp(-0 inf) = NaN.
fn medium_transmittance(sigma_t: vec3f, t: f32) -> vec3f {
    return exp(-select(sigma_t * t, vec3f(0.0), sigma_t == vec3f(0.0)));
}

// A free-flight sample along a ray segment of length t_surface (INFINITY for a ray that
// escapes) in a medium: whether it scatters before the surface, where, and the weight the
// path's throughput takes.
struct FreeFlight {
    t: f32,
    scattered: bool,
    weight: vec3f,
}

// Free-flight sampling from o along d: closed form in a homogeneous medium, delta tracking in
// a heterogeneous one (track_free_flight, whose further random numbers come from the stream
// `key`).
fn sample_free_flight(m: Medium, o: vec3f, d: vec3f, t_surface: f32, u_channel: f32, u_dist: f32, key: u32) -> FreeFlight {
    if (is_heterogeneous(m)) {
        return track_free_flight(m, o, d, t_surface, u_channel, u_dist, key);
    }
    return sample_homogeneous_flight(m, o, d, t_surface, u_channel, u_dist);
}

// Free-flight sampling with one-sample spectral MIS (pbrt-v4's and Mitsuba's volpathmis's
// balance over the channels): a channel c picked uniformly by u_channel, a distance
// t = -ln(1 - u_dist) / σ_t[c] drawn from its exponential. The density of the mixture is the
// mean over channels of σ_t[k] T_k(t), T_k = exp(-σ_t[k] t), and reaching the surface has the
// mean of T_k(t_surface); the weights are T σ_s / mean(σ_t T) at a scattering event and
// T / mean(T) at the surface, each at most 3 per channel, so every channel is unbiased
// whatever its σ_t, zero included (Mitsuba's volpath samples one channel per path, which
// differs only in variance).
fn sample_homogeneous_flight(m: Medium, o: vec3f, d: vec3f, t_surface: f32, u_channel: f32, u_dist: f32) -> FreeFlight {
    let c = min(u32(u_channel * 3.0), 2u);
    let sigma_c = m.sigma_t[c];
    // -ln(1 - u) / σ: infinite where the channel does not attenuate.
    var t = INFINITY;
    if (sigma_c > 0.0) {
        t = -log1m_stable(u_dist) / sigma_c;
    }
    if (t < t_surface) {
        let tr = medium_transmittance(m.sigma_t, t);
        let pdf = dot(m.sigma_t * tr, vec3f(1.0 / 3.0));
        let sigma_s = medium_sigma_s_at(m, o + d * t, m.sigma_t);
        return FreeFlight(t, true, select(vec3f(0.0), tr * sigma_s / pdf, pdf > 0.0));
    }
    let tr = medium_transmittance(m.sigma_t, t_surface);
    let p_pass = dot(tr, vec3f(1.0 / 3.0));
    return FreeFlight(t_surface, false, select(vec3f(0.0), tr / p_pass, p_pass > 0.0));
}

// The stretch [t0, t1] of the ray o + t d, 0 <= t <= t_max, inside the box [lo, hi] (slabs;
// an axis the ray runs parallel to keeps all or nothing); t0 >= t1 where it misses.
fn box_span(lo: vec3f, hi: vec3f, o: vec3f, d: vec3f, t_max: f32) -> vec2f {
    var t0 = 0.0;
    var t1 = t_max;
    for (var k = 0u; k < 3u; k++) {
        if (d[k] == 0.0) {
            if (o[k] < lo[k] || o[k] > hi[k]) {
                t1 = -1.0;
            }
        } else {
            let a = (lo[k] - o[k]) / d[k];
            let b = (hi[k] - o[k]) / d[k];
            t0 = max(t0, min(a, b));
            t1 = min(t1, max(a, b));
        }
    }
    return vec2f(t0, t1);
}

// Random number k of a tracking stream (delta and ratio tracking meet a number of collisions no
// sampler dimension can budget for; pbrt-v4 hashes its media's RNG likewise).
fn tracking_u(key: u32, k: u32) -> f32 {
    return u32_to_unit_float(hash2(key, k));
}

// A shadow ray's tracking stream: a hash of its origin and direction (pbrt-v4 seeds its
// transmittance RNG from the ray's end points likewise).
fn ray_key(o: vec3f, d: vec3f) -> u32 {
    let b = bitcast<vec3u>(o);
    let e = bitcast<vec3u>(d);
    return hash4(b.x ^ e.z, b.y, b.z, hash2(e.x, e.y));
}

// Mean over the channels.
fn mean3(v: vec3f) -> f32 {
    return dot(v, vec3f(1.0 / 3.0));
}

// Delta tracking with spectral weights, Mitsuba's volpath in a heterogeneous medium
// (is_spectral): tentative collisions at exponential distances of rate m (the majorant), from
// where the ray enters the medium's box; at each, with σ_n = m - σ_t(p), a null collision with
// probability mean(σ_n) / m, the weight taking σ_n / mean(σ_n), and the path going on; else a
// real one, where light scatters, the weight taking σ_s / mean(σ_t). Past the box or the
// surface the flight reaches the surface with its weight. The first collision's distance and
// choice take the segment's sampler dimensions, the others the stream `key`.
fn track_free_flight(m: Medium, o: vec3f, d: vec3f, t_surface: f32, u_event_0: f32, u_dist_0: f32, key: u32) -> FreeFlight {
    let span = box_span(m.lo, m.hi, o, d, t_surface);
    var weight = vec3f(1.0);
    if (!(span.x < span.y)) {
        return FreeFlight(t_surface, false, weight);
    }
    var t = span.x;
    var u_dist = u_dist_0;
    var u_event = u_event_0;
    for (var k = 0u; k < MAX_NULL_COLLISIONS; k++) {
        t -= log1m_stable(u_dist) / m.majorant;
        if (t >= span.y) {
            return FreeFlight(t_surface, false, weight);
        }
        let p = o + d * t;
        let sigma_t = medium_sigma_t_at(m, p);
        let sigma_n = max(vec3f(m.majorant) - sigma_t, vec3f(0.0));
        let p_null = mean3(sigma_n) / m.majorant;
        if (u_event >= p_null) {
            return FreeFlight(t, true, weight * medium_sigma_s_at(m, p, sigma_t) / mean3(sigma_t));
        }
        weight *= sigma_n / mean3(sigma_n);
        u_dist = tracking_u(key, 2u * k);
        u_event = tracking_u(key, 2u * k + 1u);
    }
    // More collisions than MAX_NULL_COLLISIONS (probability below 1e-15): the path ends.
    return FreeFlight(t_surface, false, vec3f(0.0));
}

// The transmittance of a medium along o + t d, 0 <= t <= length: Beer-Lambert in a
// homogeneous medium; in a heterogeneous one ratio tracking, Mitsuba's volpath's estimate
// (each tentative collision at rate m inside the box multiplies it by σ_n / m per channel),
// from a stream keyed by the ray itself (ray_key). `budget`: the null collisions the shadow
// ray may still meet (a straight line crosses each medium's box once, so one budget of
// MAX_NULL_COLLISIONS serves all its stretches); where it runs out, the ray counts as shadowed.
fn medium_segment_transmittance(m: Medium, o: vec3f, d: vec3f, length: f32, budget: ptr<function, u32>) -> vec3f {
    if (!is_heterogeneous(m)) {
        return medium_transmittance(m.sigma_t, length);
    }
    let key = ray_key(o, d);
    let span = box_span(m.lo, m.hi, o, d, length);
    var tr = vec3f(1.0);
    if (!(span.x < span.y)) {
        return tr;
    }
    var t = span.x;
    for (var k = 0u; k < MAX_NULL_COLLISIONS; k++) {
        if (*budget == 0u) {
            // More collisions than MAX_NULL_COLLISIONS (probability below 1e-15).
            return vec3f(0.0);
        }
        *budget -= 1u;
        t -= log1m_stable(tracking_u(key, k)) / m.majorant;
        if (t >= span.y) {
            return tr;
        }
        let sigma_t = medium_sigma_t_at(m, o + d * t);
        tr *= max(vec3f(m.majorant) - sigma_t, vec3f(0.0)) / m.majorant;
        if (max3(tr) <= 0.0) {
            return tr;
        }
    }
    return vec3f(0.0);
}

// Whether material i bounds a medium (Material::is_medium_boundary).
fn is_medium_boundary(i: u32) -> bool {
    return (material_record(i).flags & MATERIAL_MEDIUM_BOUNDARY) != 0u;
}

// The medium a ray leaving a surface of material i along d is in (Mitsuba's target_medium):
// the exterior where d points to the side of the geometric normal n, else the interior; the
// current medium where the surface bounds none.
fn medium_after(i: u32, n: vec3f, d: vec3f, current: u32) -> u32 {
    if (!is_medium_boundary(i)) {
        return current;
    }
    let f = material_record(i).flags;
    return select((f >> MEDIUM_INTERIOR_SHIFT) & 0xffu, (f >> MEDIUM_EXTERIOR_SHIFT) & 0xffu, dot(d, n) > 0.0);
}
