// bsdfs/phong.wgsl — the normalised modified Phong BRDF (the study's),
//
//   f(wi, wo) = kd / pi + ks (n + 2) / (2 pi) max(0, dot(wi, r))^n,   r = mirror of wo about n_s,
//
// with its own strategies, a one-sample mixture of the cosine and Phong lobes (BSDF_PHONG), and
// the biased demonstration BSDF_PHONG_LOBE_ONLY (the study's darker specular): it samples only
// the Phong lobe while the full BRDF (diffuse + specular) is evaluated, so directions outside
// the lobe are never taken.

// False when every material has ks = 0: the Phong lobe is compiled out.
override HAS_SPECULAR: bool = true;

struct Phong {
    kd: vec3f,
    ks: vec3f,
    n: f32,
    // Probability of sampling the Phong lobe in the one-sample mixture: lum(ks) / (lum(kd) + lum(ks)).
    p_spec: f32,
}

// f(wi, wo) and the sampling density at wi together, for unit wo, wi and a shading normal n_s
// with dot(wo, n_s) > 0: the Phong lobe cos^n(alpha) serves both, so it is computed once.
fn eval_pdf_phong(m: Phong, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let cos_i = dot(wi, n_s);
    // cos^n of the angle between wi and the mirror direction of wo (zero outside the lobe).
    var lobe = 0.0;
    if (HAS_SPECULAR || BSDF_SAMPLING == BSDF_PHONG_LOBE_ONLY) {
        lobe = phong_cos_pow(one_minus_cos_between(wi, reflect_about(wo, n_s)), m.n);
    }

    // Normalised modified Phong: kd / pi + ks (n + 2) / (2 pi) cos^n(alpha), none below the surface.
    var f = m.kd * INV_PI;
    if (HAS_SPECULAR) {
        f += m.ks * ((m.n + 2.0) * INV_2PI * lobe);
    }
    f = select(vec3f(0.0), f, cos_i > 0.0 && dot(wo, n_s) > 0.0);

    // The density of its own strategy (the generic ones are the dispatcher's, bsdf.wgsl).
    var pdf: f32;
    switch (BSDF_SAMPLING) {
        case BSDF_PHONG_LOBE_ONLY: {
            // Solid-angle pdf of the Phong lobe: (n + 1) / (2 pi) cos^n(alpha).
            pdf = (m.n + 1.0) * INV_2PI * lobe;
        }
        default: {
            // One-sample mixture: P_d cos / pi + P_s (n + 1) / (2 pi) cos^n(alpha), over the
            // whole sphere (the Phong lobe also reaches below the surface, where f = 0).
            pdf = (1.0 - m.p_spec) * pdf_cosine_hemisphere(cos_i);
            if (HAS_SPECULAR) {
                pdf += m.p_spec * ((m.n + 1.0) * INV_2PI * lobe);
            }
        }
    }
    return BsdfEval(f, pdf);
}

// f(wi, wo) alone.
fn eval_phong(m: Phong, n_s: vec3f, wo: vec3f, wi: vec3f) -> vec3f {
    return eval_pdf_phong(m, n_s, wo, wi).f;
}

// A direction from the Phong mixture: u_lobe picks the lobe, u_dir places the direction. The
// cosine lobe is the Phong lobe of exponent 1 around n_s (cos(theta) = v^(1/2)), so both lobes
// share one warp and one frame instead of computing both and discarding one.
fn sample_phong_mixture_direction(m: Phong, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> vec3f {
    let specular = HAS_SPECULAR && u_lobe < m.p_spec;
    let axis = select(n_s, reflect_about(wo, n_s), specular);
    let exponent = select(1.0, m.n, specular);
    return frame_to_world(frame_from_normal(axis), square_to_phong_lobe(u_dir, exponent));
}

// Samples wi with its own strategy, the mixture or (for the demonstration) the lobe alone.
// Samples below the surface keep their pdf and get weight 0: they count in the estimator but
// contribute nothing.
fn sample_phong(m: Phong, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    var wi: vec3f;
    switch (BSDF_SAMPLING) {
        case BSDF_PHONG_LOBE_ONLY: {
            wi = frame_to_world(frame_from_normal(reflect_about(wo, n_s)), square_to_phong_lobe(u_dir, m.n));
        }
        default: {
            wi = sample_phong_mixture_direction(m, n_s, wo, u_dir, u_lobe);
        }
    }
    let e = eval_pdf_phong(m, n_s, wo, wi);
    return BsdfSample(wi, e.pdf, path_weight(e.f, dot(wi, n_s), e.pdf), false, 1.0);
}

// The parameter block as src/scene/bsdfs/phong.rs packs it: p0 = (kd, n), p1 = (ks, p_spec).
fn phong_of(b: Bsdf) -> Phong {
    return Phong(b.p0.xyz, b.p1.xyz, b.p0.w, b.p1.w);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_phong_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    return eval_pdf_phong(phong_of(b), n_s, wo, wi);
}

fn sample_phong_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_phong(phong_of(b), n_s, wo, u_dir, u_lobe);
}
