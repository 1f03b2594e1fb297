// bsdfs/rough_plastic.wgsl — Mitsuba's `roughplastic` term for term (roughplastic.cpp): a
// diffuse base under a rough dielectric coating of relative index eta. The coating reflects by
// Torrance-Sparrow microfacets with the dielectric Fresnel term (times `specular`),
//
//   f_spec(wi, wo) = F(wo . h) D(h) G(wo, wi, h) / (4 cos_o cos_i),   h = (wi + wo) / |wi + wo|;
//
// the light it transmits scatters diffusely inside and leaves,
//
//   f_diff(wi, wo) = R / (1 - R_int) T(cos_o) T(cos_i) / (pi eta^2)
//
// (R R_int for R_int with `nonlinear`), with the coating's transmittance T and internal
// reflectance R_int precomputed by the host (src/scene/bsdfs/rough_plastic.rs) into the BSDF
// data: T at ROUGH_PLASTIC_TABLE_RES cosines k / (RES - 1), then R_int. The own sampling picks
// the coating's lobe with probability (1 - T(cos_o)) w / ((1 - T(cos_o)) w + T(cos_o)(1 - w))
// (w: the specular sampling weight from the albedos; `--lobe-selection fixed`: w alone), its
// normal drawn by the pipeline's microfacet strategy, else a cosine-weighted direction.
// One-sided: n_s is turned towards wo by the integrator.

struct RoughPlastic {
    diffuse: vec3f,
    eta: f32,
    specular: vec3f,
    specular_sampling_weight: f32,
    alpha: f32,
    distribution: u32,
    nonlinear: bool,
    // Where its data start in bsdf_data.
    table: u32,
}

// The parameter block as src/scene/bsdfs/rough_plastic.rs packs it: p0 = (diffuse, eta),
// p1 = (specular, specular_sampling_weight), p2 = (alpha, distribution, nonlinear, table).
fn rough_plastic_of(b: Bsdf) -> RoughPlastic {
    return RoughPlastic(b.p0.xyz, b.p0.w, b.p1.xyz, b.p1.w, b.p2.x, u32(b.p2.y), b.p2.z != 0.0, u32(b.p2.w));
}

// The coating's transmittance at incidence cos_theta in [0, 1]: the table interpolated linearly
// between its entries (Mitsuba's lerp_gather).
fn rough_plastic_transmittance(p: RoughPlastic, cos_theta: f32) -> f32 {
    let x = cos_theta * f32(ROUGH_PLASTIC_TABLE_RES - 1u);
    let i = min(u32(x), ROUGH_PLASTIC_TABLE_RES - 2u);
    let v0 = bsdf_data[p.table + i];
    let v1 = bsdf_data[p.table + i + 1u];
    return mix(v0, v1, x - f32(i));
}

// The probability of the coating's lobe given its transmittance t_o at wo: with LOBES_FIXED the
// specular sampling weight alone; with LOBES_FRESNEL (Mitsuba's) weighted by the coating's
// reflectance 1 - t_o (0 where both lobes' shares are 0).
fn rough_plastic_specular_prob(p: RoughPlastic, t_o: f32) -> f32 {
    if (LOBE_SELECTION == LOBES_FIXED) {
        return p.specular_sampling_weight;
    }
    let prob_specular = (1.0 - t_o) * p.specular_sampling_weight;
    let prob_diffuse = t_o * (1.0 - p.specular_sampling_weight);
    let total = prob_specular + prob_diffuse;
    return select(0.0, prob_specular / total, total > 0.0);
}

// f(wi, wo) (both lobes) and the own strategy's density at wi, in the local frame of n_s
// (+z): zero unless both directions are above the surface; the coating lobe's density is the
// normal's density times the Jacobian of reflection, 1 / (4 wi . h), the base's the cosine
// density, each times the probability of its lobe.
fn eval_pdf_rough_plastic_local(p: RoughPlastic, wo: vec3f, wi: vec3f) -> BsdfEval {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let h = normalize(wo + wi);
    let d = eval_microfacet_d(h, p.alpha, p.distribution);
    let g = smith_g_uv(wo, wi, h, vec2f(p.alpha), p.distribution);
    let f = fresnel_dielectric(dot(wo, h), p.eta).r;
    let specular = p.specular * (f * d * g / (4.0 * wo.z * wi.z));
    let t_o = rough_plastic_transmittance(p, wo.z);
    let t_i = rough_plastic_transmittance(p, wi.z);
    let internal_reflectance = bsdf_data[p.table + ROUGH_PLASTIC_TABLE_RES];
    var denominator = vec3f(1.0 - internal_reflectance);
    if (p.nonlinear) {
        denominator = 1.0 - p.diffuse * internal_reflectance;
    }
    let diffuse = p.diffuse / denominator * (INV_PI / (p.eta * p.eta) * t_o * t_i);
    let prob_specular = rough_plastic_specular_prob(p, t_o);
    let pdf_specular = pdf_microfacet(wo, h, p.alpha, p.distribution) / (4.0 * dot(wi, h));
    let pdf = prob_specular * pdf_specular + (1.0 - prob_specular) * pdf_cosine_hemisphere(wi.z);
    return BsdfEval(specular + diffuse, pdf);
}

// The coating's lobe when u_lobe is below its probability (a direction reflected about a normal
// of the pipeline's microfacet strategy), else a cosine-weighted one; weighted by path_weight
// with the whole BSDF and the mixture's density, as Mitsuba's.
fn sample_rough_plastic(p: RoughPlastic, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let frame = frame_from_normal(n_s);
    let wo_l = frame_to_local(frame, wo);
    if (wo_l.z <= 0.0) {
        return BsdfSample(n_s, 0.0, vec3f(0.0), false, 1.0);
    }
    let prob_specular = rough_plastic_specular_prob(p, rough_plastic_transmittance(p, wo_l.z));
    var wi_l: vec3f;
    if (u_lobe < prob_specular) {
        let m = sample_microfacet(wo_l, u_dir, p.alpha, p.distribution).m;
        wi_l = 2.0 * dot(wo_l, m) * m - wo_l;
    } else {
        wi_l = square_to_cosine_hemisphere(u_dir);
    }
    let e = eval_pdf_rough_plastic_local(p, wo_l, wi_l);
    return BsdfSample(frame_to_world(frame, wi_l), e.pdf, path_weight(e.f, wi_l.z, e.pdf), false, 1.0);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_rough_plastic_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let frame = frame_from_normal(n_s);
    return eval_pdf_rough_plastic_local(rough_plastic_of(b), frame_to_local(frame, wo), frame_to_local(frame, wi));
}

fn sample_rough_plastic_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_rough_plastic(rough_plastic_of(b), n_s, wo, u_dir, u_lobe);
}
