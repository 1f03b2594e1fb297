// phong_lobe.wgsl — importance sampling of the normalised modified Phong BRDF,
//   f = kd / pi + ks (n + 2) / (2 pi) cos^n(alpha),
// written against pathlab's technique contract (shaders/technique.wgsl): a one-sample mixture
// of the cosine lobe, with probability 1 - P_s, and the Phong lobe cos^n(alpha) about the
// mirror direction, with probability P_s = m.specular_probability. Each lobe is sampled exactly
// (cos = u^(1 / (e + 1)) for the lobe cos^e), and the density is the mixture's:
//   p(wi) = (1 - P_s) cos(theta) / pi + P_s (n + 1) / (2 pi) cos^n(alpha).
// The normalisation of the lobe cos^n over the sphere of directions about its axis is
// (n + 1) / (2 pi). (The study's mistake was (n + 2): see phong_n_plus_2.wgsl.)
//
//   pathlab check-technique bsdf:examples/techniques/phong_lobe.wgsl --scene assets/scenes/study.toml

// A direction about `axis` with cos(angle) = cos_t, at azimuth 2 pi v.
fn phong_lobe_direction(axis: vec3f, cos_t: f32, v: f32) -> vec3f {
    let sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
    let phi = 2.0 * PI * v;
    return frame_to_world(frame_from_normal(axis), vec3f(sin_t * cos(phi), sin_t * sin(phi), cos_t));
}

// cos^e of a cosine c (0 where c <= 0; pow(0, 0) is not defined in WGSL).
fn phong_lobe_pow(c: f32, e: f32) -> f32 {
    return select(0.0, pow(max(c, 1e-30), e), c > 0.0);
}

fn sample_bsdf_technique(wo: vec3f, m: PhongMaterial, u: vec2f, u_lobe: f32) -> vec3f {
    let mirror = vec3f(-wo.x, -wo.y, wo.z);
    if (u_lobe < m.specular_probability) {
        return phong_lobe_direction(mirror, pow(u.x, 1.0 / (m.n + 1.0)), u.y);
    }
    // The cosine lobe: cos^1 about the normal.
    return phong_lobe_direction(vec3f(0.0, 0.0, 1.0), sqrt(u.x), u.y);
}

fn pdf_bsdf_technique(wo: vec3f, m: PhongMaterial, wi: vec3f) -> f32 {
    let mirror = vec3f(-wo.x, -wo.y, wo.z);
    let diffuse = max(wi.z, 0.0) / PI;
    let specular = (m.n + 1.0) / (2.0 * PI) * phong_lobe_pow(dot(wi, mirror), m.n);
    return (1.0 - m.specular_probability) * diffuse + m.specular_probability * specular;
}
