//! Mitsuba 3's Cornell box (`mi.cornell_box()`, rebuilt as assets/scenes/cornell_box.toml)
//! rendered by pathlab with every unbiased preset, and each light-sampling preset with every
//! `--light-select` and `--triangle-sampling` choice, against Mitsuba 3.9.1 rendering the same
//! scene (tests/fixtures/cornell/: 64x64, 65536 spp in 64 passes, box filter, independent
//! sampler, with the per-pixel variance of its mean; made by scripts/cornell_reference.sh).
//!
//! Each render is z-tested channel by channel against the reference, as the correctness suite
//! does for the study scene: z = (mean - ref) / sqrt(var_ref + var), Šidák-corrected over the
//! channels of a comparison and over the comparisons (alpha = 0.01 in all), passing when at
//! least 99.75% of channels pass, so the file fails falsely with probability below 0.01. The
//! block sizes and sample counts per method are in `plan`. Power: the `mis` render with its
//! image scaled by 1.05 is rejected.

mod common;

use std::path::Path;

use common::*;
use pathlab::film::Film;
use pathlab::method::{LightSampling, Preset};
use pathlab::output::read_exr_image;
use pathlab::scene::Scene;
use pathlab::stats::{sidak, z_test};

const MIN_PASS: f64 = 0.9975;

/// Samples per pixel and block size of a method. Light sampling with BSDF sampling keeps the
/// estimator light-tailed: 2x2 blocks of 256 spp (a 32x32 image at 1024 spp). Uniform-sphere
/// sampling finds light only by chance after its first bounce (nee: in the indirect part;
/// plain and halton: all of it), and a few rare paths carry most of a pixel's value, where a
/// z-test's normal approximation fails (its sample variance is mostly too small): larger
/// blocks and more samples, as the correctness suite does for the study scene.
fn plan(method: &pathlab::method::Method) -> (u64, u32) {
    use pathlab::method::BsdfSampling;
    match (method.lights, method.bsdf) {
        (LightSampling::None, BsdfSampling::UniformSphere) => (1024, 8),
        (LightSampling::None, _) => (1024, 4),
        (_, BsdfSampling::UniformSphere) => (1024, 8),
        _ => (256, 2),
    }
}

fn fixture(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/cornell").join(name)
}

/// Mitsuba's mean and the variance of that mean, as one film.
fn reference() -> Film {
    let mean = read_exr_image(&fixture("reference.exr")).expect("tests/fixtures/cornell/reference.exr").film;
    let var = read_exr_image(&fixture("reference_var.exr")).expect("tests/fixtures/cornell/reference_var.exr").film;
    let record: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(fixture("reference.json")).unwrap()).unwrap();
    assert_eq!(record["mitsuba_version"], "3.9.1");
    Film { spp: record["spp"].as_u64().unwrap(), variance: var.mean, ..mean }
}

#[test]
fn every_method_and_light_option_agrees_with_mitsuba_on_its_cornell_box() {
    let reference = reference();
    let mut scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml")).unwrap();
    (scene.render.width, scene.render.height) = (reference.width, reference.height);
    let methods = triangle_light_methods();
    let alpha = sidak(0.01, methods.len() + 1);
    let mut report = Vec::new();
    let mut failed = Vec::new();
    let mut mis_film = None;
    for (k, method) in methods.iter().enumerate() {
        let (spp, block) = plan(method);
        let film = render(&scene, *method, spp, 500 + k as u32);
        let z = z_test(&reference.downsample(block), &film.downsample(block), alpha);
        report.push(format!(
            "{} ({spp} spp, {block}x{block} blocks): {:.4} of {} channels pass |z| <= {:.2}; max |z| {:.2}, mean z {:+.3}",
            method.name(),
            z.pass_fraction,
            z.channels,
            z.threshold,
            z.max_abs_z,
            z.mean_z
        ));
        if z.pass_fraction < MIN_PASS {
            failed.push(method.name());
        }
        if *method == (pathlab::method::Method { select: method.select, ..Preset::Mis.method() }) && mis_film.is_none() {
            mis_film = Some(film);
        }
    }
    println!("{}", report.join("\n"));
    assert!(failed.is_empty(), "disagree with Mitsuba: {failed:?}\n{}", report.join("\n"));
    // The test can see a 5% error (per 2x2 block at 256 spp, the noise of mis is ~1-2%).
    let mut biased = mis_film.unwrap();
    biased.mean.iter_mut().flatten().for_each(|c| *c *= 1.05);
    let z = z_test(&reference.downsample(2), &biased.downsample(2), alpha);
    assert!(z.pass_fraction < MIN_PASS, "a 5% bias passes: {:.4}", z.pass_fraction);
}
