// bsdfs/conductor.wgsl — Mitsuba's smooth `conductor`: a mirror, a delta lobe (eval and pdf
// are 0 for every given wi), with the exact Fresnel term of a complex index eta + i k
// (microfacet.wgsl's fresnel_conductor). `Conductor` also holds the rough conductor's roughness
// (alpha_u, alpha_v).

struct Conductor {
    // Complex index of refraction eta + i k, per channel.
    eta: vec3f,
    k: vec3f,
    // Mitsuba's specular_reflectance: a factor on the Fresnel term.
    reflectance: vec3f,
    alpha_uv: vec2f,
    distribution: u32,
}

// The mirror direction, weighted by F(cos(theta_o)) times the reflectance, whatever the
// pipeline's strategy (no other strategy can find a delta lobe).
fn sample_conductor(c: Conductor, n_s: vec3f, wo: vec3f) -> BsdfSample {
    let cos_o = dot(wo, n_s);
    let weight = select(vec3f(0.0), fresnel_conductor(cos_o, c.eta, c.k) * c.reflectance, cos_o > 0.0);
    return BsdfSample(reflect_about(wo, n_s), 0.0, weight, true, 1.0);
}

// The parameter block as src/scene/bsdfs/conductor.rs packs it: p0 = (eta, alpha),
// p1 = (k, the distribution's number), p2 = (reflectance, alpha_v: -0.0 where isotropic,
// src/scene/bsdfs/rough_conductor.rs); the smooth conductor has alpha 0 (its distribution is
// unused).
fn conductor_of(b: Bsdf) -> Conductor {
    return Conductor(b.p0.xyz, b.p1.xyz, b.p2.xyz, alpha_uv_of(b.p0.w, b.p2.w), u32(b.p1.w));
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs): no direction but the
// mirror's has a density.
fn eval_pdf_conductor_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    return BsdfEval(vec3f(0.0), 0.0);
}

fn sample_conductor_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_conductor(conductor_of(b), n_s, wo);
}
