//! Errors on linear radiance: MSE, relative MSE and the mean bias per channel.
//!
//! Relative MSE is the mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01): the
//! squared error relative to the reference value, with 0.01 keeping dark pixels from
//! dominating (as in the adaptive-sampling and denoising literature, e.g. Rousselle et al.).

use serde::Serialize;

use crate::film::Film;
use crate::stats::normal_quantile;

/// The constant added to ref^2 in the relative MSE's denominator.
pub const REL_MSE_EPSILON: f64 = 0.01;

/// Mean over pixels and channels of (x - ref)^2.
pub fn mse(test: &Film, reference: &Film) -> f64 {
    mean_over_channels(test, reference, |x, r| (x - r) * (x - r))
}

/// Mean over pixels and channels of (x - ref)^2 / (ref^2 + 0.01).
pub fn rel_mse(test: &Film, reference: &Film) -> f64 {
    mean_over_channels(test, reference, |x, r| (x - r) * (x - r) / (r * r + REL_MSE_EPSILON))
}

/// Per-pixel relative squared error, averaged over the channels (the terms of `rel_mse`).
pub fn rel_mse_map(test: &Film, reference: &Film) -> Vec<f64> {
    test.mean
        .iter()
        .zip(&reference.mean)
        .map(|(t, r)| (0..3).map(|c| rel_sq(t[c] as f64, r[c] as f64)).sum::<f64>() / 3.0)
        .collect()
}

/// One term of relMSE: (x - ref)^2 / (ref^2 + 0.01).
pub fn rel_sq(x: f64, r: f64) -> f64 {
    (x - r) * (x - r) / (r * r + REL_MSE_EPSILON)
}

fn mean_over_channels(test: &Film, reference: &Film, f: impl Fn(f64, f64) -> f64) -> f64 {
    let total: f64 = test
        .mean
        .iter()
        .zip(&reference.mean)
        .flat_map(|(t, r)| (0..3).map(move |c| (t[c] as f64, r[c] as f64)))
        .map(|(x, r)| f(x, r))
        .sum();
    total / (3 * test.mean.len()).max(1) as f64
}

/// The image-mean difference of one channel, test - reference, and relative to the reference.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ChannelBias {
    /// mean(test) - mean(reference).
    pub bias: f64,
    /// Its standard error from both images' per-pixel variances of the mean (pixels
    /// independent); `None` when neither image carries variances.
    pub std_error: Option<f64>,
    /// mean(reference) of this channel.
    pub reference_mean: f64,
}

impl ChannelBias {
    /// bias / reference mean.
    pub fn relative(&self) -> f64 {
        self.bias / self.reference_mean.abs().max(1e-30)
    }

    /// z = bias / standard error.
    pub fn z(&self) -> Option<f64> {
        self.std_error.filter(|&s| s > 0.0).map(|s| self.bias / s)
    }

    /// Half-width of the two-sided confidence interval of the relative bias at `confidence`.
    pub fn relative_half_width(&self, confidence: f64) -> Option<f64> {
        let q = normal_quantile(0.5 + confidence / 2.0);
        self.std_error.map(|s| q * s / self.reference_mean.abs().max(1e-30))
    }
}

/// Mean bias of `test` against `reference` per channel. Variances are used when present (a
/// film whose variance is all zero contributes none).
pub fn mean_bias(test: &Film, reference: &Film) -> [ChannelBias; 3] {
    let n = test.mean.len().max(1) as f64;
    let has_var = |f: &Film| f.variance.iter().flatten().any(|&v| v > 0.0);
    let with_var = has_var(test) || has_var(reference);
    std::array::from_fn(|c| {
        let mt: f64 = test.mean.iter().map(|p| p[c] as f64).sum::<f64>() / n;
        let mr: f64 = reference.mean.iter().map(|p| p[c] as f64).sum::<f64>() / n;
        let var: f64 = test.variance.iter().zip(&reference.variance).map(|(a, b)| a[c] as f64 + b[c] as f64).sum::<f64>() / (n * n);
        ChannelBias { bias: mt - mr, std_error: with_var.then(|| var.sqrt()), reference_mean: mr }
    })
}
