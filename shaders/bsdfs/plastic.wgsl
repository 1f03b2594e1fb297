// bsdfs/plastic.wgsl — Mitsuba's smooth `plastic` term for term (plastic.cpp): a diffuse base
// under a smooth dielectric coating of relative index eta. A delta lobe reflects the coating's
// Fresnel reflectance F(cos_i) in the mirror direction (times `specular`); the light that enters
// scatters diffusely inside, the internal reflections summed in closed form, and leaves:
//
//   f(wi, wo) = R / (1 - fdr_int) (1 - F(cos_i)) (1 - F(cos_o)) / (pi eta^2)
//
// (R fdr_int for fdr_int with `nonlinear`). The own sampling picks the delta lobe with Mitsuba's
// probability F w / (F w + (1 - F)(1 - w)) (w: the specular sampling weight from the albedos),
// else a cosine-weighted direction (`--lobe-selection fixed`: with probability w alone).
// One-sided: n_s is turned towards wo by the integrator.

struct Plastic {
    diffuse: vec3f,
    eta: f32,
    specular: vec3f,
    // Mitsuba's m_specular_sampling_weight: mean(specular) / (mean(diffuse) + mean(specular)).
    specular_sampling_weight: f32,
    // The diffuse Fresnel reflectance seen from inside the coating (host: plastic.rs).
    fdr_int: f32,
    nonlinear: bool,
}

// The parameter block as src/scene/bsdfs/plastic.rs packs it: p0 = (diffuse, eta),
// p1 = (specular, specular_sampling_weight), p2 = (fdr_int, nonlinear, 0, 0).
fn plastic_of(b: Bsdf) -> Plastic {
    return Plastic(b.p0.xyz, b.p0.w, b.p1.xyz, b.p1.w, b.p2.x, b.p2.y != 0.0);
}

// The probability of the delta lobe given the coating's Fresnel reflectance f_i at wo: with
// LOBES_FIXED the specular sampling weight alone; with LOBES_FRESNEL (Mitsuba's) weighted by
// f_i (0 where both lobes' shares are 0: an index-matched coating on a black base, which
// scatters nothing).
fn plastic_specular_prob(p: Plastic, f_i: f32) -> f32 {
    if (LOBE_SELECTION == LOBES_FIXED) {
        return p.specular_sampling_weight;
    }
    let prob_specular = f_i * p.specular_sampling_weight;
    let prob_diffuse = (1.0 - f_i) * (1.0 - p.specular_sampling_weight);
    let total = prob_specular + prob_diffuse;
    return select(0.0, prob_specular / total, total > 0.0);
}

// The diffuse lobe's f (without the cosine) for the cosines of wo and wi against the normal
// (both > 0), and the coating's reflectance f_i at wo.
fn eval_plastic_diffuse(p: Plastic, f_i: f32, cos_theta_o: f32) -> vec3f {
    let f_o = fresnel_dielectric(cos_theta_o, p.eta).r;
    var denominator = vec3f(1.0 - p.fdr_int);
    if (p.nonlinear) {
        denominator = 1.0 - p.diffuse * p.fdr_int;
    }
    return p.diffuse / denominator * (INV_PI / (p.eta * p.eta) * (1.0 - f_i) * (1.0 - f_o));
}

// f(wi, wo) of the diffuse lobe and the own strategy's density at wi: the cosine density
// times the probability of not picking the delta lobe.
fn eval_pdf_plastic(p: Plastic, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let cos_theta_i = dot(wo, n_s);
    let cos_theta_o = dot(wi, n_s);
    if (cos_theta_i <= 0.0 || cos_theta_o <= 0.0) {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let f_i = fresnel_dielectric(cos_theta_i, p.eta).r;
    let prob_diffuse = 1.0 - plastic_specular_prob(p, f_i);
    return BsdfEval(eval_plastic_diffuse(p, f_i, cos_theta_o), pdf_cosine_hemisphere(cos_theta_o) * prob_diffuse);
}

// The delta lobe when u_lobe < its probability (weight F / prob times `specular`, pdf 0 as for
// every delta), else a cosine-weighted direction weighted by path_weight.
fn sample_plastic(p: Plastic, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let frame = frame_from_normal(n_s);
    let wo_l = frame_to_local(frame, wo);
    if (wo_l.z <= 0.0) {
        return BsdfSample(n_s, 0.0, vec3f(0.0), false, 1.0);
    }
    let f_i = fresnel_dielectric(wo_l.z, p.eta).r;
    let prob_specular = plastic_specular_prob(p, f_i);
    if (u_lobe < prob_specular) {
        return BsdfSample(frame_to_world(frame, vec3f(-wo_l.x, -wo_l.y, wo_l.z)), 0.0, p.specular * (f_i / prob_specular), true, 1.0);
    }
    let wi_l = square_to_cosine_hemisphere(u_dir);
    let pdf = pdf_cosine_hemisphere(wi_l.z) * (1.0 - prob_specular);
    let f = eval_plastic_diffuse(p, f_i, wi_l.z);
    return BsdfSample(frame_to_world(frame, wi_l), pdf, path_weight(f, wi_l.z, pdf), false, 1.0);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_plastic_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    return eval_pdf_plastic(plastic_of(b), n_s, wo, wi);
}

fn sample_plastic_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_plastic(plastic_of(b), n_s, wo, u_dir, u_lobe);
}

// The probability with which sample_plastic picks the delta lobe (it does when u_lobe is below).
fn delta_lobe_prob_plastic_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f) -> f32 {
    let p = plastic_of(b);
    let cos_theta_i = dot(wo, n_s);
    if (cos_theta_i <= 0.0) {
        return 0.0;
    }
    return plastic_specular_prob(p, fresnel_dielectric(cos_theta_i, p.eta).r);
}
