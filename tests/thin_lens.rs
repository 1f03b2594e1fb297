//! The thin-lens camera (Mitsuba's `thinlens`): depth of field, against Mitsuba 3.9.1 rendering
//! the same XML file (per-pixel z-tests, `scripts/thinlens_reference.sh`) with the independent,
//! Halton and Sobol' samplers (the lens takes dimensions 2 and 3); a zero aperture is the
//! pinhole bit for bit; bad lenses are refused.

use crate::common;

use std::path::{Path, PathBuf};

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Scene, SceneError};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/thinlens").join(name)
}

/// Mitsuba's image of the fixture (64 passes of 1024 spp) against pathlab's at 2048 spp, z-tests
/// on 2x2 blocks Šidák-corrected over the methods and the power check (false-failure
/// probability 0.01); a 5% bias must be caught.
#[test]
fn depth_of_field_agrees_with_mitsuba_for_every_sampler() {
    let reference = mitsuba_fixture("thinlens");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture("thinlens.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!((scene.camera.aperture_radius, scene.camera.focus_distance), (0.15, 5.0));
    let methods: Vec<Method> = ["mis", "nee", "halton/phong/mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 3100, Preset::Mis.method());
}

#[test]
fn a_zero_aperture_is_the_pinhole_and_bad_lenses_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    let scene = |camera_extra: &str| {
        format!(
            "[camera]\nposition = [0, 1, 4]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n{camera_extra}\n\
             [render]\nwidth = 16\nheight = 12\nmax_depth = 3\n\
             [materials.lamp]\nemission = 4\n[materials.grey]\ndiffuse = 0.5\n\
             [[spheres]]\ncenter = [0, 2, 0]\nradius = 0.5\nmaterial = \"lamp\"\n\
             [[spheres]]\ncenter = [0, 0, 0]\nradius = 0.7\nmaterial = \"grey\"\n\
             [[planes]]\npoint = [0, -0.7, 0]\nnormal = [0, 1, 0]\nmaterial = \"grey\"\n"
        )
    };
    let load = |camera_extra: &str| {
        std::fs::write(&path, scene(camera_extra)).unwrap();
        Scene::load(&path)
    };
    let pinhole = load("").unwrap();
    let zero = load("aperture_radius = 0").unwrap();
    assert_eq!(zero.content_hash(), pinhole.content_hash());
    for method in [Preset::Mis.method(), Method::from_name("sobol/phong/mis").unwrap()] {
        assert!(bits(&render(&zero, method, 4, 7)) == bits(&render(&pinhole, method, 4, 7)), "a zero aperture renders as the pinhole");
    }
    let lens = load("aperture_radius = 0.1\nfocus_distance = 4").unwrap();
    assert_ne!(lens.content_hash(), pinhole.content_hash(), "the lens is part of the scene");
    assert!(bits(&render(&lens, Preset::Mis.method(), 4, 7)) != bits(&render(&pinhole, Preset::Mis.method(), 4, 7)));
    // The focus distance defaults to the distance to look_at.
    let default_focus = load("aperture_radius = 0.1").unwrap();
    assert!((default_focus.camera.focus_distance - 17f64.sqrt()).abs() < 1e-12);
    // A focus distance without an aperture is said, not ignored.
    let warned = load("focus_distance = 3").unwrap();
    assert!(warned.warnings.iter().any(|w| w.field == "camera.focus_distance" && w.message.contains("no effect")), "{:?}", warned.warnings);
    for (extra, field, message) in [
        ("aperture_radius = -0.1", "camera.aperture_radius", "must be >= 0"),
        ("aperture_radius = 0.1\nfocus_distance = 0", "camera.focus_distance", "must be > 0"),
    ] {
        match load(extra) {
            Err(SceneError::Invalid(d)) => assert!(d.iter().any(|d| d.field == field && d.message.contains(message) && d.line >= 1), "{extra}: {d:?}"),
            other => panic!("{extra}: accepted ({:?})", other.map(|s| s.camera.aperture_radius)),
        }
    }
    // From XML: Mitsuba requires the aperture radius, and its focus distance defaults to the far
    // clip distance (1e4, or the one given).
    let xml_path = dir.path().join("s.xml");
    let xml = |sensor: &str| {
        std::fs::write(
            &xml_path,
            format!(
                "<scene version=\"3.0.0\"><sensor type=\"thinlens\"><float name=\"fov\" value=\"45\"/>{sensor}\
                 <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/></film></sensor>\
                 <shape type=\"cube\"/></scene>"
            ),
        )
        .unwrap();
        Scene::load(&xml_path)
    };
    assert_eq!(xml("<float name=\"aperture_radius\" value=\"0.2\"/>").unwrap().camera.focus_distance, 1e4);
    assert_eq!(xml("<float name=\"aperture_radius\" value=\"0.2\"/><float name=\"far_clip\" value=\"30\"/>").unwrap().camera.focus_distance, 30.0);
    match xml("") {
        Err(SceneError::Invalid(d)) => assert!(d.iter().any(|d| d.message.contains("needs <float name=\"aperture_radius\">")), "{d:?}"),
        other => panic!("accepted: {:?}", other.map(|s| s.camera.aperture_radius)),
    }
    // `pathlab convert` keeps the lens: the same scene.
    let out = dir.path().join("converted.toml");
    let r = std::process::Command::new(env!("CARGO_BIN_EXE_pathlab")).arg("convert").arg(fixture("thinlens.xml")).arg("-o").arg(&out).output().unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(Scene::load(&out).unwrap().content_hash(), Scene::load(fixture("thinlens.xml")).unwrap().content_hash());
}
