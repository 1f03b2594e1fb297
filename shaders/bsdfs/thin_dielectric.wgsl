// bsdfs/thin_dielectric.wgsl — Mitsuba's `thindielectric` term for term (thindielectric.cpp): a
// pane of two parallel interfaces of relative index eta, infinitely close. Light reflects in
// the mirror direction with R' = 2 R / (1 + R), the Fresnel reflectance R = F(|cos_i|) with all
// the internal reflections summed (R + T R T + T R^3 T + ...), or passes straight through
// (wi = -wo: the two refractions cancel) with 1 - R'. Two delta lobes, each picked with its own
// probability, so a sample's weight is the lobe's factor alone; both sides alike.

struct ThinDielectric {
    eta: f32,
    // Mitsuba's specular_reflectance and specular_transmittance: factors on the two lobes.
    reflectance: vec3f,
    transmittance: vec3f,
}

// The parameter block as src/scene/bsdfs/thin_dielectric.rs packs it: p0 = (reflectance, eta),
// p1 = (transmittance, 0).
fn thin_dielectric_of(b: Bsdf) -> ThinDielectric {
    return ThinDielectric(b.p0.w, b.p0.xyz, b.p1.xyz);
}

// The pane's reflectance R' at |cos_i| with its internal reflections summed.
fn thin_dielectric_reflectance(d: ThinDielectric, cos_theta_i: f32) -> f32 {
    let r = fresnel_dielectric(abs(cos_theta_i), d.eta).r;
    return r * (2.0 / (1.0 + r));
}

// The mirror direction when u_lobe <= R' (Mitsuba's test), else straight through.
fn sample_thin_dielectric(d: ThinDielectric, n_s: vec3f, wo: vec3f, u_lobe: f32) -> BsdfSample {
    let cos_theta_i = dot(wo, n_s);
    if (u_lobe <= thin_dielectric_reflectance(d, cos_theta_i)) {
        return BsdfSample(2.0 * cos_theta_i * n_s - wo, 0.0, d.reflectance, true, 1.0);
    }
    return BsdfSample(-wo, 0.0, d.transmittance, true, 1.0);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs): no direction but the
// two lobes' has a density.
fn eval_pdf_thin_dielectric_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    return BsdfEval(vec3f(0.0), 0.0);
}

fn sample_thin_dielectric_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_thin_dielectric(thin_dielectric_of(b), n_s, wo, u_lobe);
}
