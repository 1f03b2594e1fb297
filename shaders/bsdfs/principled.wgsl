// bsdfs/principled.wgsl — Mitsuba's `principled` term for term (principled.cpp,
// principledhelpers.h; the host's side and the lobes' formulas: src/scene/bsdfs/principled.rs):
// the Disney principled BRDF without transmission. Lobes, with C the base colour, M metallic,
// r roughness, wo the viewer's direction (Mitsuba's wi), wi the scattered one:
//
//   specular:  F D G / (4 cos_o cos_i), GGX of alpha max(0.001, r^2) (anisotropic: of
//              (alpha_u, alpha_v), principled_alpha), F the principled Fresnel;
//   clearcoat: clearcoat / 4 Fcc Dcc Gcc (GTR1 normals; Mitsuba's, without 1 / (4 cos_o cos_i));
//   diffuse:   (1 - M) C / pi (Disney's diffuse with retro-reflection, blended by flatness
//              with the fake subsurface term);
//   sheen:     sheen (1 - M) (1 - h . wi)^5 lerp(1, C / lum(C), sheen_tint).
//
// Its own sampling picks one lobe with probabilities proportional to (1 - M) diffuse_rate,
// clearcoat / 4 clearcoat_rate and specular_rate; a reflection not above both the surface and
// its microfacet is a lost sample (density 0), as Mitsuba's mask. One-sided: n_s is turned
// towards wo by the integrator, and the back (wo.z <= 0) is black.

struct Principled {
    base_color: vec3f,
    roughness: f32,
    metallic: f32,
    spec_tint: f32,
    sheen: f32,
    sheen_tint: f32,
    clearcoat: f32,
    clearcoat_gloss: f32,
    eta: f32,
    flatness: f32,
    specular_rate: f32,
    clearcoat_rate: f32,
    diffuse_rate: f32,
    anisotropic: f32,
}

// The parameter block as src/scene/bsdfs/principled.rs packs it: p0 = (base_color, roughness),
// p1 = (metallic, spec_tint, sheen, sheen_tint), p2 = (clearcoat, clearcoat_gloss, anisotropic
// (read only where some material has anisotropic roughness), data), each number that may be a
// texture resolved by bsdf_apply_textures; the data: flatness, the three sampling rates, eta.
fn principled_of(b: Bsdf) -> Principled {
    let d = u32(b.p2.w);
    var anisotropic = 0.0;
    if (ANISOTROPIC_ROUGHNESS) {
        anisotropic = b.p2.z;
    }
    return Principled(b.p0.xyz, b.p0.w, b.p1.x, b.p1.y, b.p1.z, b.p1.w, b.p2.x, b.p2.y, bsdf_data[d + 4u],
                      bsdf_data[d], bsdf_data[d + 1u], bsdf_data[d + 2u], bsdf_data[d + 3u], anisotropic);
}

// Schlick's weight (1 - cos)^5, its argument clipped to [0, 1].
fn schlick_weight(cos_i: f32) -> f32 {
    let m = clamp(1.0 - cos_i, 0.0, 1.0);
    return (m * m) * (m * m) * m;
}

// Schlick's Fresnel approximation R0 + (1 - R0) w, with w at the incident cosine where the
// light enters the denser side (eta_it > 1), else at the refracted cosine (Mitsuba's
// calc_schlick).
fn principled_schlick(r0: vec3f, cos_theta_i: f32, eta: f32) -> vec3f {
    let outside = cos_theta_i >= 0.0;
    let eta_it = select(1.0 / eta, eta, outside);
    let eta_ti = select(eta, 1.0 / eta, outside);
    let cos_theta_t = sqrt(max(0.0, 1.0 - (1.0 - cos_theta_i * cos_theta_i) * (eta_ti * eta_ti)));
    let w = select(schlick_weight(cos_theta_t), schlick_weight(abs(cos_theta_i)), eta_it > 1.0);
    return mix(r0, vec3f(1.0), w);
}

// The colour of C's hue at unit luminance (1 where C is black): the tint of spec_tint and
// sheen_tint.
fn principled_tint(c: vec3f) -> vec3f {
    let lum = dot(LUMINANCE, c);
    return select(vec3f(1.0), c / lum, lum > 0.0);
}

// The principled Fresnel term on the front side: the dielectric's f_dielectric where neither
// metallic nor tinted, Schlick's of the base colour where metallic, of the tinted dielectric's
// R0 where tinted (Mitsuba's principled_fresnel).
fn principled_fresnel(p: Principled, f_dielectric: f32, cos_theta_i: f32) -> vec3f {
    let eta_it = select(1.0 / p.eta, p.eta, cos_theta_i >= 0.0);
    let r0_eta = ((eta_it - 1.0) / (eta_it + 1.0)) * ((eta_it - 1.0) / (eta_it + 1.0));
    let metal = p.metallic * principled_schlick(p.base_color, cos_theta_i, p.eta);
    let tinted = (1.0 - p.metallic) * p.spec_tint * principled_schlick(principled_tint(p.base_color) * r0_eta, cos_theta_i, p.eta);
    return (1.0 - p.metallic) * (1.0 - p.spec_tint) * f_dielectric + metal + tinted;
}

