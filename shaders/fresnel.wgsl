// fresnel.wgsl — the Fresnel terms the BSDFs share, Mitsuba 3's fresnel.h term for term: the
// reflectance of a dielectric interface (smooth and rough dielectrics, plastics' coatings) and of
// a conductor (smooth and rough conductors). The diffuse Fresnel reflectance, a constant of a
// material, is computed by the host (src/scene/bsdfs/plastic.rs).

// Fresnel's equations for unpolarised light at an interface of relative index eta, with
// cos_theta_i the cosine of the incident direction in the frame of the surface normal (< 0 from
// inside): the reflectance r, the cosine of the refracted direction (of the opposite sign; 0
// under total internal reflection, where r = 1) and the relative indices eta_it (towards the
// side refracted into over the side of incidence) and eta_ti = 1 / eta_it (Mitsuba's fresnel()).
struct FresnelDielectric {
    r: f32,
    cos_theta_t: f32,
    eta_it: f32,
    eta_ti: f32,
}

fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> FresnelDielectric {
    let outside = cos_theta_i >= 0.0;
    let rcp_eta = 1.0 / eta;
    let eta_it = select(rcp_eta, eta, outside);
    let eta_ti = select(eta, rcp_eta, outside);
    // Snell's law: the squared cosine of the refracted direction.
    let cos_theta_t_sqr = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * (eta_ti * eta_ti);
    let cos_i = abs(cos_theta_i);
    let cos_t = sqrt(max(cos_theta_t_sqr, 0.0));
    // The amplitudes of the reflected s- and p-polarised waves.
    let a_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
    let a_p = (cos_t - eta_it * cos_i) / (cos_t + eta_it * cos_i);
    var r = 0.5 * (a_s * a_s + a_p * a_p);
    // Index-matched (nothing reflects) and grazing incidence (everything does).
    if (eta == 1.0) {
        r = 0.0;
    } else if (cos_i == 0.0) {
        r = 1.0;
    }
    return FresnelDielectric(r, select(cos_t, -cos_t, cos_theta_i >= 0.0), eta_it, eta_ti);
}

// Fresnel reflectance of a conductor of complex index eta + i k (per channel, unpolarised),
// at cos(theta_i) > 0: the exact formula as Mitsuba writes it (fresnel_conductor).
fn fresnel_conductor(cos_theta_i: f32, eta: vec3f, k: vec3f) -> vec3f {
    let c2 = cos_theta_i * cos_theta_i;
    let s2 = 1.0 - c2;
    let s4 = s2 * s2;
    let temp_1 = eta * eta - k * k - vec3f(s2);
    let a2pb2 = sqrt(max(vec3f(0.0), temp_1 * temp_1 + 4.0 * k * k * eta * eta));
    // a^2 = (|a^2 + i b^2| + t) / 2 cancels where t < 0 (every metal: k > eta), and a GPU's
    // sqrt, which WGSL lets round by ulps, leaves a residue there whose root is far from 0 (F
    // of eta 0 + 1i, Mitsuba's "none", was 1 - 5.2e-4 on an NVIDIA H200). There the product
    // (|z| + t)(|z| - t) = 4 eta^2 k^2 gives a^2 = 2 eta^2 k^2 / (|z| - t), without cancelling.
    let a_2 = select(0.5 * (a2pb2 + temp_1), 2.0 * eta * eta * k * k / (a2pb2 - temp_1), temp_1 < vec3f(0.0));
    let a = sqrt(max(vec3f(0.0), a_2));
    let term_1 = a2pb2 + vec3f(c2);
    let term_2 = 2.0 * cos_theta_i * a;
    let r_s = (term_1 - term_2) / (term_1 + term_2);
    let term_3 = a2pb2 * c2 + vec3f(s4);
    let term_4 = term_2 * s2;
    let r_p = r_s * (term_3 - term_4) / (term_3 + term_4);
    return 0.5 * (r_s + r_p);
}
