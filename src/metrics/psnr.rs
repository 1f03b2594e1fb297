//! PSNR on display images with peak 1, as scikit-image's
//! `peak_signal_noise_ratio(ref, test, data_range=1)`: 10 log10(1 / MSE), the MSE over every
//! pixel and channel in f64.

use crate::display::DisplayImage;

/// The mean squared difference of two display images over every pixel and channel (the study's
/// L2 on the display image).
pub fn display_mse(a: &DisplayImage, b: &DisplayImage) -> f64 {
    let n = (a.pixels.len() * 3).max(1) as f64;
    a.pixels.iter().zip(&b.pixels).flat_map(|(x, y)| (0..3).map(move |c| (x[c] as f64 - y[c] as f64).powi(2))).sum::<f64>() / n
}

/// PSNR in dB (infinite for identical images).
pub fn psnr(a: &DisplayImage, b: &DisplayImage) -> f64 {
    10.0 * (1.0 / display_mse(a, b)).log10()
}
