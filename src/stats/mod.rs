//! Statistics for the correctness suite and the study: normal quantiles, the Šidák correction,
//! the per-pixel z-test between two renders (Mitsuba 3's `test_renders.py` protocol), and the
//! chi-square distribution, and power-law fits (`fit`). The distributions themselves come from
//! `statrs`.

mod fit;

pub use fit::{Fit, MAX_EXTRAPOLATION};

use statrs::distribution::{ChiSquared, ContinuousCDF, Normal, StudentsT};

use crate::film::Film;

/// Φ⁻¹(p): the standard normal quantile (statrs).
pub fn normal_quantile(p: f64) -> f64 {
    assert!(p > 0.0 && p < 1.0, "normal_quantile({p})");
    Normal::standard().inverse_cdf(p)
}

/// Φ(x): the standard normal distribution function (statrs).
pub fn normal_cdf(x: f64) -> f64 {
    Normal::standard().cdf(x)
}

/// Two-sided Student's t quantile: the t with P(|T| <= t) = `confidence` for `dof` degrees of
/// freedom (statrs); for confidence intervals of a mean over a few seeds.
pub fn student_t_two_sided(confidence: f64, dof: f64) -> f64 {
    assert!(confidence > 0.0 && confidence < 1.0 && dof > 0.0, "student_t_two_sided({confidence}, {dof})");
    let t = StudentsT::new(0.0, 1.0, dof).expect("valid Student's t");
    t.inverse_cdf(0.5 + confidence / 2.0)
}

/// Per-test significance level that keeps the family-wise false-failure probability at `alpha`
/// over `m` independent tests (Šidák): 1 - (1 - alpha)^(1/m).
pub fn sidak(alpha: f64, m: usize) -> f64 {
    // -expm1(log1p(-alpha) / m): no cancellation for tiny alpha or huge m.
    -((-alpha).ln_1p() / m as f64).exp_m1()
}

/// Two-sided |z| threshold for significance `alpha` over `m` tests (Šidák-corrected).
pub fn z_threshold(alpha: f64, m: usize) -> f64 {
    normal_quantile(1.0 - sidak(alpha, m) / 2.0)
}

/// Outcome of a per-pixel z-test of `test` against `reference`.
#[derive(Debug, Clone, Copy)]
pub struct ZTest {
    /// Fraction of pixel channels with |z| below the threshold.
    pub pass_fraction: f64,
    pub threshold: f64,
    /// Largest |z| seen.
    pub max_abs_z: f64,
    /// Mean of z over all channels (a bias shows as a mean far from 0).
    pub mean_z: f64,
    pub channels: usize,
}

/// z = (mean_test - mean_ref) / sqrt(var_ref + var_test + rounding^2) per pixel channel, where
/// the films' variances are variances of the mean and `rounding` = 2e-5 max(|mean_ref|,
/// |mean_test|) is the accumulated rounding of f32 sums, which no variance estimate sees: a
/// region of constant radiance has variance 0 on both sides, yet Mitsuba 3's llvm_ad_rgb shows
/// an emitter of radiance 7.59909 as 7.599115 (3.3e-6 above it) and a constant sky of 0.18 as
/// 0.17999795 after 65536 samples (1.1e-5 below). Šidák-corrected threshold for `alpha` over
/// all channels.
pub fn z_test(reference: &Film, test: &Film, alpha: f64) -> ZTest {
    assert_eq!((reference.width, reference.height), (test.width, test.height), "z_test: image sizes differ");
    let channels = reference.mean.len() * 3;
    let threshold = z_threshold(alpha, channels);
    let (mut passed, mut max_abs_z, mut sum_z) = (0usize, 0.0f64, 0.0f64);
    for i in 0..reference.mean.len() {
        for c in 0..3 {
            let (a, b) = (reference.mean[i][c] as f64, test.mean[i][c] as f64);
            let rounding = ROUNDING * a.abs().max(b.abs());
            let var = reference.variance[i][c] as f64 + test.variance[i][c] as f64 + rounding * rounding;
            if var > 0.0 {
                let z = (b - a) / var.sqrt();
                sum_z += z;
                max_abs_z = max_abs_z.max(z.abs());
                passed += (z.abs() <= threshold) as usize;
            } else {
                // Both black, exactly.
                passed += (a == b) as usize;
            }
        }
    }
    ZTest { pass_fraction: passed as f64 / channels as f64, threshold, max_abs_z, mean_z: sum_z / channels as f64, channels }
}

/// Relative rounding of a mean accumulated in f32 (`z_test`).
const ROUNDING: f64 = 2e-5;

/// Mean over the image and its standard error, from per-pixel variances of the mean (pixels
/// independent), for one channel.
pub fn image_mean_and_error(film: &Film, channel: usize) -> (f64, f64) {
    let n = film.mean.len() as f64;
    let mean = film.mean.iter().map(|p| p[channel] as f64).sum::<f64>() / n;
    let var = film.variance.iter().map(|p| p[channel] as f64).sum::<f64>() / (n * n);
    (mean, var.sqrt())
}

/// P(X >= x) for X ~ chi-square with `dof` degrees of freedom (statrs).
pub fn chi2_sf(x: f64, dof: usize) -> f64 {
    ChiSquared::new(dof as f64).expect("dof > 0").sf(x)
}

#[cfg(test)]
mod chi2_tests {
    #[test]
    fn chi_square_tail() {
        // Reference values (scipy.stats.chi2.sf).
        assert!((super::chi2_sf(3.84145882, 1) - 0.05).abs() < 1e-7);
        assert!((super::chi2_sf(124.342, 100) - 0.05).abs() < 1e-5);
        assert!((super::chi2_sf(10.0, 10) - 0.440493285).abs() < 1e-7);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles() {
        assert!((normal_quantile(0.975) - 1.959963984540054).abs() < 1e-6);
        assert!((normal_quantile(0.5)).abs() < 1e-7);
        assert!((normal_quantile(1e-10) + 6.361340902404056).abs() < 1e-6);
        // scipy.stats.t.ppf(0.995, 2) and (0.975, 4)
        assert!((student_t_two_sided(0.99, 2.0) - 9.924843200918276).abs() < 1e-6);
        assert!((student_t_two_sided(0.95, 4.0) - 2.7764451051977987).abs() < 1e-6);
    }

    #[test]
    fn sidak_correction() {
        assert!((sidak(0.01, 1) - 0.01).abs() < 1e-15);
        let s = sidak(0.01, 1000);
        assert!((1.0 - (1.0 - s).powi(1000) - 0.01).abs() < 1e-12);
    }
}
