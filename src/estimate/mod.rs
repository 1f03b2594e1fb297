//! Honest error estimates of a render in progress, without a reference, and the targets a
//! render can be asked to reach (`target`; the loop is `render::to_target`).
//!
//! The estimated relMSE is the study's relMSE with the unknown (x - ref)^2 replaced by its
//! expectation, the variance of the pixel mean: mean over pixels and channels of
//! var / (mean^2 + 0.01). Where the variance comes from depends on the sampler:
//!
//! - `independent`: the per-pixel sample variance / spp is an unbiased estimate of the variance
//!   of the mean (the samples are independent).
//! - low-discrepancy samplers (`halton`, `halton-scrambled`, `sobol`): the samples of a pixel are
//!   deliberately not independent, so the within-pixel variance overstates the error (by 10x and
//!   more where QMC works). The render is split into R independent randomisations (seeds: new
//!   Cranley-Patterson shifts or Owen scramblings), each an unbiased estimate; the spread of
//!   their means estimates the variance of their average, as randomised quasi-Monte Carlo does:
//!   var = sum_r (m_r - m)^2 / (R (R - 1)).
//!
//! The display-referred estimate (for `--target-psnr`) propagates each pixel's standard error
//! through the display transform g (`metrics::expected`: E[(g(X) - g(mu))^2] ~
//! ((g(m + s) - g(m - s)) / 2)^2 with s the standard error, the secant form of the delta method,
//! which also handles clipping).

pub mod target;

use serde::Serialize;

use crate::display::DisplayTransform;
use crate::metrics::expected::display_mse_from_variance;
use crate::metrics::linear::REL_MSE_EPSILON;
use crate::method::Sampler;
use crate::film::Film;

/// Randomisations of a low-discrepancy render.
pub const RANDOMISATIONS: u32 = 4;

/// How a sampler's error is estimated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Estimator {
    /// Per-pixel sample variance (independent samples).
    WithinPixel,
    /// Spread of the means of R independent randomisations.
    Randomisations(u32),
}

impl Estimator {
    /// The honest estimator for `sampler`.
    pub fn for_sampler(sampler: Sampler) -> Estimator {
        match sampler {
            Sampler::Independent => Estimator::WithinPixel,
            Sampler::Halton | Sampler::HaltonScrambled | Sampler::Sobol => Estimator::Randomisations(RANDOMISATIONS),
        }
    }

    /// Renders this estimator needs (each a seed of its own).
    pub fn renders(self) -> u32 {
        match self {
            Estimator::WithinPixel => 1,
            Estimator::Randomisations(r) => r,
        }
    }

    pub fn describe(self) -> String {
        match self {
            Estimator::WithinPixel => "within-pixel sample variance".into(),
            Estimator::Randomisations(r) => format!("spread of {r} independent randomisations"),
        }
    }
}

/// An estimate of the error of a film.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ErrorEstimate {
    /// Estimated relMSE (linear radiance).
    pub rel_mse: f64,
    /// Estimated PSNR of the display image (dB), when a display transform was given.
    pub psnr: Option<f64>,
    /// Samples per pixel behind it (all randomisations together).
    pub spp: u64,
}

/// Estimated relMSE of `mean` whose per-pixel variances of the mean are `variance`. The
/// denominator estimates ref^2 by mean^2 - var (E[mean^2] = ref^2 + var, clamped at 0): with
/// mean^2 alone, a pixel with a firefly would divide its own variance by its inflated mean and
/// hide most of its error.
pub fn rel_mse_from_variance(mean: &[[f32; 3]], variance: &[[f64; 3]]) -> f64 {
    let total: f64 = mean
        .iter()
        .zip(variance)
        .flat_map(|(m, v)| (0..3).map(move |c| v[c] / (((m[c] as f64).powi(2) - v[c]).max(0.0) + REL_MSE_EPSILON)))
        .sum();
    total / (3 * mean.len()).max(1) as f64
}

