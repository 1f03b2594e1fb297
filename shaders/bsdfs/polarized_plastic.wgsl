// bsdfs/polarized_plastic.wgsl — Mitsuba's `pplastic` as its RGB variants evaluate it
// (pplastic.cpp, the unpolarised branch; host: src/scene/bsdfs/polarized_plastic.rs): a rough
// specular reflection plus a diffuse lobe attenuated by two smooth refractions,
//
//   f_spec(wi, wo) = s F(wo . h) D(h) G(wo, wi, h) / (4 cos_o cos_i),   h = (wi + wo) / |wi + wo|,
//   f_diff(wi, wo) = R (1 - F(cos_o)) (1 - F(cos_i)) / pi,
//
// F the dielectric Fresnel reflectance of relative index eta. The own sampling picks the
// specular lobe with the fixed probability w (the specular sampling weight from the albedos,
// Mitsuba's), reflecting about a normal of the pipeline's microfacet strategy, else a
// cosine-weighted direction. One-sided: n_s is turned towards wo by the integrator.

struct PolarizedPlastic {
    diffuse: vec3f,
    eta: f32,
    specular: vec3f,
    specular_sampling_weight: f32,
    alpha_uv: vec2f,
    distribution: u32,
}

// The parameter block as src/scene/bsdfs/polarized_plastic.rs packs it: p0 = (diffuse, eta),
// p1 = (specular, specular_sampling_weight), p2 = (alpha_u, distribution, 0, alpha_v), alpha_v
// the isotropic sentinel -0.0 where alpha_u serves both (microfacet.wgsl's alpha_uv_of).
fn polarized_plastic_of(b: Bsdf) -> PolarizedPlastic {
    return PolarizedPlastic(b.p0.xyz, b.p0.w, b.p1.xyz, b.p1.w, alpha_uv_of(b.p2.x, b.p2.w), u32(b.p2.y));
}

// f(wi, wo) (both lobes) and the own strategy's density at wi, in the local frame (+z the
// shading normal, x along dp/du: bsdf_frame): zero unless both directions are above the
// surface; the specular lobe's density is the normal's density times the Jacobian of
// reflection, 1 / (4 wi . h) (zero where either direction sees the normal's back, as Mitsuba's
// pdf), the diffuse lobe's the cosine density, each times the probability of its lobe.
fn eval_pdf_polarized_plastic_local(p: PolarizedPlastic, wo: vec3f, wi: vec3f) -> BsdfEval {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let h = normalize(wo + wi);
    let d = eval_microfacet_d_uv(h, p.alpha_uv, p.distribution);
    let g = smith_g_uv(wo, wi, h, p.alpha_uv, p.distribution);
    let f = fresnel_dielectric(dot(wo, h), p.eta).r;
    let specular = p.specular * (f * d * g / (4.0 * wo.z * wi.z));
    // The two smooth refractions' transmittances, into the base at wi and out at wo.
    let t_o = 1.0 - fresnel_dielectric(wo.z, p.eta).r;
    let t_i = 1.0 - fresnel_dielectric(wi.z, p.eta).r;
    let diffuse = p.diffuse * (INV_PI * t_o * t_i);
    let w = p.specular_sampling_weight;
    let pdf_specular = select(0.0, pdf_microfacet_uv(wo, h, p.alpha_uv, p.distribution) / (4.0 * dot(wi, h)),
                              dot(wo, h) > 0.0 && dot(wi, h) > 0.0);
    let pdf = w * pdf_specular + (1.0 - w) * pdf_cosine_hemisphere(wi.z);
    return BsdfEval(specular + diffuse, pdf);
}

// The specular lobe when u_lobe is below w (a direction reflected about a normal of the
// pipeline's microfacet strategy), else a cosine-weighted one; weighted by path_weight with the
// whole BSDF and the mixture's density, as Mitsuba's.
fn sample_polarized_plastic(p: PolarizedPlastic, frame: Frame, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let wo_l = frame_to_local(frame, wo);
    if (wo_l.z <= 0.0) {
        return BsdfSample(frame.n, 0.0, vec3f(0.0), false, 1.0);
    }
    var wi_l: vec3f;
    if (u_lobe < p.specular_sampling_weight) {
        let m = sample_microfacet_uv(wo_l, u_dir, p.alpha_uv, p.distribution).m;
        wi_l = 2.0 * dot(wo_l, m) * m - wo_l;
    } else {
        wi_l = square_to_cosine_hemisphere(u_dir);
    }
    let e = eval_pdf_polarized_plastic_local(p, wo_l, wi_l);
    return BsdfSample(frame_to_world(frame, wi_l), e.pdf, path_weight(e.f, wi_l.z, e.pdf), false, 1.0);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_polarized_plastic_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let frame = bsdf_frame(b, n_s);
    return eval_pdf_polarized_plastic_local(polarized_plastic_of(b), frame_to_local(frame, wo), frame_to_local(frame, wi));
}

fn sample_polarized_plastic_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_polarized_plastic(polarized_plastic_of(b), bsdf_frame(b, n_s), wo, u_dir, u_lobe);
}
