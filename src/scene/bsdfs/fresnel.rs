//! The host's Fresnel term of a dielectric interface, for the tables materials precompute
//! (roughplastic's transmittance, plastic's checks): Mitsuba 3's `fresnel()` (fresnel.h) in
//! f64. The kernel's is `shaders/fresnel.wgsl`.

/// Fresnel's equations for unpolarised light at an interface of relative index `eta` (inside
/// over outside), `cos_theta_i` the incident cosine against the normal (< 0 from inside):
/// the reflectance and the cosine of the refracted direction, of the opposite sign (0 under
/// total internal reflection, where the reflectance is 1).
pub(crate) fn fresnel_dielectric(cos_theta_i: f64, eta: f64) -> (f64, f64) {
    let outside = cos_theta_i >= 0.0;
    let (eta_it, eta_ti) = if outside { (eta, 1.0 / eta) } else { (1.0 / eta, eta) };
    // Snell's law: the squared cosine of the refracted direction.
    let cos_t2 = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
    let cos_i = cos_theta_i.abs();
    let cos_t = cos_t2.max(0.0).sqrt();
    // The amplitudes of the reflected s- and p-polarised waves.
    let a_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
    let a_p = (cos_t - eta_it * cos_i) / (cos_t + eta_it * cos_i);
    let r = if eta == 1.0 {
        0.0
    } else if cos_i == 0.0 || cos_t2 <= 0.0 {
        1.0
    } else {
        0.5 * (a_s * a_s + a_p * a_p)
    };
    (r, if outside { -cos_t } else { cos_t })
}
