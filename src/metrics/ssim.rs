//! SSIM (Wang et al. 2004) exactly as scikit-image's `structural_similarity(a, b,
//! channel_axis=2, data_range=1.0)` computes it by default: a 7x7 uniform window, K1 = 0.01,
//! K2 = 0.03, sample covariances (normalised by N - 1 with N = 49), the SSIM map averaged over
//! the pixels whose window lies inside the image (scikit-image crops 3 pixels at each border,
//! so its boundary mode never matters), then over channels. All in f64.

use crate::display::DisplayImage;

/// Window side.
const WIN: usize = 7;
const K1: f64 = 0.01;
const K2: f64 = 0.03;

/// Sums of `v` over every `WIN` x `WIN` window that lies inside a `w` x `h` image: an
/// `(w - WIN + 1) x (h - WIN + 1)` image (separable: rows, then columns).
fn window_sums(v: &[f64], w: usize, h: usize) -> Vec<f64> {
    let ow = w - WIN + 1;
    let oh = h - WIN + 1;
    let mut rows = vec![0.0; ow * h];
    for y in 0..h {
        let line = &v[y * w..(y + 1) * w];
        for x in 0..ow {
            rows[y * ow + x] = line[x..x + WIN].iter().sum();
        }
    }
    let mut out = vec![0.0; ow * oh];
    for y in 0..oh {
        for x in 0..ow {
            out[y * ow + x] = (0..WIN).map(|k| rows[(y + k) * ow + x]).sum();
        }
    }
    out
}

/// Mean SSIM of one channel.
fn ssim_channel(a: &[f64], b: &[f64], w: usize, h: usize) -> f64 {
    let n = (WIN * WIN) as f64;
    let cov_norm = n / (n - 1.0);
    let (c1, c2) = ((K1 * 1.0).powi(2), (K2 * 1.0).powi(2));
    let products = |f: &dyn Fn(f64, f64) -> f64| -> Vec<f64> { a.iter().zip(b).map(|(&x, &y)| f(x, y)).collect() };
    let ux = window_sums(a, w, h);
    let uy = window_sums(b, w, h);
    let uxx = window_sums(&products(&|x, _| x * x), w, h);
    let uyy = window_sums(&products(&|_, y| y * y), w, h);
    let uxy = window_sums(&products(&|x, y| x * y), w, h);
    let mut total = 0.0;
    for i in 0..ux.len() {
        let (mx, my) = (ux[i] / n, uy[i] / n);
        let vx = cov_norm * (uxx[i] / n - mx * mx);
        let vy = cov_norm * (uyy[i] / n - my * my);
        let vxy = cov_norm * (uxy[i] / n - mx * my);
        total += ((2.0 * mx * my + c1) * (2.0 * vxy + c2)) / ((mx * mx + my * my + c1) * (vx + vy + c2));
    }
    total / ux.len() as f64
}

/// Mean SSIM of two display images of the same size, at least 7x7 (the caller checks).
pub fn ssim(a: &DisplayImage, b: &DisplayImage) -> f64 {
    let (w, h) = (a.width as usize, a.height as usize);
    assert!(w >= WIN && h >= WIN && (a.width, a.height) == (b.width, b.height), "ssim: images must match and be at least 7x7");
    let channel = |img: &DisplayImage, c: usize| -> Vec<f64> { img.pixels.iter().map(|p| p[c] as f64).collect() };
    (0..3).map(|c| ssim_channel(&channel(a, c), &channel(b, c), w, h)).sum::<f64>() / 3.0
}

/// Smallest image side SSIM accepts.
pub const MIN_SIZE: u32 = WIN as u32;
