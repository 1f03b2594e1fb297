//! Every preset renders the study scene sanely, and rendering is deterministic.

use crate::common;

use common::*;
use pathlab::method::Preset;

/// Every preset at 64x32, 16 spp: finite everywhere, not black, and the image mean within a
/// broad physical range (the converged mean of this scene at max_depth 2 is about 0.9).
#[test]
fn every_preset_renders_the_study_scene() {
    let mut scene = study_scene();
    scene.render.width = 64;
    scene.render.height = 32;
    for preset in Preset::ALL {
        let film = render(&scene, preset.method(), 16, 1);
        assert!(film.is_finite(), "{preset:?}: non-finite pixel");
        let mean = film.average();
        assert!(mean > 0.2 && mean < 5.0, "{preset:?}: image mean {mean} outside the physical range");
        // Not black: at 16 spp even `plain` (lights found only by uniform directions) lights
        // a good share of the pixels.
        let lit = film.mean.iter().filter(|p| p.iter().any(|&c| c > 0.0)).count();
        assert!(lit > film.mean.len() / 5, "{preset:?}: only {lit} of {} pixels lit", film.mean.len());
        assert!(film.mean.iter().flatten().all(|&c| c >= 0.0), "{preset:?}: negative radiance");
    }
}

#[test]
fn same_seed_is_bit_identical_and_different_seeds_differ() {
    let mut scene = study_scene();
    scene.render.width = 48;
    scene.render.height = 24;
    for preset in [Preset::Plain, Preset::Halton, Preset::Best] {
        let a = render(&scene, preset.method(), 8, 7);
        let b = render(&scene, preset.method(), 8, 7);
        let c = render(&scene, preset.method(), 8, 8);
        assert_eq!(bits(&a), bits(&b), "{preset:?}: same seed, different image");
        assert_ne!(bits(&a), bits(&c), "{preset:?}: different seeds, same image");
    }
}

/// Samples are addressed by (pixel, index, dimension) and the accumulator state carries over
/// exactly, so a render split into pieces equals the render done at once, bit for bit.
#[test]
fn split_render_equals_single_render() {
    use pathlab::render::{Budget, Renderer};
    use std::sync::atomic::AtomicBool;
    let mut scene = study_scene();
    scene.render.width = 40;
    scene.render.height = 20;
    let method = Preset::Best.method();
    let whole = render(&scene, method, 12, 3);
    let mut r = Renderer::new(gpu(), pipelines(), &scene, method, 3).unwrap();
    for n in [1, 2, 4, 5] {
        r.render(Budget::Samples(n), &AtomicBool::new(false), |_| {}).unwrap();
    }
    let pieces = r.film().unwrap();
    assert_eq!(pieces.spp, 12);
    assert_eq!(bits(&whole), bits(&pieces));
}

/// An image split into accumulator bands (forced here to 3 rows each; by default bands are as
/// large as the adapter's storage binding allows) equals the single-band render bit for bit.
#[test]
fn banded_accumulator_equals_single_band() {
    use pathlab::render::{Budget, Renderer};
    use std::sync::atomic::AtomicBool;
    let mut scene = study_scene();
    scene.render.width = 40;
    scene.render.height = 20;
    let method = Preset::Best.method();
    let whole = render(&scene, method, 6, 9);
    let row_bytes = 40 * std::mem::size_of::<pathlab::film::AccumPixel>() as u64;
    let mut r = Renderer::with_band_bytes(gpu(), pipelines(), &scene, method, 9, 3 * row_bytes).unwrap();
    assert_eq!(r.bands(), 7);
    r.render(Budget::Samples(6), &AtomicBool::new(false), |_| {}).unwrap();
    assert_eq!(bits(&whole), bits(&r.film().unwrap()));
}

/// Specialisation to the scene's features removes code, never changes the estimator: the
/// pipeline with every optional feature on (environment lookups, shadow tests of every plane,
/// light sampling from inside, specular lobe) renders the study scene to the same image, and
/// traces the same rays. Deterministic: no false failures.
#[test]
fn unspecialised_pipeline_renders_the_same_image() {
    use pathlab::render::Renderer;
    let mut scene = study_scene();
    scene.render.width = 48;
    scene.render.height = 24;
    scene.render.max_depth = 3;
    let f = pathlab::gpu::SceneFeatures::of(&scene);
    assert_ne!(f, f.all_on(), "the study scene should be specialised");
    for preset in [Preset::Plain, Preset::Nee, Preset::Mis, Preset::Best] {
        let a = finish(Renderer::unspecialised(gpu(), pipelines(), &scene, preset.method(), 5).expect("renderer"), 16);
        let b = finish(Renderer::new(gpu(), pipelines(), &scene, preset.method(), 5).expect("renderer"), 16);
        if gpu().info.device_type == wgpu::DeviceType::Cpu {
            assert_eq!(a.rays, b.rays, "{preset:?}: different ray counts");
            assert_eq!(bits(&a.film), bits(&b.film), "{preset:?}: specialisation changed the image");
        } else {
            // A GPU's compiler fuses multiply-adds differently in the two kernels (WGSL allows
            // it; an NVIDIA H200 does), so only the rounding may differ: the image means agree
            // to 1e-4 relative, per channel.
            for c in 0..3 {
                let mean = |f: &pathlab::film::Film| f.mean.iter().map(|p| p[c] as f64).sum::<f64>() / f.mean.len() as f64;
                let (ma, mb) = (mean(&a.film), mean(&b.film));
                assert!((ma - mb).abs() <= 1e-4 * ma.abs().max(mb.abs()), "{preset:?}: specialisation changed channel {c}'s mean: {ma} against {mb}");
            }
        }
    }
}
