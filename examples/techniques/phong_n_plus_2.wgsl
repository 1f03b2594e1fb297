// phong_n_plus_2.wgsl — the study's mistake, kept to show what pathlab does with it: the
// Phong lobe is sampled as in phong_lobe.wgsl (cos = u^(1 / (n + 1))), but its density is
// normalised with (n + 2) / (2 pi), the BRDF's factor, instead of (n + 1) / (2 pi). The sampler
// and the pdf then disagree: the pdf integrates to 1 + P_s / (n + 1) over the sphere, every
// specular sample's weight is (n + 1) / (n + 2) too small, and the image comes out darker.
// The study's author read that darker image as an expected trade-off; pathlab's check refuses
// the technique before it renders:
//
//   pathlab check-technique bsdf:examples/techniques/phong_n_plus_2.wgsl --scene assets/scenes/study.toml

fn phong_n_plus_2_direction(axis: vec3f, cos_t: f32, v: f32) -> vec3f {
    let sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
    let phi = 2.0 * PI * v;
    return frame_to_world(frame_from_normal(axis), vec3f(sin_t * cos(phi), sin_t * sin(phi), cos_t));
}

fn phong_n_plus_2_pow(c: f32, e: f32) -> f32 {
    return select(0.0, pow(max(c, 1e-30), e), c > 0.0);
}

fn sample_bsdf_technique(wo: vec3f, m: PhongMaterial, u: vec2f, u_lobe: f32) -> vec3f {
    let mirror = vec3f(-wo.x, -wo.y, wo.z);
    if (u_lobe < m.specular_probability) {
        return phong_n_plus_2_direction(mirror, pow(u.x, 1.0 / (m.n + 1.0)), u.y);
    }
    return phong_n_plus_2_direction(vec3f(0.0, 0.0, 1.0), sqrt(u.x), u.y);
}

fn pdf_bsdf_technique(wo: vec3f, m: PhongMaterial, wi: vec3f) -> f32 {
    let mirror = vec3f(-wo.x, -wo.y, wo.z);
    let diffuse = max(wi.z, 0.0) / PI;
    // THE MISTAKE: (n + 2), the BRDF's normalisation, where the lobe's density has (n + 1).
    let specular = (m.n + 2.0) / (2.0 * PI) * phong_n_plus_2_pow(dot(wi, mirror), m.n);
    return (1.0 - m.specular_probability) * diffuse + m.specular_probability * specular;
}
