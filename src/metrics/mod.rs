//! Image metrics, one place for the study, `pathlab compare` and the viewer.
//!
//! - `linear`: on linear radiance: MSE, relative MSE, the mean bias per channel;
//! - `psnr`, `ssim`, `flip`: on the display image (see `display`), matching scikit-image and
//!   NVIDIA's FLIP (tested against values those libraries computed, `tests/metrics_fixtures.rs`);
//! - `compare`: all of them for a pair of films, with the z-test verdict of the correctness
//!   suite when both carry variances, and (`expected`) the display MSE and PSNR their noise
//!   alone would give.

pub mod expected;
pub mod flip;
pub mod linear;
pub mod psnr;
pub mod ssim;

use serde::Serialize;

use crate::display::DisplayTransform;
use crate::film::Film;
use crate::stats::{z_test, ZTest};

pub use flip::flip;
pub use linear::{mean_bias, mse, rel_mse, rel_mse_map, ChannelBias};
pub use psnr::psnr;
pub use ssim::ssim;

/// Significance of the per-pixel z-test in `compare` (Šidák-corrected over all channels).
pub const Z_TEST_ALPHA: f64 = 0.01;
/// Share of channels that must pass the z-test (the correctness suite's protocol).
pub const Z_TEST_MIN_PASS: f64 = 0.9975;

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum MetricsError {
    #[error("the images differ in size: {0}x{1} against {2}x{3}")]
    SizeMismatch(u32, u32, u32, u32),
    #[error("the images are {0}x{1}; SSIM needs at least 7x7 pixels")]
    TooSmall(u32, u32),
    #[error("z-test blocks of {0}x{0} pixels must divide the image size {1}x{2}")]
    Block(u32, u32, u32),
}

/// The z-test of the correctness suite, summarised.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ZTestSummary {
    /// Side of the pixel blocks tested (1: per pixel).
    pub block: u32,
    pub alpha: f64,
    pub pass_fraction: f64,
    pub threshold: f64,
    pub max_abs_z: f64,
    pub mean_z: f64,
    pub channels: usize,
    /// pass_fraction >= 0.9975.
    pub passed: bool,
}

impl From<ZTest> for ZTestSummary {
    fn from(z: ZTest) -> Self {
        ZTestSummary {
            block: 1,
            alpha: Z_TEST_ALPHA,
            pass_fraction: z.pass_fraction,
            threshold: z.threshold,
            max_abs_z: z.max_abs_z,
            mean_z: z.mean_z,
            channels: z.channels,
            passed: z.pass_fraction >= Z_TEST_MIN_PASS,
        }
    }
}

/// Every metric of a test image against a reference.
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    pub width: u32,
    pub height: u32,
    pub mse: f64,
    pub rel_mse: f64,
    /// Mean bias per channel (R, G, B).
    pub bias: [ChannelBias; 3],
    /// The display transform of PSNR, SSIM and FLIP.
    pub display: String,
    pub psnr: f64,
    pub ssim: f64,
    pub flip: f64,
    /// The display MSE (peak 1: the study's L2 on the display image) and PSNR.
    pub display_mse: f64,
    /// When both images carry variances: the display MSE and PSNR their noise alone would give
    /// (two independent unbiased renders reach these; `expected`).
    pub expected_display_mse: Option<f64>,
    pub expected_psnr: Option<f64>,
    /// Per-pixel z-test, when both images carry variances.
    pub z_test: Option<ZTestSummary>,
}

/// Checks that two films can be compared.
pub fn check_sizes(test: &Film, reference: &Film) -> Result<(), MetricsError> {
    if (test.width, test.height) != (reference.width, reference.height) {
        return Err(MetricsError::SizeMismatch(test.width, test.height, reference.width, reference.height));
    }
    if test.width < ssim::MIN_SIZE || test.height < ssim::MIN_SIZE {
        return Err(MetricsError::TooSmall(test.width, test.height));
    }
    Ok(())
}

/// Every metric of `test` against `reference`; `with_variance` says both films carry
/// meaningful variances (then the per-pixel z-test runs).
pub fn compare(test: &Film, reference: &Film, display: DisplayTransform, with_variance: bool) -> Result<Comparison, MetricsError> {
    compare_blocks(test, reference, display, with_variance, 1)
}

/// Like `compare`, with the z-test on `block` x `block` pixel blocks (block means and their
/// variances), as the correctness suite tests methods whose per-pixel estimates are too
/// heavy-tailed for a normal approximation. `block` must divide both sides.
pub fn compare_blocks(test: &Film, reference: &Film, display: DisplayTransform, with_variance: bool, block: u32) -> Result<Comparison, MetricsError> {
    check_sizes(test, reference)?;
    if block == 0 || test.width % block != 0 || test.height % block != 0 {
        return Err(MetricsError::Block(block, test.width, test.height));
    }
    let (t, r) = (display.film(test), display.film(reference));
    let expected = with_variance.then(|| expected::expected_noise_error(test, reference, &display));
    Ok(Comparison {
        display_mse: psnr::display_mse(&r, &t),
        expected_display_mse: expected.map(|e| e.0),
        expected_psnr: expected.map(|e| e.1),
        width: test.width,
        height: test.height,
        mse: mse(test, reference),
        rel_mse: rel_mse(test, reference),
        bias: mean_bias(test, reference),
        display: display.to_string(),
        psnr: psnr(&r, &t),
        ssim: ssim(&r, &t),
        flip: flip(&r, &t),
        z_test: with_variance.then(|| {
            let z = if block > 1 {
                z_test(&reference.downsample(block), &test.downsample(block), Z_TEST_ALPHA)
            } else {
                z_test(reference, test, Z_TEST_ALPHA)
            };
            ZTestSummary { block, ..z.into() }
        }),
    })
}
