// ggx_bounded_vndf.wgsl — a microfacet technique for reflection: Eto and Tokuyoshi's bounded
// visible normals ("Bounded VNDF Sampling for Smith-GGX Reflections", SIGGRAPH Asia 2023
// technical communications). Spherical-cap sampling (ggx_spherical_caps.wgsl) draws some
// normals whose mirror direction lies below the surface, samples a reflection-only BSDF wastes;
// the bounded cap z > -k wo_std.z, with
//   k = (1 - a^2) s^2 / (s^2 + a^2 wo.z^2),   s = 1 + |wo.xy|,   a = min(alpha, 1),
// leaves out a part of them (never a normal whose reflection is above the surface), and the
// density of every normal it can draw grows by the ratio of the caps' areas:
//   pdf(m) = D(m) G1(wo) max(0, wo.m) / cos(theta_o) x (1 + wo_std.z) / (1 + k wo_std.z).
// Valid for reflection only: a rough dielectric refracts about normals this never draws, so
// pathlab refuses it on a scene that has one. Beckmann normals: from the distribution.
//
//   pathlab check-technique bsdf:examples/techniques/ggx_bounded_vndf.wgsl --scene assets/scenes/cornell_conductors.xml

// The bound: the cap's lowest z, -b.
fn ggx_bounded_vndf_b(wo: vec3f, alpha: f32, wo_std: vec3f) -> f32 {
    let a = min(alpha, 1.0);
    let s = 1.0 + length(wo.xy);
    let a2 = a * a;
    let s2 = s * s;
    let k = (1.0 - a2) * s2 / (s2 + a2 * wo.z * wo.z);
    return k * wo_std.z;
}

fn sample_microfacet_technique(wo: vec3f, alpha: f32, distribution: u32, u: vec2f) -> vec3f {
    if (distribution != DISTRIBUTION_GGX) {
        return sample_microfacet_ndf(u, alpha, distribution);
    }
    let wo_std = normalize(vec3f(wo.xy * alpha, wo.z));
    let b = ggx_bounded_vndf_b(wo, alpha, wo_std);
    let phi = 2.0 * PI * u.x;
    let z = (1.0 - u.y) * (1.0 + b) - b;
    let sin_theta = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    let h = vec3f(sin_theta * cos(phi), sin_theta * sin(phi), z) + wo_std;
    return normalize(vec3f(h.xy * alpha, h.z));
}

fn pdf_microfacet_technique(wo: vec3f, m: vec3f, alpha: f32, distribution: u32) -> f32 {
    let d = eval_microfacet_d(m, alpha, distribution);
    if (distribution != DISTRIBUTION_GGX) {
        return d * m.z;
    }
    let stretched = vec3f(wo.xy * alpha, wo.z);
    let t = length(stretched);
    let wo_std = stretched / t;
    let b = ggx_bounded_vndf_b(wo, alpha, wo_std);
    // The cap's point c of normal m: wo_std reflected about the stretched normal.
    let m_std = normalize(vec3f(m.xy / alpha, m.z));
    let c_z = 2.0 * dot(m_std, wo_std) * m_std.z - wo_std.z;
    let g1 = 2.0 * wo.z / (wo.z + t);
    let vndf = d * g1 * dot(wo, m) / wo.z;
    return select(0.0, vndf * (1.0 + wo_std.z) / (1.0 + b), dot(wo, m) > 0.0 && c_z >= -b);
}
