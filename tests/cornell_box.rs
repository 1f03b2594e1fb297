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

use crate::common;

use common::*;
use pathlab::method::{LightSampling, Preset};
use pathlab::scene::Scene;

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

#[test]
fn every_method_and_light_option_agrees_with_mitsuba_on_its_cornell_box() {
    let reference = mitsuba_fixture("cornell");
    let mut scene = Scene::load(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/cornell_box.toml")).unwrap();
    (scene.render.width, scene.render.height) = (reference.width, reference.height);
    let methods = triangle_light_methods();
    // The power check scales the first `mis` render (2x2 blocks of 256 spp, its noise ~1-2%).
    let mis = *methods.iter().find(|m| pathlab::method::Method { select: m.select, ..Preset::Mis.method() } == **m).unwrap();
    agrees_with_reference(&reference, &scene, &methods, plan, 500, mis);
}
