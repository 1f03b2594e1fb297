//! Lights that project images: Mitsuba's spot `texture` (`SpotTexture`) and `projector`
//! (`ProjectorLight`), against Mitsuba 3.9.1 rendering the same XML file (per-pixel z-tests;
//! WIDTH=64 HEIGHT=48 scripts/xml_fixture_reference.sh
//! tests/fixtures/projected_lights/projected_lights.xml); a texture turned over, a projector
//! scaled by its to_world's scale squared (not once, as Mitsuba) and one with its field of view
//! along x instead of y are rejected; the TOML form round-trips and bad lights are refused.

use crate::common;

use std::path::{Path, PathBuf};

use common::*;
use glam::DVec3;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Fov, Scene, Texture};

fn fixture() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/projected_lights/projected_lights.xml")
}

fn load_fixture(width: u32, height: u32) -> Scene {
    let defines = [("resx".to_string(), width.to_string()), ("resy".to_string(), height.to_string())];
    Scene::load_with(fixture(), &defines).unwrap()
}

/// Mitsuba's image of the fixture (64 passes of 1024 spp) against pathlab's `mis` and `best` at
/// 2048 spp: z-tests on 2x2 blocks, at least 99.75% of channels passing, Šidák-corrected over
/// the methods and the power check (false-failure probability 0.01); `mis` x1.05 is rejected.
/// Three wrong lights at the same sample count are each rejected.
#[test]
fn projected_lights_agree_with_mitsubas() {
    let reference = mitsuba_fixture("projected_lights");
    let scene = load_fixture(reference.width, reference.height);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    // What was read: the spot's texture and frame, the projectors' fields of view (the second
    // by Mitsuba's default focal length, 50mm: the diagonal angle 2 atan(43.27 / 100)) and
    // their scales (the first's 0.25 times its to_world's scale 2: Mitsuba's projector divides
    // by the local depth squared, (z / 2)^2, and by its unnormalised axis's 2 cos(theta)).
    let spot = &scene.spot_lights[0];
    let texture = spot.texture.as_ref().expect("the spot's texture");
    assert!(matches!(texture.texture, Texture::Bitmap(_)));
    assert!(texture.up.dot(spot.direction).abs() < 1e-12 && texture.up.y > 0.0, "{texture:?}");
    let [slide, plain] = &scene.projector_lights[..] else { panic!("{:?}", scene.projector_lights) };
    assert_eq!((slide.fov, slide.resolution()), (Fov::Y(22.0), (24, 16)));
    assert!((slide.scale - 0.5).abs() < 1e-12, "{}", slide.scale);
    let Fov::Diagonal(d) = plain.fov else { panic!("{:?}", plain.fov) };
    assert!((d - 2.0 * (36f64.hypot(24.0) / 100.0).atan().to_degrees()).abs() < 1e-12);
    assert_eq!(plain.irradiance, Texture::RawConstant { value: DVec3::new(0.5, 0.35, 0.25) });
    assert!(pathlab::gpu::SceneFeatures::of(&scene).has_light_textures);

    let methods: Vec<Method> = ["mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 4300, Preset::Mis.method());

    let rejected = |wrong: &Scene, what: &str, seed: u32| {
        let film = render(wrong, Preset::Mis.method(), 2048, seed);
        let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
        println!("{what} (2048 spp, 2x2 blocks): {:.4} of channels pass, max |z| {:.1}", z.pass_fraction, z.max_abs_z);
        assert!(z.pass_fraction < 0.9975, "{what} passes: {:.4} of channels", z.pass_fraction);
    };
    let mut turned = scene.clone();
    if let Some(t) = turned.spot_lights[0].texture.as_mut() {
        t.up = -t.up;
    }
    rejected(&turned, "the spot's texture turned over (up reversed)", 4302);
    let mut squared = scene.clone();
    squared.projector_lights[0].scale = 0.25 * 4.0;
    rejected(&squared, "the projector with its to_world's scale squared (the axis normalised)", 4303);
    let mut along_x = scene.clone();
    along_x.projector_lights[0].fov = Fov::X(22.0);
    rejected(&along_x, "the projector's field of view along x", 4304);
}

#[test]
fn projected_lights_round_trip_through_toml_and_bad_ones_are_refused() {
    // `convert` writes the spot's texture and up and the projectors, which load as the same
    // scene.
    let scene = load_fixture(64, 48);
    let dir = tempfile::tempdir().unwrap();
    let defines = [("resx".to_string(), "64".to_string()), ("resy".to_string(), "48".to_string())];
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &defines, dir.path()).unwrap();
    assert!(toml.contains("[[projector_lights]]") && toml.contains("fov_diagonal"), "{toml}");
    std::fs::copy(fixture().with_file_name("slide.png"), dir.path().join("slide.png")).unwrap();
    let path = dir.path().join("p.toml");
    std::fs::write(&path, &toml).unwrap();
    let back = Scene::load(&path).unwrap();
    assert_eq!(back.content_hash(), scene.content_hash());
    // The projectors are part of the scene's identity.
    let mut moved = scene.clone();
    moved.projector_lights[1].scale = 2.0;
    assert_ne!(moved.content_hash(), scene.content_hash());

    let base = "[camera]\nposition = [0, 1, 4]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfov_x = 40\n\
                [render]\nwidth = 16\nheight = 8\nmax_depth = 2\n\
                [materials.grey]\ndiffuse = 0.5\n\
                [[planes]]\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"grey\"\n";
    let parse = |extra: &str| Scene::parse(&format!("{base}{extra}"), dir.path().join("s.toml"));
    let s = parse("[[projector_lights]]\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nup = [0, 0, 1]\nfov_x = 30\nirradiance = [1, 2, 3]\n").unwrap();
    assert_eq!(s.projector_lights[0].irradiance, Texture::RawConstant { value: DVec3::new(1.0, 2.0, 3.0) });
    assert_eq!(s.projector_lights[0].scale, 1.0);
    let refused = |extra: &str, wants: &[&str]| {
        let e = parse(extra).unwrap_err().to_string();
        assert!(e.contains("s.toml:") && wants.iter().all(|w| e.contains(w)), "{e}");
    };
    refused("[[projector_lights]]\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nup = [0, 0, 1]\nirradiance = 1\n", &["projector_lights[0]", "missing field of view"]);
    refused("[[projector_lights]]\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nup = [0, 1, 0]\nfov_x = 30\nirradiance = 1\n", &["projector_lights[0].up", "parallel"]);
    refused("[[projector_lights]]\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nup = [0, 0, 1]\nfov_x = 180\nirradiance = 1\n", &["projector_lights[0].fov_x", "strictly between 0 and 180"]);
    refused("[[projector_lights]]\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nup = [0, 0, 1]\nfov_x = 30\nirradiance = \"bright\"\n", &["projector_lights[0].irradiance", "a colour >= 0"]);
    refused("[[projector_lights]]\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nup = [0, 0, 1]\nfov_x = 30\nirradiance = 1\nscale = -1\n", &["projector_lights[0].scale", ">= 0"]);
    let spot = "[[spot_lights]]\nposition = [0, 2, 0]\ndirection = [0, -1, 0]\nintensity = 1\n";
    refused(&format!("{spot}texture = {{ texture = \"checkerboard\" }}\n"), &["spot_lights[0].up", "needs `up`"]);
    refused(&format!("{spot}texture = 1\nup = [0, 0, 1]\n"), &["spot_lights[0].texture", "texture table"]);
    let s = parse(&format!("{spot}up = [0, 0, 1]\n")).unwrap();
    assert!(s.warnings.iter().any(|w| w.field == "spot_lights[0].up" && w.message.contains("no effect")), "{:?}", s.warnings);

    // Mitsuba XML: a projector's to_world must not shear or stretch.
    let xml = std::fs::read_to_string(fixture()).unwrap().replace("<scale value=\"2\"/>", "<scale x=\"2\"/>");
    let e = load_xml(&xml, "p.xml").unwrap_err().to_string();
    assert!(e.contains("p.xml:") && e.contains("the `to_world` of a projector must be a rotation with a uniform scale"), "{e}");
}
