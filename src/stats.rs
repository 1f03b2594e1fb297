//! Statistics for the correctness suite and the study: normal quantiles, the Šidák correction,
//! the per-pixel z-test between two renders (Mitsuba 3's `test_renders.py` protocol), and the
//! chi-square distribution.

use crate::render::Film;

/// Φ⁻¹(p): the standard normal quantile (Acklam's rational approximation, refined by one
/// Halley step against `erfc`).
pub fn normal_quantile(p: f64) -> f64 {
    assert!(p > 0.0 && p < 1.0, "normal_quantile({p})");
    const A: [f64; 6] =
        [-3.969683028665376e1, 2.209460984245205e2, -2.759285104469687e2, 1.383577518672690e2, -3.066479806614716e1, 2.506628277459239];
    const B: [f64; 5] = [-5.447609879822406e1, 1.615858368580409e2, -1.556989798598866e2, 6.680131188771972e1, -1.328068155288572e1];
    const C: [f64; 6] =
        [-7.784894002430293e-3, -3.223964580411365e-1, -2.400758277161838, -2.549732539343734, 4.374664141464968, 2.938163982698783];
    const D: [f64; 4] = [7.784695709041462e-3, 3.224671290700398e-1, 2.445134137142996, 3.754408661907416];
    let p_low = 0.02425;
    let x = if p < p_low {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5]) / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - p_low {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        let q = (-2.0 * (1.0 - p).ln()).sqrt();
        -(((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5]) / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    // One Halley step on Φ(x) - p.
    let e = 0.5 * erfc(-x / std::f64::consts::SQRT_2) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (x * x / 2.0).exp();
    x - u / (1.0 + x * u / 2.0)
}

/// Complementary error function (Numerical Recipes' erfcc: relative error < 1.2e-7, which
/// bounds the accuracy of `normal_quantile` to about 1e-7 as well: ample for test thresholds).
pub fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.26551223
            + t * (1.00002368
                + t * (0.37409196
                    + t * (0.09678418
                        + t * (-0.18628806 + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))
            .exp();
    if x >= 0.0 { r } else { 2.0 - r }
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

/// z = (mean_test - mean_ref) / sqrt(var_ref + var_test) per pixel channel, where the films'
/// variances are variances of the mean; Šidák-corrected threshold for `alpha` over all channels.
/// Channels where both variances are 0 pass only when the means agree to 1e-6 relative.
pub fn z_test(reference: &Film, test: &Film, alpha: f64) -> ZTest {
    assert_eq!((reference.width, reference.height), (test.width, test.height), "z_test: image sizes differ");
    let channels = reference.mean.len() * 3;
    let threshold = z_threshold(alpha, channels);
    let (mut passed, mut max_abs_z, mut sum_z) = (0usize, 0.0f64, 0.0f64);
    for i in 0..reference.mean.len() {
        for c in 0..3 {
            let (a, b) = (reference.mean[i][c] as f64, test.mean[i][c] as f64);
            let var = reference.variance[i][c] as f64 + test.variance[i][c] as f64;
            if var > 0.0 {
                let z = (b - a) / var.sqrt();
                sum_z += z;
                max_abs_z = max_abs_z.max(z.abs());
                passed += (z.abs() <= threshold) as usize;
            } else {
                passed += ((b - a).abs() <= 1e-6 * a.abs().max(1.0)) as usize;
            }
        }
    }
    ZTest { pass_fraction: passed as f64 / channels as f64, threshold, max_abs_z, mean_z: sum_z / channels as f64, channels }
}

/// Mean over the image and its standard error, from per-pixel variances of the mean (pixels
/// independent), for one channel.
pub fn image_mean_and_error(film: &Film, channel: usize) -> (f64, f64) {
    let n = film.mean.len() as f64;
    let mean = film.mean.iter().map(|p| p[channel] as f64).sum::<f64>() / n;
    let var = film.variance.iter().map(|p| p[channel] as f64).sum::<f64>() / (n * n);
    (mean, var.sqrt())
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
pub fn ln_gamma(x: f64) -> f64 {
    const G: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection formula.
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let series = G[1..].iter().enumerate().fold(G[0], |acc, (i, g)| acc + g / (x + i as f64 + 1.0));
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

/// Regularised upper incomplete gamma Q(a, x) = Γ(a, x) / Γ(a) (series below a + 1, Lentz's
/// continued fraction above, as in Numerical Recipes' gammq).
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let ln_prefix = -x + a * x.ln() - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        1.0 - sum * ln_prefix.exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        h * ln_prefix.exp()
    }
}

/// P(X >= x) for X ~ chi-square with `dof` degrees of freedom.
pub fn chi2_sf(x: f64, dof: usize) -> f64 {
    gamma_q(dof as f64 / 2.0, x / 2.0)
}

#[cfg(test)]
mod chi2_tests {
    #[test]
    fn chi_square_tail() {
        // Reference values (scipy.stats.chi2.sf).
        assert!((super::chi2_sf(3.84145882, 1) - 0.05).abs() < 1e-7);
        assert!((super::chi2_sf(124.342, 100) - 0.05).abs() < 1e-5);
        assert!((super::chi2_sf(10.0, 10) - 0.440493285).abs() < 1e-7);
        assert!((super::ln_gamma(10.0) - 362880f64.ln()).abs() < 1e-12);
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
    }

    #[test]
    fn sidak_correction() {
        assert!((sidak(0.01, 1) - 0.01).abs() < 1e-15);
        let s = sidak(0.01, 1000);
        assert!((1.0 - (1.0 - s).powi(1000) - 0.01).abs() < 1e-12);
    }
}
