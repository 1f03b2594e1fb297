// bsdfs/rough_conductor.wgsl — Mitsuba's `roughconductor` term for term: Torrance-Sparrow
// microfacet reflection,
//
//   f(wi, wo) = F(wo . h) D(h) G(wo, wi, h) / (4 cos(theta_o) cos(theta_i)),   h = (wi + wo) / |wi + wo|,
//
// with the distributions, shadowing and Fresnel term of microfacet.wgsl, its normals sampled by
// the pipeline's microfacet strategy (MICROFACET_SAMPLING) where the BSDF strategy is the
// material's own.

// f(wi, wo) |cos(theta_i)| and the density of the pipeline's strategy at wi, in the local
// frame of n_s (+z; wo.z > 0; x along the surface's dp/du, bsdf_frame): with h the half vector,
//   f cos(theta_i) = F(wo . h) D(h) G(wo, wi, h) / (4 cos(theta_o)),
// zero unless both directions are above the surface; the density of microfacet sampling is
// the normal's density times the Jacobian of reflection, 1 / (4 wi . h).
struct ConductorEval {
    f_cos: vec3f,
    pdf: f32,
}

fn eval_pdf_rough_conductor_local(c: Conductor, wo: vec3f, wi: vec3f) -> ConductorEval {
    let h = normalize(wo + wi);
    let above = wo.z > 0.0 && wi.z > 0.0;
    let d = eval_microfacet_d_uv(h, c.alpha_uv, c.distribution);
    let g = smith_g_uv(wo, wi, h, c.alpha_uv, c.distribution);
    let f = fresnel_conductor(dot(wo, h), c.eta, c.k) * c.reflectance;
    let value = select(vec3f(0.0), f * (d * g / (4.0 * wo.z)), above && d != 0.0);
    let pdf = select(0.0, pdf_microfacet_uv(wo, h, c.alpha_uv, c.distribution) / (4.0 * dot(wi, h)),
                     above && dot(wo, h) > 0.0 && dot(wi, h) > 0.0);
    return ConductorEval(value, pdf);
}

// A direction reflected about a microfacet normal drawn by the pipeline's microfacet strategy:
// its own strategy (the material strategies `phong` and `phong-lobe-only`; the generic ones
// are the dispatcher's, bsdf.wgsl).
fn sample_rough_conductor(c: Conductor, frame: Frame, wo: vec3f, u_dir: vec2f) -> BsdfSample {
    let wo_l = frame_to_local(frame, wo);
    let m = sample_microfacet_uv(wo_l, u_dir, c.alpha_uv, c.distribution).m;
    let wi_l = 2.0 * dot(wo_l, m) * m - wo_l;
    let e = eval_pdf_rough_conductor_local(c, wo_l, wi_l);
    // path_weight's f |cos| / pdf, with f |cos| already formed.
    return BsdfSample(frame_to_world(frame, wi_l), e.pdf, path_weight(e.f_cos, 1.0, e.pdf), false, 1.0);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_rough_conductor_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let frame = bsdf_frame(b, n_s);
    let wi_l = frame_to_local(frame, wi);
    let e = eval_pdf_rough_conductor_local(conductor_of(b), frame_to_local(frame, wo), wi_l);
    // f = (f cos) / cos, zero where cos is (f cos is zero there too).
    return BsdfEval(select(vec3f(0.0), e.f_cos / wi_l.z, wi_l.z > 0.0), e.pdf);
}

fn sample_rough_conductor_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_rough_conductor(conductor_of(b), bsdf_frame(b, n_s), wo, u_dir);
}