// The clearcoat's GTR1 distribution of normals of roughness a (Burley 2012):
//   D(m) = (a^2 - 1) / (pi log(a^2) (1 + (a^2 - 1) cos^2(theta_m))), 0 unless D cos > 1e-20.
fn eval_gtr1(m: vec3f, a: f32) -> f32 {
    let a2 = a * a;
    let d = (a2 - 1.0) / (PI * log(a2) * (1.0 + (a2 - 1.0) * m.z * m.z));
    return select(0.0, d, d * m.z > 1e-20);
}

// GTR1 normals with density D(m) cos(theta_m): cos^2(theta) = (1 - a^(2 (1 - u.y))) / (1 - a^2),
// phi = 2 pi u.x.
fn sample_gtr1(u: vec2f, a: f32) -> vec3f {
    let a2 = a * a;
    let cos2 = (1.0 - pow(a2, 1.0 - u.y)) / (1.0 - a2);
    let sin_theta = sqrt(max(0.0, 1.0 - cos2));
    let cos_theta = sqrt(max(0.0, cos2));
    let phi = 2.0 * PI * u.x;
    return vec3f(cos(phi) * sin_theta, sin(phi) * sin_theta, cos_theta);
}

// Smith's G1 of GGX at roughness a for the clearcoat (Mitsuba's smith_ggx1: 1 at normal
// incidence, 0 where v sees the back of m).
fn clearcoat_g1(v: vec3f, m: vec3f, a: f32) -> f32 {
    let cos2 = v.z * v.z;
    let tan2 = (1.0 - cos2) / cos2;
    var g = 2.0 / (1.0 + sqrt(1.0 + a * a * tan2));
    g = select(g, 1.0, v.z == 1.0);
    return select(g, 0.0, dot(v, m) * v.z <= 0.0);
}

// The clearcoat's roughness: clearcoat_gloss maps 0..1 to 0.1..0.001.
fn clearcoat_alpha(p: Principled) -> f32 {
    return mix(0.1, 0.001, p.clearcoat_gloss);
}

// The main specular lobe's GGX roughness (alpha_u, alpha_v) (Mitsuba's calc_dist_params):
// max(0.001, r^2) along both where not anisotropic, else (max(0.001, r^2 / aspect),
// max(0.001, r^2 aspect)) with aspect = sqrt(1 - 0.9 anisotropic).
fn principled_alpha(p: Principled) -> vec2f {
    let r2 = p.roughness * p.roughness;
    if (ANISOTROPIC_ROUGHNESS && p.anisotropic > 0.0) {
        let aspect = sqrt(1.0 - 0.9 * p.anisotropic);
        return max(vec2f(0.001), vec2f(r2 / aspect, r2 * aspect));
    }
    return vec2f(max(0.001, r2));
}

// The probabilities of the diffuse lobe and of the clearcoat in the own sampling (the main
// specular has the rest), normalised from the lobes' rates on the front side.
fn principled_lobe_probs(p: Principled) -> vec2f {
    let diffuse = (1.0 - p.metallic) * p.diffuse_rate;
    let clearcoat = 0.25 * p.clearcoat * p.clearcoat_rate;
    let total = p.specular_rate + clearcoat + diffuse;
    return vec2f(diffuse, clearcoat) / total;
}