/// The estimate from per-pixel variances of the mean.
fn estimate(mean: &[[f32; 3]], variance: &[[f64; 3]], spp: u64, display: Option<&DisplayTransform>) -> ErrorEstimate {
    ErrorEstimate {
        rel_mse: rel_mse_from_variance(mean, variance),
        psnr: display.map(|d| 10.0 * (1.0 / display_mse_from_variance(mean, variance, d).max(1e-30)).log10()),
        spp,
    }
}

/// The within-pixel estimate of one film (right for independent samples).
pub fn within_pixel(film: &Film, display: Option<&DisplayTransform>) -> ErrorEstimate {
    let variance: Vec<[f64; 3]> = film.variance.iter().map(|v| v.map(|x| x as f64)).collect();
    estimate(&film.mean, &variance, film.spp, display)
}

/// The randomised-QMC estimate from R >= 2 independent randomisations of equal spp; returns
/// their average too (the image to keep).
pub fn randomisations(films: &[Film], display: Option<&DisplayTransform>) -> (Film, ErrorEstimate) {
    assert!(films.len() >= 2, "randomisations: need at least two");
    let r = films.len() as f64;
    let average = Film::mean_of(films);
    let variance: Vec<[f64; 3]> = (0..average.mean.len())
        .map(|i| {
            std::array::from_fn(|c| {
                let m = average.mean[i][c] as f64;
                films.iter().map(|f| (f.mean[i][c] as f64 - m).powi(2)).sum::<f64>() / (r * (r - 1.0))
            })
        })
        .collect();
    let e = estimate(&average.mean, &variance, average.spp, display);
    (average, e)
}

/// The honest estimate for a render made of `films` (one film for `WithinPixel`, R for
/// `Randomisations`), and the image to keep.
pub fn estimate_films(estimator: Estimator, films: &[Film], display: Option<&DisplayTransform>) -> (Film, ErrorEstimate) {
    match estimator {
        Estimator::WithinPixel => (films[0].clone(), within_pixel(&films[0], display)),
        Estimator::Randomisations(_) => randomisations(films, display),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn film(mean: f32, variance: f32, spp: u64) -> Film {
        Film { width: 2, height: 1, spp, mean: vec![[mean; 3]; 2], variance: vec![[variance; 3]; 2] }
    }

    #[test]
    fn within_pixel_is_variance_over_unbiased_mean_squared_plus_epsilon() {
        let e = within_pixel(&film(0.3, 0.001, 100), None);
        assert!((e.rel_mse - 0.001 / (0.09 - 0.001 + 0.01)).abs() < 1e-6);
        // mean^2 - var clamps at 0.
        let e = within_pixel(&film(0.01, 0.001, 100), None);
        assert!((e.rel_mse - 0.001 / 0.01).abs() < 1e-6);
    }

    #[test]
    fn randomisations_use_the_spread_of_their_means() {
        // Means 1 and 3: average 2, spread sum (1 + 1) / (2 * 1) = 1.
        let (avg, e) = randomisations(&[film(1.0, 0.5, 10), film(3.0, 0.5, 10)], None);
        assert_eq!(avg.mean[0][0], 2.0);
        assert_eq!(avg.spp, 20);
        assert!((e.rel_mse - 1.0 / (4.0 - 1.0 + 0.01)).abs() < 1e-9);
    }

    #[test]
    fn display_estimate_follows_the_slope_of_the_transform() {
        // Linear region of gamma 1 with no clipping: display MSE = variance.
        let d = DisplayTransform { transfer: crate::display::Transfer::Gamma(1.0), exposure: 0.0 };
        let e = within_pixel(&film(0.5, 1e-4, 100), Some(&d));
        assert!((e.psnr.unwrap() - 40.0).abs() < 1e-3);
        // Fully clipped pixels contribute nothing.
        let e = within_pixel(&film(5.0, 1e-4, 100), Some(&d));
        assert!(e.psnr.unwrap() > 200.0);
    }
}
