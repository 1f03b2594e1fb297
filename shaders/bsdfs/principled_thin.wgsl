// bsdfs/principled_thin.wgsl — Mitsuba's `principledthin` term for term (principledthin.cpp,
// principledhelpers.h; the host's side and the lobes' formulas: src/scene/bsdfs/principled_thin.rs):
// the principled BSDF of a thin sheet, which scatters alike on both sides and passes light
// through without bending it. Everything is computed in the frame of n_s, which the integrator
// turns towards wo (cos_o = wo.z > 0: Mitsuba's mulsign to the front). With S = spec_trans,
// T = diff_trans / 2, C the base colour, wi_r = wi mirrored to wo's side and h = normalize(wo +
// wi_r), f |cos_i| is the sum of
//
//   specular reflection:   S F_thin D G / (4 cos_o), GGX of (alpha_u, alpha_v) = calc_dist_params(r),
//                          F_thin = lerp(F_dielectric(wo . h, eta), Schlick(c_tint R0(eta)), spec_tint);
//   specular transmission: S C (1 - F_dielectric) D' G' / (4 cos_o), wi below the sheet, GGX of
//                          the roughness scaled by 0.65 eta - 0.35 (Burley 2015, fig. 15);
//   diffuse reflection:    (1 - S)(1 - T) |cos_i| (C / pi shape + sheen (1 - h . wi)^5 c_sheen),
//                          principled.wgsl's shape and sheen colour;
//   diffuse transmission:  (1 - S) T C / pi |cos_i|.
//
// The own sampling's density: the lobes' (visible or all normals of each GGX times the
// Jacobian 1 / (4 wi_r . h); the cosine hemispheres on either side) weighted by the lobe
// probabilities of principled_thin_lobe_probs. A specular lobe's normal whose direction is not
// on the side it needs (Mitsuba's mac_mic_compatibility) is a lost sample, counted in neither.

struct PrincipledThin {
    base_color: vec3f,
    roughness: f32,
    anisotropic: f32,
    spec_trans: f32,
    sheen: f32,
    sheen_tint: f32,
    flatness: f32,
    spec_tint: f32,
    // Mitsuba's diff_trans / 2, in [0, 1].
    diff_trans: f32,
    eta: f32,
    // The sampling rates: specular reflectance, specular transmittance, diffuse reflectance,
    // diffuse transmittance.
    rates: vec4f,
}

// The parameter block as src/scene/bsdfs/principled_thin.rs packs it: p0 = (base_color,
// roughness), p1 = (anisotropic (read only where some material has anisotropic roughness),
// spec_trans, sheen, sheen_tint), p2 = (flatness, spec_tint, diff_trans, data), each number
// that may be a texture resolved by bsdf_apply_textures; the data: eta, the four rates.
fn principled_thin_of(b: Bsdf) -> PrincipledThin {
    let d = u32(b.p2.w);
    var anisotropic = 0.0;
    if (ANISOTROPIC_ROUGHNESS) {
        anisotropic = b.p1.x;
    }
    let rates = vec4f(bsdf_data[d + 1u], bsdf_data[d + 2u], bsdf_data[d + 3u], bsdf_data[d + 4u]);
    return PrincipledThin(b.p0.xyz, b.p0.w, anisotropic, b.p1.y, b.p1.z, b.p1.w, b.p2.x, b.p2.y, 0.5 * b.p2.z, bsdf_data[d], rates);
}

// The probabilities of the own sampling's lobes (specular reflection, specular transmission,
// diffuse reflection, diffuse transmission): S / 2, S / 2, (1 - S)(1 - T) and (1 - S) T, each
// times its rate, normalised.
fn principled_thin_lobe_probs(p: PrincipledThin) -> vec4f {
    let s = p.spec_trans;
    let w = vec4f(0.5 * s * p.rates.x, 0.5 * s * p.rates.y, p.rates.z * (1.0 - s) * (1.0 - p.diff_trans), p.rates.w * (1.0 - s) * p.diff_trans);
    return w / (w.x + w.y + w.z + w.w);
}

// The specular transmission's GGX roughness: the roughness scaled by 0.65 eta - 0.35.
fn principled_thin_transmission_alpha(p: PrincipledThin) -> vec2f {
    return principled_dist_params((0.65 * p.eta - 0.35) * p.roughness, p.anisotropic);
}