// f(wi, wo) (every lobe) and the own strategy's density at wi, in the local frame of n_s (+z):
// zero unless both directions are above the surface; the microfacet lobes' densities are their
// normals' times the Jacobian of reflection, 1 / (4 wi . h), counted only where h is on the side
// of both directions (the normals the sampling keeps).
fn eval_pdf_principled_local(p: Principled, wo: vec3f, wi: vec3f) -> BsdfEval {
    if (wo.z <= 0.0 || wi.z <= 0.0) {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let h = normalize(wo + wi);
    let compatible = dot(wo, h) > 0.0 && dot(wi, h) > 0.0;
    let alpha = principled_alpha(p);
    let f_dielectric = fresnel_dielectric(dot(wo, h), p.eta).r;
    var f = vec3f(0.0);
    // The main specular reflection (Mitsuba's mask: only where the dielectric reflects).
    if (compatible && f_dielectric > 0.0) {
        let d = eval_microfacet_d_uv(h, alpha, DISTRIBUTION_GGX);
        let g = smith_g_uv(wo, wi, h, alpha, DISTRIBUTION_GGX);
        f += principled_fresnel(p, f_dielectric, dot(wo, h)) * (d * g / (4.0 * wo.z * wi.z));
    }
    // The clearcoat: Schlick's F of R0 = 0.04, GTR1 normals, GGX's G1 at roughness 0.25.
    let a_cc = clearcoat_alpha(p);
    if (compatible && p.clearcoat > 0.0) {
        let f_cc = principled_schlick(vec3f(0.04), dot(wo, h), p.eta).x;
        let g_cc = clearcoat_g1(wo, h, 0.25) * clearcoat_g1(wi, h, 0.25);
        f += vec3f(0.25 * p.clearcoat * f_cc * eval_gtr1(h, a_cc) * g_cc);
    }
    // The diffuse lobe with retro-reflection (and the fake subsurface term), and the sheen.
    let brdf = 1.0 - p.metallic;
    if (brdf > 0.0) {
        let f_o = schlick_weight(wi.z);
        let f_i = schlick_weight(wo.z);
        let f_diff = (1.0 - 0.5 * f_i) * (1.0 - 0.5 * f_o);
        let cos_theta_d = dot(h, wi);
        let rr = 2.0 * p.roughness * cos_theta_d * cos_theta_d;
        var shape = f_diff + rr * (f_o + f_i + f_o * f_i * (rr - 1.0));
        if (p.flatness > 0.0) {
            // Hanrahan-Krueger's subsurface approximation, flattening the retro-reflection.
            let f_ss90 = 0.5 * rr;
            let f_ss = (1.0 + f_o * (f_ss90 - 1.0)) * (1.0 + f_i * (f_ss90 - 1.0));
            let subsurface = 1.25 * (f_ss * (1.0 / (wi.z + wo.z) - 0.5) + 0.5);
            shape += p.flatness * (subsurface - shape);
        }
        f += brdf * p.base_color * (INV_PI * shape);
        if (p.sheen > 0.0) {
            let c_sheen = mix(vec3f(1.0), principled_tint(p.base_color), p.sheen_tint);
            f += p.sheen * brdf * schlick_weight(abs(cos_theta_d)) * c_sheen;
        }
    }
    // The own strategy's density: the lobes' densities weighted by their probabilities.
    let probs = principled_lobe_probs(p);
    var pdf = probs.x * pdf_cosine_hemisphere(wi.z);
    if (compatible) {
        let jacobian = 1.0 / (4.0 * dot(wi, h));
        let prob_specular = 1.0 - probs.x - probs.y;
        pdf += prob_specular * pdf_microfacet_uv(wo, h, alpha, DISTRIBUTION_GGX) * jacobian;
        pdf += probs.y * eval_gtr1(h, a_cc) * h.z * jacobian;
    }
    return BsdfEval(f, pdf);
}

// One lobe by u_lobe (diffuse, clearcoat, then the main specular), its direction from u_dir;
// weighted by path_weight with the whole BSDF and the mixture's density, as Mitsuba's.
fn sample_principled(p: Principled, frame: Frame, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let n_s = frame.n;
    let wo_l = frame_to_local(frame, wo);
    if (wo_l.z <= 0.0) {
        return BsdfSample(n_s, 0.0, vec3f(0.0), false, 1.0);
    }
    let probs = principled_lobe_probs(p);
    var wi_l: vec3f;
    var kept = true;
    if (u_lobe < probs.x) {
        wi_l = square_to_cosine_hemisphere(u_dir);
    } else {
        var m: vec3f;
        if (u_lobe < probs.x + probs.y) {
            m = sample_gtr1(u_dir, clearcoat_alpha(p));
        } else {
            m = sample_microfacet_uv(wo_l, u_dir, principled_alpha(p), DISTRIBUTION_GGX).m;
        }
        wi_l = 2.0 * dot(wo_l, m) * m - wo_l;
        // Mitsuba's mask: the reflection must be above the surface and see the normal's front.
        kept = wi_l.z > 0.0 && dot(wo_l, m) > 0.0;
    }
    if (!kept) {
        return BsdfSample(frame_to_world(frame, wi_l), 0.0, vec3f(0.0), false, 1.0);
    }
    let e = eval_pdf_principled_local(p, wo_l, wi_l);
    return BsdfSample(frame_to_world(frame, wi_l), e.pdf, path_weight(e.f, wi_l.z, e.pdf), false, 1.0);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_principled_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let frame = bsdf_frame(b, n_s);
    return eval_pdf_principled_local(principled_of(b), frame_to_local(frame, wo), frame_to_local(frame, wi));
}

fn sample_principled_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_principled(principled_of(b), bsdf_frame(b, n_s), wo, u_dir, u_lobe);
}
