// bsdfs/rough_dielectric.wgsl — Mitsuba's `roughdielectric` term for term (roughdielectric.cpp;
// Walter et al. 2007): reflection and refraction about microfacet normals m of the
// distributions in microfacet.wgsl, with the Fresnel term of unpolarised light. Everything is
// computed in the frame of n_s, which the integrator turns towards wo (so cos_o > 0), with the
// relative index seen from wo's side (eta, or 1 / eta where wo is inside): Mitsuba's formulas
// for cos_o < 0 are the mirror image of these. With eta that index,
//   reflection (wi.z > 0, m = normalize(wo + wi)):
//     f |cos_i| = F(wo . m) D(m) G(wo, wi, m) / (4 cos_o),
//   refraction (wi.z < 0, m = normalize(wo + eta wi), turned up):
//     f |cos_i| = (1 - F) D G |(wo . m)(wi . m)| / (cos_o (wo . m + eta wi . m)^2)
//   (radiance transport: Mitsuba's inv_eta^2 scale times its eta^2 numerator);
// the density: the normal's (the pipeline's microfacet strategy) times F or 1 - F, times the
// Jacobian of reflection 1 / (4 wi . m) or of refraction eta^2 |wi . m| / (wo . m + eta wi . m)^2.
// The ndf strategy samples and evaluates with Walter's widened roughness alpha (1.2 - 0.2
// sqrt(cos_o)), as Mitsuba does without sample_visible.

struct RoughDielectric {
    eta: f32,
    reflectance: vec3f,
    transmittance: vec3f,
    // (alpha_u, alpha_v).
    alpha_uv: vec2f,
    distribution: u32,
}

// The parameter block as src/scene/bsdfs/rough_dielectric.rs packs it: p0 = (reflectance, eta),
// p1 = (transmittance, alpha), p2 = (distribution, alpha_v: -0.0 where isotropic, 0, 0).
fn rough_dielectric_of(b: Bsdf) -> RoughDielectric {
    return RoughDielectric(b.p0.w, b.p0.xyz, b.p1.xyz, alpha_uv_of(b.p1.w, b.p2.y), u32(b.p2.x));
}

// The roughness normals are sampled with: Walter's widening of both alphas for the ndf strategy
// (a researcher's microfacet technique gets the material's own).
fn rough_dielectric_sample_alpha(d: RoughDielectric, cos_o: f32) -> vec2f {
    if (MICROFACET_SAMPLING == MICROFACET_NDF && !(BSDF_TECHNIQUE && BSDF_TECHNIQUE_MICROFACET)) {
        return d.alpha_uv * (1.2 - 0.2 * sqrt(abs(cos_o)));
    }
    return d.alpha_uv;
}

struct RoughDielectricEval {
    f_cos: vec3f,
    pdf: f32,
}

// f |cos_i| and the own strategy's density at wi, in the local frame of n_s (wo.z > 0), for
// the relative index eta seen from wo's side.
fn eval_pdf_rough_dielectric_local(d: RoughDielectric, eta: f32, wo: vec3f, wi: vec3f) -> RoughDielectricEval {
    let cos_o = wo.z;
    let cos_i = wi.z;
    let reflect = cos_i > 0.0;
    var m = normalize(wo + wi * select(eta, 1.0, reflect));
    m = select(m, -m, m.z < 0.0);
    let dot_wo_m = dot(wo, m);
    let dot_wi_m = dot(wi, m);
    // The micro- and the macro-surface agree on the sides of both directions.
    let valid = cos_o > 0.0 && cos_i != 0.0 && dot_wo_m * cos_o > 0.0 && dot_wi_m * cos_i > 0.0;
    let dist = eval_microfacet_d_uv(m, d.alpha_uv, d.distribution);
    let f = fresnel_dielectric(dot_wo_m, eta).r;
    let g = smith_g_uv(wo, wi, m, d.alpha_uv, d.distribution);
    var value: vec3f;
    var jacobian: f32;
    var lobe: f32;
    if (reflect) {
        value = d.reflectance * (f * dist * g / (4.0 * cos_o));
        jacobian = 1.0 / (4.0 * dot_wi_m);
        lobe = f;
    } else {
        let denominator = dot_wo_m + eta * dot_wi_m;
        value = d.transmittance * abs((1.0 - f) * dist * g * dot_wo_m * dot_wi_m / (cos_o * denominator * denominator));
        jacobian = eta * eta * dot_wi_m / (denominator * denominator);
        lobe = 1.0 - f;
    }
    let pdf = pdf_microfacet_uv(wo, m, rough_dielectric_sample_alpha(d, cos_o), d.distribution) * lobe * abs(jacobian);
    return RoughDielectricEval(select(vec3f(0.0), value, valid), select(0.0, pdf, valid));
}

