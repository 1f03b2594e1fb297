//! The error a comparison would show from noise alone: the display MSE (and PSNR) that two
//! unbiased images differing only by their Monte Carlo noise reach, predicted from their
//! per-pixel variances of the mean. A measured PSNR at this level says the two images agree up
//! to their noise; it does not say either is unbiased (the z-test does, `stats::z_test`).
//!
//! Through the display transform g (clipping and a power or sRGB curve), the difference of two
//! independent estimates with variances v_a and v_b has, to first order (the delta method),
//! E[(g(A) - g(B))^2] = g'(m)^2 (v_a + v_b). The derivative is taken as the secant over one
//! standard deviation, (g(m + s) - g(m - s)) / 2 with s = sqrt(v_a + v_b), which stays finite at
//! g's kink at 0 and flat beyond the clip, where a tangent would not.

use crate::display::DisplayTransform;
use crate::film::Film;

/// Expected display MSE (peak 1) of an image of means `mean` whose per-pixel variance of the
/// difference to its comparison is `variance`.
pub fn display_mse_from_variance(mean: &[[f32; 3]], variance: &[[f64; 3]], display: &DisplayTransform) -> f64 {
    let total: f64 = mean
        .iter()
        .zip(variance)
        .flat_map(|(m, v)| {
            (0..3).map(move |c| {
                let (x, s) = (m[c], v[c].max(0.0).sqrt() as f32);
                let half = (display.apply(x + s) - display.apply(x - s)) as f64 / 2.0;
                half * half
            })
        })
        .sum();
    total / (3 * mean.len()).max(1) as f64
}

/// The display MSE and PSNR (dB) that `test` against `reference` would reach from their noise
/// alone (both carry variances of the mean), evaluated at the reference's means.
pub fn expected_noise_error(test: &Film, reference: &Film, display: &DisplayTransform) -> (f64, f64) {
    let variance: Vec<[f64; 3]> =
        test.variance.iter().zip(&reference.variance).map(|(a, b)| std::array::from_fn(|c| a[c] as f64 + b[c] as f64)).collect();
    let mse = display_mse_from_variance(&reference.mean, &variance, display);
    (mse, 10.0 * (1.0 / mse.max(1e-30)).log10())
}
