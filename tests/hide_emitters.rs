//! Mitsuba's `hide_emitters` (`RenderSettings::hide_emitters`, `HIDE_EMITTERS` in
//! shaders/integrator.wgsl): camera rays pass through every area emitter they meet and see no
//! environment, while light reaches the scene as before. tests/fixtures/hide_emitters/
//! hide_emitters.xml (a sphere light in front of a red sphere, a rectangle light in front of a
//! cube, a constant sky) rendered by `mis` and `mis+env` is z-tested against Mitsuba 3.9.1
//! rendering the same file (48x48, 65536 spp in 64 passes with the per-pixel variance of its
//! mean; scripts/xml_fixture_reference.sh tests/fixtures/hide_emitters/hide_emitters.xml), on 2x2 blocks as tests/cornell_box.rs does (at
//! least 99.75% of channels passing, Šidák-corrected: fails falsely with probability below
//! 0.01; `mis` scaled by 1.05 is rejected). The same file without `hide_emitters` must be
//! rejected: the lights and the sky in view change the image.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::Scene;

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hide_emitters/hide_emitters.xml")
}

#[test]
fn hidden_emitters_agree_with_mitsuba_and_shown_ones_do_not() {
    let reference = mitsuba_fixture("hide_emitters");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.render.hide_emitters);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "mis+env"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 2100, Preset::Mis.method());

    // The same scene with its emitters shown: rejected on its blocks.
    let shown = Scene { render: pathlab::scene::RenderSettings { hide_emitters: false, ..scene.render.clone() }, ..scene.clone() };
    assert_ne!(shown.content_hash(), scene.content_hash(), "hide_emitters is part of the scene's content");
    // 64 spp: the shown lights and sky differ from the reference by far more than its noise.
    let film = render(&shown, Preset::Mis.method(), 64, 2200);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    println!("emitters shown (64 spp, 2x2 blocks): {:.4} of channels pass", z.pass_fraction);
    assert!(z.pass_fraction < 0.9975, "the emitters shown pass as hidden: {:.4} of channels pass", z.pass_fraction);
}

/// With media (the volumetric path tracer, Mitsuba's volpath): tests/fixtures/
/// hide_emitters_media/hide_emitters_media.xml (the media fixture with hide_emitters, a
/// constant sky, a rectangle light in view directly and through a thin-dielectric sphere, and a
/// rectangle light inside the `null` sphere's medium) against Mitsuba 3.9.1 on the same file (64x48,
/// 65536 spp in 64 passes; WIDTH=64 HEIGHT=48 scripts/xml_fixture_reference.sh
/// tests/fixtures/hide_emitters_media/hide_emitters_media.xml), on 4x4 blocks as above; shown,
/// the emitters are rejected.
#[test]
fn hidden_emitters_in_a_scene_with_media_agree_with_mitsuba() {
    let reference = mitsuba_fixture("hide_emitters_media");
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hide_emitters_media/hide_emitters_media.xml");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(file, &defines).unwrap();
    assert!(scene.render.hide_emitters && !scene.media.is_empty());
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // `nee+all`, not `nee`: NEE alone from points in the medium near the light inside it has
    // infinite variance (area sampling's second moment grows as 1 / h^2 at height h above the
    // light, and free flights reach every h: README, "Participating media"), and power
    // selection picks that small light one time in 60, which leaves 4x4 blocks of the fog
    // 13-25% dark at 2048 spp, different blocks for each seed, never a bright one; every light
    // sampled at every vertex keeps the tail rare enough to z-test.
    let methods: Vec<Method> = ["mis", "nee+all"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 4), 5200, Preset::Mis.method());
    let shown = Scene { render: pathlab::scene::RenderSettings { hide_emitters: false, ..scene.render.clone() }, ..scene.clone() };
    let film = render(&shown, Preset::Mis.method(), 64, 5210);
    let z = pathlab::stats::z_test(&reference.downsample(4), &film.downsample(4), 0.01);
    println!("emitters shown (64 spp, 4x4 blocks): {:.4} of channels pass", z.pass_fraction);
    assert!(z.pass_fraction < 0.9975, "the emitters shown pass as hidden: {:.4} of channels pass", z.pass_fraction);
}

#[test]
fn with_one_segment_a_scene_of_hidden_emitters_is_black() {
    // Mitsuba's own test (test_integrators.py, test02_path_directly_visible): at max_depth 1 a
    // path is its camera segment alone, and with the emitters hidden it finds nothing.
    let mut scene = Scene::load(fixture()).unwrap();
    scene.render.max_depth = 1;
    for method in ["mis", "mis+env", "plain"] {
        let film = render(&scene, Method::from_name(method).unwrap(), 4, 7);
        assert!(film.mean.iter().flatten().all(|&v| v == 0.0), "{method}: some pixel is not black");
    }
    // Shown, the lights and the sky are there.
    scene.render.hide_emitters = false;
    let film = render(&scene, Preset::Mis.method(), 4, 7);
    assert!(film.mean.iter().flatten().any(|&v| v > 1.0), "the lights are not seen");
}

#[test]
fn hide_emitters_is_read_from_xml_and_toml_and_written_by_convert() {
    let scene = Scene::load(fixture()).unwrap();
    assert!(scene.render.hide_emitters);
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert!(toml.contains("hide_emitters = true"), "{toml}");
    // A false value is Mitsuba's default: no line, the same hash as without it.
    let text = std::fs::read_to_string(fixture()).unwrap();
    let write = |t: &str| {
        let p = dir.path().join("s.xml");
        std::fs::write(&p, t).unwrap();
        Scene::load(&p).unwrap()
    };
    let off = write(&text.replace("value=\"true\"/>\n    </integrator>", "value=\"false\"/>\n    </integrator>"));
    let none = write(&text.replace("<boolean name=\"hide_emitters\" value=\"true\"/>", ""));
    assert!(!off.render.hide_emitters);
    assert_eq!(off.content_hash(), none.content_hash());
}