// The relative index seen from wo's side.
fn rough_dielectric_eta(d: RoughDielectric, inside: bool) -> f32 {
    return select(d.eta, 1.0 / d.eta, inside);
}

// A normal by the pipeline's microfacet strategy, then reflection with probability F(wo . m)
// (u_lobe <= F, Mitsuba's test) or refraction; the weight is f |cos| / pdf of the result.
fn sample_rough_dielectric(d: RoughDielectric, inside: bool, frame: Frame, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let n_s = frame.n;
    let wo_l = frame_to_local(frame, wo);
    let eta = rough_dielectric_eta(d, inside);
    let m = sample_microfacet_uv(wo_l, u_dir, rough_dielectric_sample_alpha(d, wo_l.z), d.distribution).m;
    let fr = fresnel_dielectric(dot(wo_l, m), eta);
    var wi_l: vec3f;
    var rel = 1.0;
    if (u_lobe <= fr.r) {
        wi_l = 2.0 * dot(wo_l, m) * m - wo_l;
    } else {
        // Mitsuba's refract(): the refracted direction about m.
        wi_l = m * (dot(wo_l, m) * fr.eta_ti + fr.cos_theta_t) - wo_l * fr.eta_ti;
        rel = fr.eta_it;
    }
    let e = eval_pdf_rough_dielectric_local(d, eta, wo_l, wi_l);
    // A normal the strategy cannot draw (GGX's visible slopes overflow for u at 1 - 2^-24)
    // gives no direction: nothing scatters.
    if (!(e.pdf > 0.0)) {
        return BsdfSample(n_s, 0.0, vec3f(0.0), false, 1.0);
    }
    // A normal facing away from wo (drawn by the ndf strategy), a refracted sample that leaves
    // on wo's side, or a reflected one below it, scatters nothing (Mitsuba's G1 is 0 there):
    // weight and density 0. (The same direction drawn through the right normal is counted by
    // the density.)
    if (dot(wo_l, m) <= 0.0 || (u_lobe <= fr.r) != (wi_l.z > 0.0)) {
        return BsdfSample(frame_to_world(frame, wi_l), 0.0, vec3f(0.0), false, 1.0);
    }
    return BsdfSample(frame_to_world(frame, wi_l), e.pdf, path_weight(e.f_cos, 1.0, e.pdf), false, rel);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_rough_dielectric_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let d = rough_dielectric_of(b);
    let frame = bsdf_frame(b, n_s);
    let wi_l = frame_to_local(frame, wi);
    let e = eval_pdf_rough_dielectric_local(d, rough_dielectric_eta(d, b.inside), frame_to_local(frame, wo), wi_l);
    // f = (f |cos|) / |cos|, zero where cos is (f |cos| is zero there too).
    return BsdfEval(select(vec3f(0.0), e.f_cos / abs(wi_l.z), wi_l.z != 0.0), e.pdf);
}

fn sample_rough_dielectric_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_rough_dielectric(rough_dielectric_of(b), b.inside, bsdf_frame(b, n_s), wo, u_dir, u_lobe);
}
