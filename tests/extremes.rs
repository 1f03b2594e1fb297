//! Numerical stability at the extremes (issue 3, section 5): every preset renders every scene
//! of `assets/scenes/extremes/` with no NaN or inf and no negative radiance, and matches the
//! answer where one is known. Known answers are z-tested (Šidák-corrected over all checks of
//! this file, family alpha 1e-4: the false-failure probability of the file).

use crate::common;

use std::path::Path;
use std::sync::atomic::AtomicBool;

use common::*;
use pathlab::method::{Method, Preset, Sampler};
use pathlab::render::{Budget, Renderer};
use pathlab::scene::Scene;
use pathlab::stats::{image_mean_and_error, z_test, z_threshold};

const ALPHA: f64 = 1e-4;

fn extreme(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/extremes").join(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// What is known of each scene's image.
enum Known {
    /// Every pixel converges to this value.
    EveryPixel(f32),
    /// The image mean converges to this value.
    ImageMean(f64),
    /// Only finiteness and non-negativity.
    Nothing,
}

const SCENES: [(&str, Known); 7] = [
    ("huge_sphere_wall.toml", Known::EveryPixel(1.0)),
    ("tiny_sphere.toml", Known::EveryPixel(1.0)),
    ("far_away.toml", Known::EveryPixel(1.0)),
    ("grazing_plane.toml", Known::EveryPixel(1.0)),
    ("camera_inside_light.toml", Known::ImageMean(0.875)),
    ("glossiness_extremes.toml", Known::Nothing),
    ("bright_light.toml", Known::Nothing),
];

#[test]
fn every_preset_is_stable_on_every_extreme_scene() {
    let checks = SCENES.len() * Preset::ALL.len();
    let mean_threshold = z_threshold(ALPHA, checks);
    let mut failures = Vec::new();
    for (file, known) in &SCENES {
        let scene = extreme(file);
        for preset in Preset::ALL {
            let film = render(&scene, preset.method(), 64, 21);
            let label = format!("{file} {}", preset.name());
            if !film.is_finite() {
                failures.push(format!("{label}: NaN or inf"));
                continue;
            }
            if film.mean.iter().flatten().any(|&c| c < 0.0) {
                failures.push(format!("{label}: negative radiance"));
            }
            match known {
                Known::EveryPixel(v) => {
                    let z = z_test(&constant_film(film.width, film.height, *v), &film, ALPHA / checks as f64);
                    if z.pass_fraction < 0.9975 {
                        failures.push(format!("{label}: {:.4} of pixels match {v} (max |z| {:.1})", z.pass_fraction, z.max_abs_z));
                    }
                }
                Known::ImageMean(m) => {
                    let (mean, err) = image_mean_and_error(&film, 0);
                    if (mean - m).abs() > mean_threshold * err {
                        failures.push(format!("{label}: image mean {mean:.5} vs {m} (z {:.1})", (mean - m) / err));
                    }
                }
                Known::Nothing => {}
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Sample indices just below 2^32 for every sampler: still finite, still converging to 1 on
/// the huge-sphere furnace.
#[test]
fn sample_indices_near_two_to_the_32() {
    let scene = extreme("huge_sphere_wall.toml");
    for sampler in Sampler::ALL {
        let method = Method { sampler, ..Preset::Mis.method() };
        let mut r = Renderer::new(gpu(), pipelines(), &scene, method, 3).unwrap();
        r.start_at_sample((1u64 << 32) - 64).unwrap();
        r.render(Budget::Samples(64), &AtomicBool::new(false), |_| {}).unwrap();
        let film = r.film().unwrap();
        assert!(film.is_finite(), "{sampler:?}");
        let z = z_test(&constant_film(film.width, film.height, 1.0), &film, ALPHA);
        assert!(z.pass_fraction >= 0.9975, "{sampler:?}: {:.4} pass near 2^32", z.pass_fraction);
        // One more sample would pass 2^32: refused, not wrapped around.
        assert!(r.render(Budget::Samples(1), &AtomicBool::new(false), |_| {}).is_err());
    }
}
