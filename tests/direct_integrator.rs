//! Mitsuba's `direct` integrator, read as `path` with max_depth 2 (`Translator::integrator`,
//! src/scene/mitsuba/mod.rs): emitted light and one bounce of direct light, the same expected
//! image. tests/fixtures/direct/direct.xml (the textured-anisotropy fixture's rough metals,
//! rough glass and principled sphere under a rectangle light, with `<integrator type="direct"/>`)
//! rendered by `mis` and `best` is z-tested against Mitsuba 3.9.1's `direct` rendering the same
//! file (64x48, 65536 spp in 64 passes with the per-pixel variance of its mean; WIDTH=64
//! scripts/xml_fixture_reference.sh tests/fixtures/direct/direct.xml), on 2x2 blocks as
//! tests/cornell_box.rs does (at least 99.75% of channels passing, Šidák-corrected: fails
//! falsely with probability below 0.01; `mis` scaled by 1.05 is rejected). The same scene at
//! max_depth 3 (one more bounce) is rejected. Its sample counts are read and left unused (they
//! change only the noise), `hide_emitters` is read as for `path`.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::Scene;

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/direct/direct.xml")
}

#[test]
fn the_direct_integrator_agrees_with_mitsubas() {
    let reference = mitsuba_fixture("direct");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert_eq!(scene.render.max_depth, 2);
    assert!(scene.warnings.iter().any(|w| w.field == "type" && w.message.contains("path with max_depth 2")), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 4010, Preset::Mis.method());

    // One bounce more: rejected.
    let mut deeper = scene.clone();
    deeper.render.max_depth = 3;
    let film = render(&deeper, Preset::Mis.method(), 2048, 4100);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    println!("max_depth 3 (2048 spp, 2x2 blocks): {:.4} of channels pass", z.pass_fraction);
    assert!(z.pass_fraction < 0.9975, "max_depth 3 passes: {:.4} of channels", z.pass_fraction);
}

#[test]
fn the_direct_integrators_settings_are_read_or_refused() {
    let scene = |integrator: &str| {
        let text = std::fs::read_to_string(fixture()).unwrap().replace("<integrator type=\"direct\"/>", integrator);
        load_xml(&text, "d.xml")
    };
    let s = scene("<integrator type=\"direct\"><integer name=\"emitter_samples\" value=\"4\"/><integer name=\"bsdf_samples\" value=\"0\"/></integrator>").unwrap();
    assert_eq!(s.render.max_depth, 2);
    // hide_emitters: camera rays pass through area lights, in Mitsuba's direct as in pathlab's
    // path (tests/hide_emitters.rs).
    let s = scene("<integrator type=\"direct\"><boolean name=\"hide_emitters\" value=\"true\"/></integrator>").unwrap();
    assert!(s.render.hide_emitters);
    let e = scene("<integrator type=\"direct\"><integer name=\"bsdf_samples\" value=\"-1\"/></integrator>").unwrap_err().to_string();
    assert!(e.contains("d.xml:") && e.contains("bsdf_samples must be at least 0"), "{e}");
    let e = scene("<integrator type=\"direct\"><integer name=\"max_depth\" value=\"4\"/></integrator>").unwrap_err().to_string();
    assert!(e.contains("`max_depth` of <integrator type=\"direct\"> is not supported"), "{e}");
    // Mitsuba's `moment` around it, as its test scenes write it.
    let s = scene("<integrator type=\"moment\"><integrator type=\"direct\"/></integrator>").unwrap();
    assert_eq!(s.render.max_depth, 2);

    // Mitsuba's `aov` renders its first nested integrator's image (its AOVs go to channels
    // pathlab does not write); `ptracer` has path's expectation at its depth.
    let s = scene("<integrator type=\"aov\"><string name=\"aovs\" value=\"dd.y:depth,nn:sh_normal\"/><integrator type=\"path\"><integer name=\"max_depth\" value=\"3\"/></integrator></integrator>").unwrap();
    assert_eq!(s.render.max_depth, 3);
    assert!(s.warnings.iter().any(|w| w.message.contains("read as its first nested integrator")), "{:?}", s.warnings);
    let e = scene("<integrator type=\"aov\"><string name=\"aovs\" value=\"dd.y:depth\"/></integrator>").unwrap_err().to_string();
    assert!(e.contains("without a nested integrator"), "{e}");
    let s = scene("<integrator type=\"ptracer\"><integer name=\"max_depth\" value=\"4\"/><integer name=\"samples_per_pass\" value=\"8\"/></integrator>").unwrap();
    assert_eq!((s.render.max_depth, s.render.rr_depth), (4, None));
    assert!(s.warnings.iter().any(|w| w.message.contains("ptracer") && w.message.contains("specular")), "{:?}", s.warnings);
    let e = scene("<integrator type=\"ptracer\"><integer name=\"max_depth\" value=\"0\"/></integrator>").unwrap_err().to_string();
    assert!(e.contains("max_depth must be -1"), "{e}");
}
