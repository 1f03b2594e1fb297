// bsdfs/principled.wgsl — Mitsuba's `principled` term for term (principled.cpp,
// principledhelpers.h; the host's side and the lobes' formulas: src/scene/bsdfs/principled.rs):
// the Disney principled BSDF. Lobes, with C the base colour, M metallic, S spec_trans, r
// roughness, wo the viewer's direction (Mitsuba's wi), wi the scattered one, in the frame of n_s
// turned towards wo:
//
//   specular:     F D G / (4 cos_o cos_i), GGX of alpha max(0.001, r^2) (anisotropic: of
//                 (alpha_u, alpha_v), principled_alpha), F the principled Fresnel;
//   clearcoat:    clearcoat / 4 Fcc Dcc Gcc (GTR1 normals; Mitsuba's, without 1 / (4 cos_o cos_i));
//   diffuse:      (1 - M)(1 - S) C / pi (Disney's diffuse with retro-reflection, blended by
//                 flatness with the fake subsurface term);
//   sheen:        sheen (1 - M) (1 - h . wi)^5 lerp(1, C / lum(C), sheen_tint);
//   transmission: sqrt(C) (1 - M) S, times a rough dielectric's refraction about GGX normals
//                 (1 - F) D G |(wo . h)(wi . h)| / (cos_o cos_i (wo . h + eta wi . h)^2), eta
//                 the index seen from wo's side (radiance: Mitsuba's inv_eta^2 scale times its
//                 eta^2 numerator).
//
// A material with spec_trans (Principled.transmits, Mitsuba's has_spec_trans) is two-sided by
// its nature: seen from inside, it is the dielectric alone, reflection (1 - M) S F D G / (4
// cos_o cos_i) and the transmission, with the index 1 / eta. One without is one-sided (the
// integrator keeps its back black unless the material is two-sided, and then both sides are its
// front, as Mitsuba's twosided).
//
// Its own sampling picks one lobe with probabilities proportional to (1 - M)(1 - S)
// diffuse_rate, clearcoat / 4 clearcoat_rate, specular_rate (1 - (1 - M) S (1 - F)) and
// specular_rate (1 - M) S (1 - F), F the dielectric's at the drawn specular normal (inside:
// F and 1 - F); a reflection not above both the surface and its microfacet, or a refraction
// not below, is a lost sample (density 0), as Mitsuba's mask.

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
    spec_trans: f32,
    // Mitsuba's has_spec_trans: the material transmits and is two-sided by its nature.
    transmits: bool,
}

// Whether material b transmits (the generated bsdf_transmits asks where PRINCIPLED_TRANSMITS):
// p3.y, set by the host where spec_trans is given other than 0.
fn principled_transmits(b: Bsdf) -> bool {
    return b.p3.y > 0.0;
}

// The parameter block as src/scene/bsdfs/principled.rs packs it: p0 = (base_color, roughness),
// p1 = (metallic, spec_tint, sheen, sheen_tint), p2 = (clearcoat, clearcoat_gloss, anisotropic
// (read only where some material has anisotropic roughness), data), p3 = (spec_trans, 1 where
// the material transmits, 0, 0) (read only where some principled material transmits), each
// number that may be a texture resolved by bsdf_apply_textures; the data: flatness, the three
// sampling rates, eta.
fn principled_of(b: Bsdf) -> Principled {
    let d = u32(b.p2.w);
    var anisotropic = 0.0;
    if (ANISOTROPIC_ROUGHNESS) {
        anisotropic = b.p2.z;
    }
    var spec_trans = 0.0;
    var transmits = false;
    if (PRINCIPLED_TRANSMITS) {
        spec_trans = b.p3.x;
        transmits = principled_transmits(b);
    }
    return Principled(b.p0.xyz, b.p0.w, b.p1.x, b.p1.y, b.p1.z, b.p1.w, b.p2.x, b.p2.y, bsdf_data[d + 4u],
                      bsdf_data[d], bsdf_data[d + 1u], bsdf_data[d + 2u], bsdf_data[d + 3u], anisotropic, spec_trans, transmits);
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
    return principled_dist_params(p.roughness, p.anisotropic);
}

