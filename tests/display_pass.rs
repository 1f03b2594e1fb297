//! The viewer's display pass (`shaders/display.wgsl`) on the device against the CPU code it
//! must agree with: the display transform of `src/display.rs` for the radiance view, and the
//! relMSE terms / sample-variance estimate through the magma table for the false-colour views.
//! Runs on the test adapter (lavapipe in CI), no window; the accumulators are split into
//! several bands so that the band offsets are exercised.

use crate::common;

use common::{gpu, pipelines, study_scene};
use pathlab::display::{DisplayTransform, Transfer};
use pathlab::figures::colormap::magma_at;
use pathlab::method::Preset;
use pathlab::metrics::linear::rel_mse_map;
use pathlab::render::{Budget, Renderer};
use pathlab::film::Film;
use pathlab::display::View;
use pathlab::viewer::display_pass::{read_shown_rgb8, DisplayPass, GpuReference};

const W: u32 = 48;
const H: u32 = 24;

fn scene() -> pathlab::scene::Scene {
    let mut s = study_scene();
    s.render.width = W;
    s.render.height = H;
    s
}

/// Renders `spp` samples into a renderer whose accumulators are bands of 5 rows.
fn rendered(seed: u32, spp: u64) -> Renderer {
    let bytes = 5 * W as u64 * std::mem::size_of::<pathlab::film::AccumPixel>() as u64;
    let mut r = Renderer::with_band_bytes(gpu(), pipelines(), &scene(), Preset::Nee.method(), seed, bytes).unwrap();
    assert!(r.bands() > 1);
    r.render(Budget::Samples(spp), &std::sync::atomic::AtomicBool::new(false), |_| {}).unwrap();
    r
}

fn shown(renderer: &Renderer, reference: Option<&Film>, view: View, display: DisplayTransform) -> Vec<u8> {
    let g = gpu();
    let pass = DisplayPass::new(&g.device, &g.queue);
    let reference = reference.map(|f| GpuReference::new(&g.device, &g.queue, f));
    let image = pass.shown_image(&g.device, renderer, reference.as_ref());
    pass.run(&g.device, &g.queue, &image, view, display);
    read_shown_rgb8(&g.device, &g.queue, &image).unwrap()
}

/// Largest and mean absolute difference of two RGB8 images.
fn differences(a: &[u8], b: &[u8]) -> (u8, f64) {
    assert_eq!(a.len(), b.len());
    let max = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
    let mean = a.iter().zip(b).map(|(x, y)| x.abs_diff(*y) as f64).sum::<f64>() / a.len() as f64;
    (max, mean)
}

#[test]
fn radiance_view_is_the_display_transform_of_the_mean() {
    let r = rendered(3, 16);
    let film = r.film().unwrap();
    for display in [
        DisplayTransform::default(),
        DisplayTransform { transfer: Transfer::Gamma(1.6), exposure: 0.0 },
        DisplayTransform { transfer: Transfer::Srgb, exposure: -1.5 },
    ] {
        let gpu_bytes = shown(&r, None, View::Radiance, display);
        let cpu_bytes = display.film(&film).to_rgb8();
        // f32 on the device against f64 on the host: at most one step of rounding apart.
        let (max, _) = differences(&gpu_bytes, &cpu_bytes);
        assert!(max <= 1, "{display}: display pass differs from the CPU transform by {max}/255");
    }
}

/// Magma of log10(v) over [lo, hi], as RGB8.
fn false_colour(values: &[f64], (lo, hi): (f32, f32)) -> Vec<u8> {
    values.iter().flat_map(|&v| magma_at((v.max(1e-30).log10() - lo as f64) / (hi - lo) as f64)).collect()
}

#[test]
fn error_views_match_the_metrics_terms() {
    let r = rendered(5, 16);
    let film = r.film().unwrap();
    let reference = rendered(11, 64).film().unwrap();
    let display = DisplayTransform::default();

    // Relative squared error: the per-pixel terms of relMSE (metrics::linear).
    let expected = false_colour(&rel_mse_map(&film, &reference), View::RelError.log10_range());
    let (max, mean) = differences(&shown(&r, Some(&reference), View::RelError, display), &expected);
    // The device rounds in f32: a value on a table boundary may land on the neighbouring entry.
    assert!(mean < 0.5 && max <= 12, "relative error view: max {max}, mean {mean}");

    // Absolute error, channel mean.
    let abs: Vec<f64> = film
        .mean
        .iter()
        .zip(&reference.mean)
        .map(|(t, r)| (0..3).map(|c| (t[c] as f64 - r[c] as f64).abs()).sum::<f64>() / 3.0)
        .collect();
    let (max, mean) = differences(&shown(&r, Some(&reference), View::AbsError, display), &false_colour(&abs, View::AbsError.log10_range()));
    assert!(mean < 0.5 && max <= 12, "absolute error view: max {max}, mean {mean}");

    // Relative standard error from the film's own variance (as the relMSE estimate).
    let rel_stderr: Vec<f64> = film
        .mean
        .iter()
        .zip(&film.variance)
        .map(|(m, v)| {
            let terms: f64 = (0..3)
                .map(|c| {
                    let (m, v) = (m[c] as f64, v[c] as f64);
                    v / ((m * m - v).max(0.0) + 0.01)
                })
                .sum();
            (terms / 3.0).sqrt()
        })
        .collect();
    let (max, mean) = differences(&shown(&r, None, View::RelStderr, display), &false_colour(&rel_stderr, View::RelStderr.log10_range()));
    assert!(mean < 0.5 && max <= 12, "relative standard error view: max {max}, mean {mean}");
}
