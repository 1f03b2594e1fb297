// ggx_spherical_caps.wgsl — a microfacet technique: GGX's visible normals drawn by Dupuy and
// Benyoub's spherical caps ("Sampling Visible GGX Normals with Spherical Caps", HPG 2023), for
// isotropic and anisotropic roughness (the contract's pair of (alpha_u, alpha_v)): in the
// configuration where the roughness is 1 (wo stretched by alpha_u along x and alpha_v along y),
// the visible normals' halfway vectors are c + wo with c uniform on the spherical cap
// z > -wo.z; unstretching gives the normal. Its density is the visible-normal distribution
// itself, D(m) G1(wo) max(0, wo.m) / cos(theta_o), the density of pathlab's built-in
// `--microfacet-sampling vndf` (Heitz 2018), drawn with fewer operations. Beckmann normals are
// drawn from the distribution (pathlab's sample_microfacet_ndf_uv, density D(m) cos(theta_m)).
//
//   pathlab check-technique bsdf:examples/techniques/ggx_spherical_caps.wgsl --scene assets/scenes/cornell_conductors.xml
//   pathlab check-technique bsdf:examples/techniques/ggx_spherical_caps.wgsl --scene tests/fixtures/anisotropic/anisotropic.xml

fn sample_microfacet_uv_technique(wo: vec3f, alpha_uv: vec2f, distribution: u32, u: vec2f) -> vec3f {
    if (distribution != DISTRIBUTION_GGX) {
        return sample_microfacet_ndf_uv(u, alpha_uv, distribution);
    }
    let wo_std = normalize(vec3f(wo.xy * alpha_uv, wo.z));
    // c uniform on the cap of the unit sphere above z = -wo_std.z.
    let phi = 2.0 * PI * u.x;
    let z = (1.0 - u.y) * (1.0 + wo_std.z) - wo_std.z;
    let sin_theta = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    let h = vec3f(sin_theta * cos(phi), sin_theta * sin(phi), z) + wo_std;
    return normalize(vec3f(h.xy * alpha_uv, h.z));
}

fn pdf_microfacet_uv_technique(wo: vec3f, m: vec3f, alpha_uv: vec2f, distribution: u32) -> f32 {
    let d = eval_microfacet_d_uv(m, alpha_uv, distribution);
    if (distribution != DISTRIBUTION_GGX) {
        return d * m.z;
    }
    // GGX's Smith G1(wo) = 2 cos / (cos + |stretched wo|); 0 for a normal wo cannot see.
    let t = length(vec3f(wo.xy * alpha_uv, wo.z));
    let g1 = 2.0 * wo.z / (wo.z + t);
    return select(0.0, d * g1 * dot(wo, m) / wo.z, dot(wo, m) > 0.0);
}