// GGX's (alpha_u, alpha_v) of roughness r and anisotropy a (Mitsuba's calc_dist_params, which
// the thin principled BSDF shares).
fn principled_dist_params(roughness: f32, anisotropic: f32) -> vec2f {
    let r2 = roughness * roughness;
    if (ANISOTROPIC_ROUGHNESS && anisotropic > 0.0) {
        let aspect = sqrt(1.0 - 0.9 * anisotropic);
        return max(vec2f(0.001), vec2f(r2 / aspect, r2 * aspect));
    }
    return vec2f(max(0.001, r2));
}

// The diffuse lobe's shape, f pi / C: Disney's diffuse with retro-reflection, Fo = (1 - cos_i)^5,
// Fi = (1 - cos_o)^5, Rr = 2 r cos_d^2 (cos_d = h . wi):
//   (1 - Fi / 2)(1 - Fo / 2) + Rr (Fo + Fi + Fo Fi (Rr - 1)),
// blended by flatness with Hanrahan-Krueger's fake subsurface term, 1.25 (Fss (1 / (cos_i +
// cos_o) - 0.5) + 0.5), Fss = lerp(1, Rr / 2, Fo) lerp(1, Rr / 2, Fi). cos_o and cos_i are the
// two directions' cosines (both > 0).
fn principled_diffuse_shape(cos_o: f32, cos_i: f32, cos_d: f32, roughness: f32, flatness: f32) -> f32 {
    let f_o = schlick_weight(cos_i);
    let f_i = schlick_weight(cos_o);
    let f_diff = (1.0 - 0.5 * f_i) * (1.0 - 0.5 * f_o);
    let rr = 2.0 * roughness * cos_d * cos_d;
    var shape = f_diff + rr * (f_o + f_i + f_o * f_i * (rr - 1.0));
    if (flatness > 0.0) {
        // Hanrahan-Krueger's subsurface approximation, flattening the retro-reflection.
        let f_ss90 = 0.5 * rr;
        let f_ss = (1.0 + f_o * (f_ss90 - 1.0)) * (1.0 + f_i * (f_ss90 - 1.0));
        let subsurface = 1.25 * (f_ss * (1.0 / (cos_i + cos_o) - 0.5) + 0.5);
        shape += flatness * (subsurface - shape);
    }
    return shape;
}

// The sheen's colour, lerp(1, C / lum(C), sheen_tint).
fn principled_sheen_color(base_color: vec3f, sheen_tint: f32) -> vec3f {
    return mix(vec3f(1.0), principled_tint(base_color), sheen_tint);
}

// The probabilities of the diffuse lobe and of the clearcoat in the own sampling (the main
// specular, reflected and transmitted, has the rest), normalised from the lobes' rates on the
// front side.
fn principled_lobe_probs(p: Principled) -> vec2f {
    let w = principled_lobe_weights(p);
    return w.xy / w.z;
}

// The front side's lobe weights before normalising: the diffuse lobe's (1 - M)(1 - S)
// diffuse_rate, the clearcoat's clearcoat / 4 clearcoat_rate, and their sum with the main
// specular's rate (its reflection's and transmission's weights sum to it whatever F).
fn principled_lobe_weights(p: Principled) -> vec3f {
    let diffuse = (1.0 - p.metallic) * (1.0 - p.spec_trans) * p.diffuse_rate;
    let clearcoat = 0.25 * p.clearcoat * p.clearcoat_rate;
    return vec3f(diffuse, clearcoat, p.specular_rate + clearcoat + diffuse);
}

// The probability of the main specular's transmission, given the dielectric's Fresnel term F
// at its normal: (1 - M) S (1 - F) of the specular rate, normalised as principled_lobe_probs
// (the reflection's and the transmission's weights sum to the rate whatever F), on the front;
// 1 - F inside (the dielectric alone).
fn principled_transmission_prob(p: Principled, f_dielectric: f32, front: bool) -> f32 {
    if (!p.transmits) {
        return 0.0;
    }
    if (!front) {
        return 1.0 - f_dielectric;
    }
    return p.specular_rate * (1.0 - p.metallic) * p.spec_trans * (1.0 - f_dielectric) / principled_lobe_weights(p).z;
}

