// normal_map.wgsl — Mitsuba's normalmap (src/bsdfs/normalmap.cpp, normalmap_helpers.h; host:
// src/scene/bsdfs/normal_map.rs): a texture of normals around a material's BSDF. The nested BSDF
// scatters in the perturbed frame (Bsdf.normal, with Bsdf.tangent its first axis: bsdf_frame
// builds exactly that frame); bsdf.wgsl's eval_pdf_bsdf and sample_bsdf keep only directions on
// the same side of the surface's shading normal and of the perturbed one, and weigh the value
// by Estevez et al.'s shadowing term (shadow_terminator).

// Some material is normal-mapped (SceneFeatures::has_normal_maps): without, all of it compiles
// out.
override HAS_NORMAL_MAPS: bool = false;

// The BSDF b perturbed by the normal-map texel c (Mitsuba's NormalMap::frame), at a point whose
// shading frame is Mitsuba's sh_frame, s (dp/du made orthogonal to the shading normal n_front)
// and t = n_front x s, with its third axis n_s, the shading normal turned towards the viewer wo
// (Mitsuba's twosided mirrors the local z on the back, keeping s and t): the normal n = 2 c - 1
// of that frame (perturbed_frame).
fn normal_mapped(b: Bsdf, c: vec3f, n_front: vec3f, n_s: vec3f, wo: vec3f) -> Bsdf {
    return perturbed_frame(b, 2.0 * c - vec3f(1.0), bsdf_frame(b, n_front), n_s, wo);
}

// The BSDF b scattering in the frame of a perturbed normal n_in, given in the local shading frame
// (f.t, f.b, n_s) (normal_mapped, bump_mapped; Mitsuba's NormalMap::frame and BumpMap::frame
// after their normals): n_in mirrored about the shading normal, (-x, -y, z), where the viewer
// sees its back (flip_invalid_normals: cos(theta_o) (wo . n) <= 0 in the local frame);
// n' = normalize(n), s' = normalize(x - n' n'.x), both taken to the world.
fn perturbed_frame(b: Bsdf, n_in: vec3f, f: Frame, n_s: vec3f, wo: vec3f) -> Bsdf {
    let s = f.t;
    let t = f.b;
    var n = n_in;
    let wo_l = vec3f(dot(wo, s), dot(wo, t), dot(wo, n_s));
    if (wo_l.z * dot(wo_l, n) <= 0.0) {
        n = vec3f(-n.x, -n.y, n.z);
    }
    let n_l = normalize(n);
    let s_l = normalize(vec3f(1.0, 0.0, 0.0) - n_l * n_l.x);
    var mapped = b;
    mapped.normal = s * n_l.x + t * n_l.y + n_s * n_l.z;
    mapped.tangent = s * s_l.x + t * s_l.y + n_s * s_l.z;
    return mapped;
}

// Whether b scatters in a normal map's or a bump map's perturbed frame.
fn is_normal_mapped(b: Bsdf) -> bool {
    return (HAS_NORMAL_MAPS || HAS_BUMP_MAPS) && dot(b.normal, b.normal) > 0.0;
}

// Estevez et al.'s microfacet-based shadowing of a perturbed normal n_p (Ray Tracing Gems 2019,
// Mitsuba's eval_shadow_terminator), for a direction w, both tilted from the shading normal n_s:
// 2 / (1 + sqrt(1 + a^2 tan^2(theta_w))), a^2 = min(tan^2(theta_n_p) / 8, 1).
fn shadow_terminator(n_p: vec3f, n_s: vec3f, w: vec3f) -> f32 {
    let cos_n = dot(n_p, n_s);
    let cos_w = dot(w, n_s);
    let tan2_n = max(0.0, 1.0 - cos_n * cos_n) / (cos_n * cos_n);
    let tan2_w = max(0.0, 1.0 - cos_w * cos_w) / (cos_w * cos_w);
    let alpha2 = min(0.125 * tan2_n, 1.0);
    return 2.0 / (1.0 + sqrt(1.0 + alpha2 * tan2_w));
}
