// bsdfs/dielectric.wgsl — Mitsuba's smooth `dielectric` term for term (dielectric.cpp and
// fresnel.h): an interface of relative index eta = int_ior / ext_ior with two delta lobes, the
// mirror direction with the Fresnel reflectance F of unpolarised light and the refracted one
// with 1 - F, each picked with its own probability (eval and pdf are 0 for every given wi). In
// radiance transport the refracted weight carries eta_ti^2, the compression of solid angle
// across the interface (Mitsuba's TransportMode::Radiance factor).

struct Dielectric {
    // eta = int_ior / ext_ior (the inside is against the surface normal).
    eta: f32,
    // Mitsuba's specular_reflectance and specular_transmittance: factors on the two lobes.
    reflectance: vec3f,
    transmittance: vec3f,
}

// The parameter block as src/scene/bsdfs/dielectric.rs packs it: p0 = (reflectance, eta),
// p1 = (transmittance, 0).
fn dielectric_of(b: Bsdf) -> Dielectric {
    return Dielectric(b.p0.w, b.p0.xyz, b.p1.xyz);
}

// One of the two lobes, by u_lobe against F: the mirror direction with weight `reflectance`,
// or the refracted one with weight `transmittance` eta_ti^2 (the lobe's mass over its
// probability is 1 for both). n_s is turned towards wo; `inside` says that wo is against the
// surface normal, where the relative index is 1 / eta.
fn sample_dielectric(d: Dielectric, inside: bool, n_s: vec3f, wo: vec3f, u_lobe: f32) -> BsdfSample {
    let frame = frame_from_normal(n_s);
    let wo_l = frame_to_local(frame, wo);
    // The cosine in the frame of the surface normal itself, as Mitsuba's Frame3f::cos_theta.
    let f = fresnel_dielectric(select(wo_l.z, -wo_l.z, inside), d.eta);
    if (u_lobe < f.r) {
        return BsdfSample(frame_to_world(frame, vec3f(-wo_l.x, -wo_l.y, wo_l.z)), 0.0, d.reflectance, true, 1.0);
    }
    // Refraction: the tangential part scaled by eta_ti and reversed, the normal part through
    // the surface (n_s is on wo's side, so the refracted direction is below it).
    let wi_l = vec3f(-f.eta_ti * wo_l.x, -f.eta_ti * wo_l.y, -abs(f.cos_theta_t));
    return BsdfSample(frame_to_world(frame, wi_l), 0.0, d.transmittance * (f.eta_ti * f.eta_ti), true, f.eta_it);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs): no direction but the
// two lobes' has a density.
fn eval_pdf_dielectric_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    return BsdfEval(vec3f(0.0), 0.0);
}

fn sample_dielectric_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_dielectric(dielectric_of(b), b.inside, n_s, wo, u_lobe);
}
