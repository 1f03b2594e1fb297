//! Veach's multiple-importance-sampling scene (Bitterli's "Veach, MIS", assets/scenes/veach_mis.xml:
//! four copper plates of Beckmann alpha 0.01 to 0.25 under three spherical lights), rendered
//! by pathlab with the methods that combine BSDF and light sampling (`mis`, `best`,
//! `mis-balance`), each with both microfacet strategies (`vndf`, `ndf`), against Mitsuba 3.9.1 loading the
//! same file (tests/fixtures/veach_mis/: 128x72, max_depth 2 through Mitsuba's -D, box filter,
//! independent sampler, 65536 spp in 64 passes with the per-pixel variance of its mean; made by
//! scripts/veach_reference.sh). Depth 2 is direct lighting, Veach's figure: the file's own depth
//! 3 adds glossy caustics (camera, wall, plate, light), found by BSDF sampling at the wall by
//! chance, whose heavy tails make sample means fall short at any sample count CI affords
//! (`mis` on 4x4 blocks of 256 spp: mean z -0.24, 1.2% of channels past the threshold; at 4096
//! spp it agrees with Mitsuba there to 0.02%).
//!
//! Each render is z-tested channel by channel against the reference as in tests/cornell_box.rs:
//! Šidák-corrected over channels and renders at alpha = 0.01, at least 99.75% of channels
//! passing, so the file fails falsely with probability below 0.01. Power: the `mis` render
//! scaled by 1.05 is rejected.

use crate::common;

use common::*;
use pathlab::method::{LightSampling, Method, MicrofacetSampling, Preset};
use pathlab::scene::Scene;

/// Samples per pixel and block size: 4x4 blocks of 256 spp (4096 samples a cell). Not more: on
/// the back wall, where the middle light hides part of the large one, Mitsuba's reference is
/// 0.12% brighter than the analytic irradiance with that occlusion (+2.9 of its own standard
/// errors over the top-left 8x32 pixels), while pathlab's 4096-spp image is within 2e-5 of it
/// (see the issue-19 note); at 8x8 blocks of 1024 spp pathlab's noise is small enough for that
/// to fail 3 of 432 channels.
fn plan(_method: &Method) -> (u64, u32) {
    (256, 4)
}

/// The methods that combine both strategies, with both microfacet strategies: `mis`, `best`
/// and `mis-balance`. The presets that sample only the BSDF or only the lights are the
/// figure's point: on the plates' highlights of the small light (radius 0.05, radiance 3040)
/// their variance is too large for a z-test in CI's time (`plain`: 70% of channels pass at 8x8
/// blocks of 1024 spp, mean z -9.4); they are held to Mitsuba on tests/cornell_conductors.rs.
fn methods() -> Vec<Method> {
    let mut methods = Vec::new();
    for m in [Preset::Mis.method(), Preset::Best.method(), Method { lights: LightSampling::MisBalance, ..Preset::Mis.method() }] {
        methods.push(m);
        methods.push(Method { microfacet: MicrofacetSampling::Ndf, ..m });
    }
    methods
}

#[test]
fn every_method_and_microfacet_strategy_agrees_with_mitsuba_on_the_veach_scene() {
    let reference = mitsuba_fixture("veach_mis");
    let defines = [
        ("resx".to_string(), reference.width.to_string()),
        ("resy".to_string(), reference.height.to_string()),
        ("max_depth".to_string(), "2".to_string()),
    ];
    let scene = Scene::load_with(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/veach_mis.xml"), &defines).unwrap();
    agrees_with_reference(&reference, &scene, &methods(), plan, 900, Preset::Mis.method());
}
