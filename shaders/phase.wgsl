// phase.wgsl — phase functions of participating media (host: src/scene/media/mod.rs): how a
// scattering event in a medium redistributes light over the sphere of directions. One kind,
// Henyey and Greenstein's, with isotropic scattering as its g = 0 (Mitsuba's `isotropic` and
// `hg`, src/phase/). Densities are per steradian; the phase function is its own sampling density,
// so a sampled direction's weight is 1.
//
// Conventions: `d` is the direction light travelled in before the event (the ray's direction),
// `wi` the direction it leaves in; cos θ = dot(d, wi), and g > 0 scatters forward.

struct PhaseSample {
    wi: vec3f,
    // Solid-angle density of wi, which equals the phase function's value there.
    pdf: f32,
}

// Below this |g| the lobe is sampled as isotropic (Mitsuba's hg.cpp does the same): the
// inversion's 1 / (2 g) loses all precision.
const PHASE_ISOTROPIC_G: f32 = 1e-3;

// Henyey-Greenstein's density at cos θ: (1 - g²) / (4π (1 + g² - 2 g cos θ)^{3/2}).
fn eval_hg_phase(g: f32, cos_theta: f32) -> f32 {
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * PI * denom * sqrt(denom));
}

fn pdf_hg_phase(g: f32, d: vec3f, wi: vec3f) -> f32 {
    return eval_hg_phase(g, dot(d, wi));
}

// Inverts the lobe's distribution of cos θ (u.x; u.x = 1 is straight ahead, as Mitsuba's hg),
// then turns uniformly about d (u.y): Mitsuba's sample, term for term.
fn sample_hg_phase(g: f32, d: vec3f, u: vec2f) -> PhaseSample {
    var cos_theta = 1.0 - 2.0 * u.x;
    if (abs(g) >= PHASE_ISOTROPIC_G) {
        let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
        cos_theta = clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
    }
    let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
    let local = spherical_direction(cos_theta, sin_theta, 2.0 * PI * u.y);
    let wi = normalize(frame_to_world(frame_from_normal(d), local));
    return PhaseSample(wi, eval_hg_phase(g, cos_theta));
}
