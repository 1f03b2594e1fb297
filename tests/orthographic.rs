//! The orthographic camera (Mitsuba's `orthographic`: parallel rays from a rectangle
//! `to_world`'s x scale times 2 across, starting `near_clip` along the view), against Mitsuba
//! 3.9.1 rendering the same XML file (per-pixel z-tests; WIDTH=64 HEIGHT=48
//! scripts/xml_fixture_reference.sh tests/fixtures/orthographic/orthographic.xml); a near clip
//! left out and a wider view are rejected; bad sensors and cameras are refused.

use crate::common;

use std::path::{Path, PathBuf};

use common::*;
use glam::DVec3;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Projection, Scene};

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/orthographic/orthographic.xml")
}

fn load_fixture(width: u32, height: u32) -> Scene {
    let defines = [("resx".to_string(), width.to_string()), ("resy".to_string(), height.to_string())];
    Scene::load_with(fixture(), &defines).unwrap()
}

/// Mitsuba's image of the fixture (64 passes of 1024 spp) against pathlab's `mis` and `best` at
/// 2048 spp: z-tests on 2x2 blocks, at least 99.75% of channels passing, Šidák-corrected over
/// the methods and the power check (false-failure probability 0.01); `mis` x1.05 is rejected.
/// Then two wrong cameras at the same sample count, each rejected: rays from the sensor's
/// origin (near_clip left out: the dark sphere in front of the near plane is then seen) and a
/// view 10% wider.
#[test]
fn the_orthographic_camera_agrees_with_mitsubas() {
    let reference = mitsuba_fixture("orthographic");
    let scene = load_fixture(reference.width, reference.height);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // The view: 2 x 1.4 across; its rectangle's centre 1.5 along the view from the origin.
    let origin = DVec3::new(1.0, 1.6, 5.0);
    let forward = (DVec3::new(0.0, 0.6, 0.0) - origin).normalize();
    let Projection::Orthographic { width } = scene.camera.projection else { panic!("{:?}", scene.camera.projection) };
    assert!((width - 2.8).abs() < 1e-12, "{width}");
    assert!(scene.camera.position.distance(origin + 1.5 * forward) < 1e-12, "{:?}", scene.camera.position);
    assert!(pathlab::gpu::SceneFeatures::of(&scene).orthographic);
    let methods: Vec<Method> = ["mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 4200, Preset::Mis.method());

    let rejected = |wrong: &Scene, what: &str, seed: u32| {
        let film = render(wrong, Preset::Mis.method(), 2048, seed);
        let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
        println!("{what} (2048 spp, 2x2 blocks): {:.4} of channels pass, max |z| {:.1}", z.pass_fraction, z.max_abs_z);
        assert!(z.pass_fraction < 0.9975, "{what} passes: {:.4} of channels", z.pass_fraction);
    };
    let mut no_near_clip = scene.clone();
    no_near_clip.camera.position = origin;
    no_near_clip.camera.look_at = origin + forward;
    rejected(&no_near_clip, "rays from the sensor's origin (near_clip left out)", 4202);
    let mut wider = scene.clone();
    wider.camera.projection = Projection::Orthographic { width: 2.8 * 1.1 };
    rejected(&wider, "a view 10% wider", 4203);
}

#[test]
fn orthographic_sensors_and_cameras_are_read_or_refused() {
    let text = std::fs::read_to_string(fixture()).unwrap();
    let sensor = |transform: &str, extra: &str| {
        let start = text.find("<sensor").unwrap();
        let end = text.find("</sensor>").unwrap();
        let new = format!(
            "<sensor type=\"orthographic\">{extra}<transform name=\"to_world\">{transform}</transform>\
             <film type=\"hdrfilm\"><integer name=\"width\" value=\"32\"/><integer name=\"height\" value=\"16\"/></film>"
        );
        format!("{}{}{}", &text[..start], new, &text[end..])
    };
    // No near_clip: Mitsuba's 0.01; no scale: 2 across.
    let s = load_xml(&sensor("<lookat origin=\"0, 1, 5\" target=\"0, 1, 0\" up=\"0, 1, 0\"/>", ""), "o.xml").unwrap();
    assert_eq!(s.camera.projection, Projection::Orthographic { width: 2.0 });
    assert!(s.camera.position.distance(DVec3::new(0.0, 1.0, 4.99)) < 1e-12, "{:?}", s.camera.position);
    assert_eq!((s.render.width, s.render.height), (32, 16));
    // far_clip: warned, as for the perspective camera.
    let s = load_xml(&sensor("<lookat origin=\"0, 1, 5\" target=\"0, 1, 0\" up=\"0, 1, 0\"/>", "<float name=\"far_clip\" value=\"100\"/>"), "o.xml").unwrap();
    assert!(s.warnings.iter().any(|w| w.field == "far_clip" && w.message.contains("ignored")), "{:?}", s.warnings);
    let refused = |t: String, wants: &[&str]| {
        let e = load_xml(&t, "o.xml").unwrap_err().to_string();
        assert!(e.contains("o.xml:") && wants.iter().all(|w| e.contains(w)), "{e}");
    };
    refused(sensor("<scale x=\"2\" y=\"1\"/><lookat origin=\"0, 1, 5\" target=\"0, 1, 0\" up=\"0, 1, 0\"/>", ""), &["to_world", "x and y unequally"]);
    refused(sensor("<scale x=\"-1\"/><lookat origin=\"0, 1, 5\" target=\"0, 1, 0\" up=\"0, 1, 0\"/>", ""), &["mirrors"]);
    refused(sensor("<lookat origin=\"0, 1, 5\" target=\"0, 1, 0\" up=\"0, 1, 0\"/>", "<float name=\"near_clip\" value=\"-1\"/>"), &["near_clip", ">= 0"]);
    refused(sensor("<lookat origin=\"0, 1, 5\" target=\"0, 1, 0\" up=\"0, 1, 0\"/>", "<float name=\"fov\" value=\"30\"/>"), &["fov"]);
    // A perspective camera whose to_world scales its axes unequally: its field of view would
    // change, so it is refused rather than read without the scale.
    let perspective = text.replace("type=\"orthographic\"", "type=\"perspective\"").replace("<float name=\"near_clip\" value=\"1.5\"/>", "");
    let e = load_xml(&perspective, "p.xml").unwrap_err().to_string();
    assert!(e.contains("p.xml:") && e.contains("scales its axes unequally"), "{e}");

    // `convert` writes orthographic_width, and the TOML loads as the same scene.
    let scene = load_fixture(64, 48);
    let dir = tempfile::tempdir().unwrap();
    let defines = [("resx".to_string(), "64".to_string()), ("resy".to_string(), "48".to_string())];
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &defines, dir.path()).unwrap();
    assert!(toml.contains("orthographic_width = 2.7999"), "{toml}");
    let path = dir.path().join("o.toml");
    std::fs::write(&path, &toml).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), scene.content_hash());
    // The camera's projection is part of the scene's identity.
    let mut wider = scene.clone();
    wider.camera.projection = Projection::Orthographic { width: 3.0 };
    assert_ne!(wider.content_hash(), scene.content_hash());

    // TOML: a width instead of a field of view, > 0, without a lens.
    let toml = |camera: &str| {
        format!(
            "[camera]\nposition = [0, 1, 4]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\n{camera}\n\
             [render]\nwidth = 16\nheight = 8\nmax_depth = 3\n\
             [materials.lamp]\nemission = 4\n[materials.grey]\ndiffuse = 0.5\n\
             [[spheres]]\ncenter = [0, 3, 0]\nradius = 0.5\nmaterial = \"lamp\"\n\
             [[planes]]\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"grey\"\n"
        )
    };
    let s = Scene::parse(&toml("orthographic_width = 3"), "c.toml").unwrap();
    assert_eq!(s.camera.projection.half_extents(16, 8), (1.5, 0.75));
    let toml_refused = |camera: &str, wants: &[&str]| {
        let e = Scene::parse(&toml(camera), "c.toml").unwrap_err().to_string();
        assert!(e.contains("c.toml:") && wants.iter().all(|w| e.contains(w)), "{e}");
    };
    toml_refused("orthographic_width = 0", &["camera.orthographic_width", "> 0"]);
    toml_refused("orthographic_width = 2\nfov_x = 40", &["not both"]);
    toml_refused("orthographic_width = 2\naperture_radius = 0.1", &["camera.aperture_radius", "no lens"]);

    // Another aspect ratio keeps the width and says so.
    let mut resized = s.clone();
    let overrides = pathlab::scene::Overrides { width: Some(16), height: Some(16), ..Default::default() };
    let reframing = overrides.apply(&mut resized).unwrap().expect("a new aspect ratio");
    let said = reframing.to_string();
    assert!(said.contains("orthographic view's width") && said.contains("3.000 scene units x 3.000 scene units instead of 3.000 scene units x 1.500"), "{said}");
}
