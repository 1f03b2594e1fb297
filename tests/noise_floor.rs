//! The noise floor of a comparison: two independent unbiased renders of the same scene differ by
//! their Monte Carlo noise alone, and the PSNR between them is predicted from their variance
//! channels through the display transform's derivative (`metrics::expected`). At 64x32 on the
//! study scene under its gamma-1.6 display, the measured display MSE pooled over several pairs
//! of seeds must match the pooled prediction within 0.3 dB, for `mis` (16 pairs at 4096 spp) and
//! `cosine` (8 pairs at 16384 spp).
//!
//! One pair's measured PSNR scatters around the prediction by about 0.3 dB (mis) and 0.15 dB
//! (cosine), standard deviation over the seeds measured while writing this test: the squared
//! differences are heavy-tailed (light paths through the glossy spheres). Pooled over 16 and 8
//! pairs that is about 0.08 and 0.05 dB, so 0.3 dB is about 4 and 6 standard deviations: a
//! correct prediction fails with probability below 1e-4. Leaving out one image's variance (the
//! prediction 3 dB too high) or the display transform's slope fails it.

use crate::common;

use pathlab::display::DisplayTransform;
use pathlab::method::Preset;
use pathlab::metrics::expected::expected_noise_error;
use pathlab::metrics::psnr::display_mse;

#[test]
fn psnr_between_independent_renders_is_predicted_by_their_variance() {
    let mut scene = common::study_scene();
    (scene.render.width, scene.render.height) = (64, 32);
    let display: DisplayTransform = scene.display;
    for (preset, spp, pairs) in [(Preset::Mis, 4096, 16u32), (Preset::Cosine, 16384, 8)] {
        let (mut measured, mut predicted) = (0.0, 0.0);
        for pair in 0..pairs {
            let a = common::render(&scene, preset.method(), spp, 100 + 2 * pair);
            let b = common::render(&scene, preset.method(), spp, 101 + 2 * pair);
            measured += display_mse(&display.film(&a), &display.film(&b));
            predicted += expected_noise_error(&a, &b, &display).0;
        }
        let db = |mse: f64| 10.0 * (pairs as f64 / mse).log10();
        println!("{} at {spp} spp, {pairs} pairs: measured {:.3} dB, predicted {:.3} dB", preset.name(), db(measured), db(predicted));
        assert!((db(measured) - db(predicted)).abs() < 0.3, "{}: measured {:.3} dB, predicted {:.3} dB", preset.name(), db(measured), db(predicted));
    }
}
