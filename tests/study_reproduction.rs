//! The study's own table, reproduced on its scene (issue 11): at 256x128, max_depth 2, 10 spp,
//! against a converged reference, under the scene's display transform (the study's
//! clip(x, 0, 1)^(1/1.6), declared in `assets/scenes/study.toml`'s `[display]` table), the mean
//! over 5 seeds of PSNR and SSIM must lie within 0.5 dB and 0.015 of the study's published
//! numbers: plain 8.785 dB / 0.120, cosine importance sampling 10.6 dB / 0.152.
//!
//! The reference is `best` (Sobol' + Phong + MIS, the lowest-variance method) at 8192 spp: its
//! display-image MSE against the 100,000-spp reference is below 1e-5, against about 0.13 for
//! plain at 10 spp (see the README, "Reproducing the study"), so its own error moves the PSNR
//! by far less than the tolerance. Deterministic: fixed seeds.

use crate::common;

use common::*;
use pathlab::display::Transfer;
use pathlab::method::Preset;
use pathlab::metrics::{psnr, ssim};

const SEEDS: u32 = 5;

#[test]
fn plain_and_cosine_at_10_spp_match_the_studys_published_numbers() {
    let mut scene = study_scene();
    assert_eq!(scene.display.transfer, Transfer::Gamma(1.6), "the study scene declares the study's display transform");
    assert_eq!(scene.render.max_depth, 2);
    scene.render.width = 256;
    scene.render.height = 128;
    let display = scene.display;
    let reference = display.film(&render(&scene, Preset::Best.method(), 8192, 4242));
    let mut failures = Vec::new();
    for (preset, study_psnr, study_ssim) in [(Preset::Plain, 8.785, 0.120), (Preset::Cosine, 10.6, 0.152)] {
        let (mut p, mut s) = (0.0, 0.0);
        for seed in 1..=SEEDS {
            let img = display.film(&render(&scene, preset.method(), 10, seed));
            p += psnr(&reference, &img) / SEEDS as f64;
            s += ssim(&reference, &img) / SEEDS as f64;
        }
        println!("{}: PSNR {p:.3} dB (study {study_psnr}), SSIM {s:.4} (study {study_ssim})", preset.name());
        if (p - study_psnr).abs() > 0.5 || (s - study_ssim).abs() > 0.015 {
            failures.push(format!("{}: {p:.3} dB / {s:.4} against the study's {study_psnr} / {study_ssim}", preset.name()));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