// f(wi, wo) (every lobe) and the own strategy's density at wi, in the local frame of n_s (+z,
// turned towards wo: wo.z > 0); `inside`: wo is behind the surface, which matters where the
// material transmits. Reflection lobes need wi above, the transmission wi below; the microfacet
// lobes' densities are their normals' times the Jacobian of reflection, 1 / (4 wi . h), or of
// refraction, eta^2 |wi . h| / (wo . h + eta wi . h)^2, counted only where h is on the side
// the lobe needs (the normals the sampling keeps).
fn eval_pdf_principled_local(p: Principled, inside: bool, wo: vec3f, wi: vec3f) -> BsdfEval {
    let reflect = wi.z > 0.0;
    if (wo.z <= 0.0 || !(reflect || (p.transmits && wi.z < 0.0))) {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    // The front: both sides of a material that does not transmit (Mitsuba's twosided).
    let front = !(p.transmits && inside);
    let eta = select(1.0 / p.eta, p.eta, front);
    // The half vector of a reflection, or of a refraction, normalize(wo + eta wi), turned up.
    var h = normalize(wo + wi * select(eta, 1.0, reflect));
    h = select(h, -h, h.z < 0.0);
    let compatible = dot(wo, h) > 0.0 && select(dot(wi, h) < 0.0, dot(wi, h) > 0.0, reflect);
    let alpha = principled_alpha(p);
    let f_dielectric = fresnel_dielectric(dot(wo, h), eta).r;
    let bsdf = (1.0 - p.metallic) * p.spec_trans;
    var f = vec3f(0.0);
    if (reflect) {
        // The main specular reflection (Mitsuba's mask: only where the dielectric reflects);
        // inside, the dielectric's alone.
        if (compatible && f_dielectric > 0.0) {
            let d = eval_microfacet_d_uv(h, alpha, DISTRIBUTION_GGX);
            let g = smith_g_uv(wo, wi, h, alpha, DISTRIBUTION_GGX);
            let fresnel = select(vec3f(bsdf * f_dielectric), principled_fresnel(p, f_dielectric, dot(wo, h)), front);
            f += fresnel * (d * g / (4.0 * wo.z * wi.z));
        }
        // The clearcoat: Schlick's F of R0 = 0.04, GTR1 normals, GGX's G1 at roughness 0.25.
        let a_cc = clearcoat_alpha(p);
        if (front && compatible && p.clearcoat > 0.0) {
            let f_cc = principled_schlick(vec3f(0.04), dot(wo, h), p.eta).x;
            let g_cc = clearcoat_g1(wo, h, 0.25) * clearcoat_g1(wi, h, 0.25);
            f += vec3f(0.25 * p.clearcoat * f_cc * eval_gtr1(h, a_cc) * g_cc);
        }
        // The diffuse lobe with retro-reflection (and the fake subsurface term), and the sheen.
        let brdf = (1.0 - p.metallic) * (1.0 - p.spec_trans);
        if (front && brdf > 0.0) {
            let cos_theta_d = dot(h, wi);
            let shape = principled_diffuse_shape(wo.z, wi.z, cos_theta_d, p.roughness, p.flatness);
            f += brdf * p.base_color * (INV_PI * shape);
            if (p.sheen > 0.0) {
                f += p.sheen * (1.0 - p.metallic) * schlick_weight(abs(cos_theta_d)) * principled_sheen_color(p.base_color, p.sheen_tint);
            }
        }
        // The own strategy's density: the lobes' densities weighted by their probabilities.
        let probs = select(vec2f(0.0), principled_lobe_probs(p), front);
        var pdf = probs.x * pdf_cosine_hemisphere(wi.z);
        if (compatible) {
            let jacobian = 1.0 / (4.0 * dot(wi, h));
            let prob_specular = select(f_dielectric, 1.0 - probs.x - probs.y - principled_transmission_prob(p, f_dielectric, front), front);
            pdf += prob_specular * pdf_microfacet_uv(wo, h, alpha, DISTRIBUTION_GGX) * jacobian;
            pdf += probs.y * eval_gtr1(h, a_cc) * h.z * jacobian;
        }
        return BsdfEval(f, pdf);
    }
    // The transmission (Mitsuba's mask: only where the dielectric does not reflect everything).
    if (!compatible || !(bsdf > 0.0) || !(f_dielectric < 1.0)) {
        return BsdfEval(vec3f(0.0), 0.0);
    }
    let d = eval_microfacet_d_uv(h, alpha, DISTRIBUTION_GGX);
    let g = smith_g_uv(wo, wi, h, alpha, DISTRIBUTION_GGX);
    let denominator = dot(wo, h) + eta * dot(wi, h);
    let f_cos = abs((1.0 - f_dielectric) * d * g * dot(wo, h) * dot(wi, h) / (wo.z * denominator * denominator));
    let jacobian = eta * eta * abs(dot(wi, h)) / (denominator * denominator);
    let pdf = principled_transmission_prob(p, f_dielectric, front) * pdf_microfacet_uv(wo, h, alpha, DISTRIBUTION_GGX) * jacobian;
    return BsdfEval(sqrt(p.base_color) * (bsdf * f_cos / abs(wi.z)), pdf);
}

// One lobe by u_lobe (diffuse, clearcoat, the main specular's transmission, then its
// reflection, Mitsuba's order), its direction from u_dir; weighted by path_weight with the
// whole BSDF and the mixture's density, as Mitsuba's. The transmission's share depends on the
// Fresnel term at the drawn normal; its sample carries the relative index eta_it.
fn sample_principled(p: Principled, inside: bool, frame: Frame, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    let n_s = frame.n;
    let wo_l = frame_to_local(frame, wo);
    if (wo_l.z <= 0.0) {
        return BsdfSample(n_s, 0.0, vec3f(0.0), false, 1.0);
    }
    let front = !(p.transmits && inside);
    let probs = select(vec2f(0.0), principled_lobe_probs(p), front);
    var wi_l: vec3f;
    var kept = true;
    var rel = 1.0;
    if (u_lobe < probs.x) {
        wi_l = square_to_cosine_hemisphere(u_dir);
    } else if (u_lobe < probs.x + probs.y) {
        let m = sample_gtr1(u_dir, clearcoat_alpha(p));
        wi_l = 2.0 * dot(wo_l, m) * m - wo_l;
        // Mitsuba's mask: the reflection must be above the surface and see the normal's front.
        kept = wi_l.z > 0.0 && dot(wo_l, m) > 0.0;
    } else {
        let m = sample_microfacet_uv(wo_l, u_dir, principled_alpha(p), DISTRIBUTION_GGX).m;
        let fr = fresnel_dielectric(dot(wo_l, m), select(1.0 / p.eta, p.eta, front));
        if (u_lobe < probs.x + probs.y + principled_transmission_prob(p, fr.r, front)) {
            // Mitsuba's refract(): the refracted direction about m, below the surface.
            wi_l = m * (dot(wo_l, m) * fr.eta_ti + fr.cos_theta_t) - wo_l * fr.eta_ti;
            rel = fr.eta_it;
            kept = wi_l.z < 0.0 && dot(wo_l, m) > 0.0 && dot(wi_l, m) < 0.0;
        } else {
            wi_l = 2.0 * dot(wo_l, m) * m - wo_l;
            kept = wi_l.z > 0.0 && dot(wo_l, m) > 0.0;
        }
    }
    if (!kept) {
        return BsdfSample(frame_to_world(frame, wi_l), 0.0, vec3f(0.0), false, 1.0);
    }
    let e = eval_pdf_principled_local(p, inside, wo_l, wi_l);
    return BsdfSample(frame_to_world(frame, wi_l), e.pdf, path_weight(e.f, wi_l.z, e.pdf), false, rel);
}

// The dispatcher's entry points (generated from src/scene/bsdfs/mod.rs).
fn eval_pdf_principled_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, wi: vec3f) -> BsdfEval {
    let frame = bsdf_frame(b, n_s);
    return eval_pdf_principled_local(principled_of(b), b.inside, frame_to_local(frame, wo), frame_to_local(frame, wi));
}

fn sample_principled_bsdf(b: Bsdf, n_s: vec3f, wo: vec3f, u_dir: vec2f, u_lobe: f32) -> BsdfSample {
    return sample_principled(principled_of(b), b.inside, bsdf_frame(b, n_s), wo, u_dir, u_lobe);
}
