// medium.wgsl — homogeneous participating media (host: src/scene/media/mod.rs; Mitsuba's
// `homogeneous`, src/media/homogeneous.cpp): their records, free-flight sampling and
// transmittance, and which medium a ray is in after crossing a surface.

// Media in the scene (SceneFeatures::num_media): 0 compiles every volumetric step out, and the
// path tracer is integrator.wgsl's trace_path alone.
override NUM_MEDIA: u32 = 0u;
// The medium the camera sits in (Scene::camera_medium), NO_MEDIUM for none.
override CAMERA_MEDIUM: u32 = NO_MEDIUM;

// A homogeneous medium: extinction σ_t and scattering σ_s = albedo σ_t per channel (per unit
// length), and its phase function's mean cosine g (phase.wgsl).
struct HomogeneousMedium {
    sigma_t: vec3f,
    g: f32,
    sigma_s: vec3f,
}

// Medium k's record: the first MEDIUM_RECORD_FLOATS * NUM_MEDIA numbers of bsdf_data hold the
// media (`Medium::pack`: σ_t, g, σ_s, 0), before every BSDF's data.
fn medium_at(k: u32) -> HomogeneousMedium {
    let b = k * MEDIUM_RECORD_FLOATS;
    return HomogeneousMedium(
        vec3f(bsdf_data[b], bsdf_data[b + 1u], bsdf_data[b + 2u]),
        bsdf_data[b + 3u],
        vec3f(bsdf_data[b + 4u], bsdf_data[b + 5u], bsdf_data[b + 6u]),
    );
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

// Free-flight sampling with one-sample spectral MIS (pbrt-v4's and Mitsuba's volpathmis's
// balance over the channels): a channel c picked uniformly by u_channel, a distance
// t = -ln(1 - u_dist) / σ_t[c] drawn from its exponential. The density of the mixture is the
// mean over channels of σ_t[k] T_k(t), T_k = exp(-σ_t[k] t), and reaching the surface has the
// mean of T_k(t_surface); the weights are T σ_s / mean(σ_t T) at a scattering event and
// T / mean(T) at the surface, each at most 3 per channel, so every channel is unbiased
// whatever its σ_t, zero included (Mitsuba's volpath samples one channel per path, which
// differs only in variance).
fn sample_free_flight(medium: HomogeneousMedium, t_surface: f32, u_channel: f32, u_dist: f32) -> FreeFlight {
    let c = min(u32(u_channel * 3.0), 2u);
    let sigma_c = medium.sigma_t[c];
    // -ln(1 - u) / σ: infinite where the channel does not attenuate.
    var t = INFINITY;
    if (sigma_c > 0.0) {
        t = -log1m_stable(u_dist) / sigma_c;
    }
    if (t < t_surface) {
        let tr = medium_transmittance(medium.sigma_t, t);
        let pdf = dot(medium.sigma_t * tr, vec3f(1.0 / 3.0));
        return FreeFlight(t, true, select(vec3f(0.0), tr * medium.sigma_s / pdf, pdf > 0.0));
    }
    let tr = medium_transmittance(medium.sigma_t, t_surface);
    let p_pass = dot(tr, vec3f(1.0 / 3.0));
    return FreeFlight(t_surface, false, select(vec3f(0.0), tr / p_pass, p_pass > 0.0));
}

// Whether material i bounds a medium (Material::is_medium_boundary).
fn is_medium_boundary(i: u32) -> bool {
    return (materials[i].flags & MATERIAL_MEDIUM_BOUNDARY) != 0u;
}

// The medium a ray leaving a surface of material i along d is in (Mitsuba's target_medium):
// the exterior where d points to the side of the geometric normal n, else the interior; the
// current medium where the surface bounds none.
fn medium_after(i: u32, n: vec3f, d: vec3f, current: u32) -> u32 {
    if (!is_medium_boundary(i)) {
        return current;
    }
    let f = materials[i].flags;
    return select((f >> MEDIUM_INTERIOR_SHIFT) & 0xffu, (f >> MEDIUM_EXTERIOR_SHIFT) & 0xffu, dot(d, n) > 0.0);
}