// f(wi, wo) (every lobe) and the own strategy's density at wi, in the local frame of n_s
// (wo.z > 0; wi on either side).
fn eval_pdf_principled_thin_local(p: PrincipledThin, wo: vec3f, wi: vec3f) -> BsdfEval {
    if (wo.z <= 0.0 || wi.z == 0.0) {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let cos_o = wo.z;
    let cos_i = abs(wi.z);
    let reflect = wi.z > 0.0;
    // The half vector of wo and wi mirrored to wo's side: a transmitted direction is a
    // reflection about h turned through the sheet.
    let wi_r = vec3f(wi.xy, cos_i);
    let h = normalize(wo + wi_r);
    let s = p.spec_trans;
    let t = p.diff_trans;
    let probs = principled_thin_lobe_probs(p);
    var f_cos = vec3f(0.0);
    var pdf = 0.0;
    if (s > 0.0) {
        let f_dielectric = fresnel_dielectric(dot(wo, h), p.eta).r;
        // The Jacobian of reflection about h, 1 / (4 wi_r . h).
        let jacobian = abs(1.0 / (4.0 * dot(wi_r, h)));
        // Micro- and macro-surface agree: wo sees h's front, and wi is on h's front
        // (reflection) or back (transmission).
        let sees = dot(wo, h) > 0.0;
        if (reflect && sees && dot(wi, h) > 0.0) {
            let alpha = principled_dist_params(p.roughness, p.anisotropic);
            let r0 = ((p.eta - 1.0) / (p.eta + 1.0)) * ((p.eta - 1.0) / (p.eta + 1.0));
            let f_schlick = principled_schlick(principled_tint(p.base_color) * r0, dot(wo, h), p.eta);
            let f_thin = mix(vec3f(f_dielectric), f_schlick, p.spec_tint);
            let d = eval_microfacet_d_uv(h, alpha, DISTRIBUTION_GGX);
            let g = smith_g_uv(wo, wi, h, alpha, DISTRIBUTION_GGX);
            f_cos += s * f_thin * (d * g / (4.0 * cos_o));
            pdf += probs.x * pdf_microfacet_uv(wo, h, alpha, DISTRIBUTION_GGX) * jacobian;
        }
        if (!reflect && sees && dot(wi, h) < 0.0) {
            let alpha = principled_thin_transmission_alpha(p);
            let d = eval_microfacet_d_uv(h, alpha, DISTRIBUTION_GGX);
            let g = smith_g_uv(wo, wi, h, alpha, DISTRIBUTION_GGX);
            f_cos += s * p.base_color * ((1.0 - f_dielectric) * d * g / (4.0 * cos_o));
            pdf += probs.y * pdf_microfacet_uv(wo, h, alpha, DISTRIBUTION_GGX) * jacobian;
        }
    }
    if (reflect) {
        if (s < 1.0 && t < 1.0) {
            let cos_theta_d = dot(h, wi);
            let shape = principled_diffuse_shape(cos_o, cos_i, cos_theta_d, p.roughness, p.flatness);
            var diffuse = p.base_color * (INV_PI * shape);
            if (p.sheen > 0.0) {
                diffuse += p.sheen * schlick_weight(abs(cos_theta_d)) * principled_sheen_color(p.base_color, p.sheen_tint);
            }
            f_cos += (1.0 - s) * (1.0 - t) * cos_i * diffuse;
        }
        pdf += probs.z * pdf_cosine_hemisphere(cos_i);
    } else {
        if (s < 1.0 && t > 0.0) {
            f_cos += (1.0 - s) * t * p.base_color * (INV_PI * cos_i);
        }
        pdf += probs.w * pdf_cosine_hemisphere(cos_i);
    }
    return BsdfEval(f_cos / cos_i, pdf);
}

// One lobe by u_lobe (specular reflection, specular transmission, diffuse reflection, then
// diffuse transmission), its direction from u_dir; weighted by path_weight with the whole BSDF
// and the mixture's density, as Mitsuba's.
fn sample_principled_thin(p: PrincipledThin, frame: Frame, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let n_s = frame.n;
    let wo_l = frame_to_local(frame, wo);
    if (wo_l.z <= 0.0) {
        return BsdfSample(n_s, 0.0, vec3f(0.0), false, 1.0);
    }
    let probs = principled_thin_lobe_probs(p);
    var wi_l: vec3f;
    var kept = true;
    if (u_lobe < probs.x + probs.y) {
        let transmit = u_lobe >= probs.x;
        let alpha = select(principled_dist_params(p.roughness, p.anisotropic), principled_thin_transmission_alpha(p), transmit);
        let m = sample_microfacet_uv(wo_l, u_dir, alpha, DISTRIBUTION_GGX).m;
        let r = 2.0 * dot(wo_l, m) * m - wo_l;
        // Transmission: the reflection turned through the sheet.
        wi_l = select(r, vec3f(r.xy, -r.z), transmit);
        // Mitsuba's mask: the direction on the lobe's side of the surface and of the normal.
        kept = dot(wo_l, m) > 0.0 && select(wi_l.z > 0.0 && dot(wi_l, m) > 0.0, wi_l.z < 0.0 && dot(wi_l, m) < 0.0, transmit);
    } else {
        wi_l = square_to_cosine_hemisphere(u_dir);
        if (u_lobe >= probs.x + probs.y + probs.z) {
            wi_l = -wi_l;
        }
    }
    if (!kept) {
        return BsdfSample(frame_to_world(frame, wi_l), 0.0, vec3f(0.0), false, 1.0);
    }
    let e = eval_pdf_principled_thin_local(p, wo_l, wi_l);
    return BsdfSample(frame_to_world(frame, wi_l), e.pdf, path_weight(e.f, wi_l.z, e.pdf), false, 1.0);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_principled_thin_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let frame = bsdf_frame(b, n_s);
    return eval_pdf_principled_thin_local(principled_thin_of(b), frame_to_local(frame, wo), frame_to_local(frame, wi));
}

fn sample_principled_thin_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_principled_thin(principled_thin_of(b), bsdf_frame(b, n_s), wo, u_dir, u_lobe);
}
