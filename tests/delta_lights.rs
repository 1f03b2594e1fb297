//! Point, spot and directional lights (Mitsuba's `point`, `spot`, `directional`): delta lights
//! that only next event estimation finds. Against Mitsuba 3.9.1 rendering the same XML file
//! (per-pixel z-tests, `scripts/delta_lights_reference.sh`), against the exact radiance of a
//! diffuse plane under a directional light, and refused where a method cannot see them.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::{Scene, SceneError};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/delta_lights").join(name)
}

/// Mitsuba's image of the fixture (64 passes of 1024 spp) against pathlab's (4096 spp: the glossy
/// reflections of the point and spot light in the rough metal are heavy-tailed, and 1024 spp
/// underestimate their variance in a few pixels) with light
/// sampling alone, with MIS, and with one light per vertex drawn uniformly or by power (whose
/// weights are the delta lights' powers). Each z-test is Šidák-corrected (false-failure
/// probability 0.01 over the methods and the power check); a 5% bias must be caught.
#[test]
fn every_light_sampling_method_agrees_with_mitsuba_under_point_spot_and_directional_lights() {
    let reference = mitsuba_fixture("delta_lights");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture("delta_lights.xml"), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!((scene.point_lights.len(), scene.spot_lights.len(), scene.directional_lights.len()), (1, 1, 1));
    let methods: Vec<Method> = ["mis", "nee", "mis+uniform", "mis+power"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (4096, 2), 2100, Preset::Mis.method());
}

/// A diffuse plane of albedo rho under a directional light of irradiance E at angle theta:
/// every point reflects L = rho / pi * E cos(theta), and nothing else is in the scene, so every
/// pixel is exactly that, for every method that sees the light. Deterministic up to f32.
#[test]
fn a_plane_under_a_directional_light_has_the_exact_radiance() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("sun.toml");
    let (rho, e) = (0.7, [2.0, 1.5, 1.0]);
    let d = glam::DVec3::new(0.3, -1.0, 0.2).normalize();
    std::fs::write(
        &path,
        format!(
            "[camera]\nposition = [0, 3, 0.01]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nfov_x = 40\n\
             [render]\nwidth = 16\nheight = 12\nmax_depth = 4\n\
             [materials.floor]\ndiffuse = {rho}\n\
             [[planes]]\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"floor\"\n\
             [[directional_lights]]\ndirection = [{}, {}, {}]\nirradiance = [{}, {}, {}]\n",
            d.x, d.y, d.z, e[0], e[1], e[2]
        ),
    )
    .unwrap();
    let scene = Scene::load(&path).unwrap();
    let cos = -d.y;
    for name in ["nee", "mis", "mis+power"] {
        let film = render(&scene, Method::from_name(name).unwrap(), 4, 5);
        for px in &film.mean {
            for c in 0..3 {
                let exact = rho / std::f64::consts::PI * e[c] * cos;
                assert!((px[c] as f64 - exact).abs() <= 1e-5 * exact, "{name}: {px:?} against {exact} in channel {c}");
            }
        }
    }
}

fn pathlab() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pathlab"))
}

#[test]
fn methods_that_cannot_see_delta_lights_are_refused_by_render_and_left_out_by_study() {
    let scene = fixture("delta_lights.xml");
    // render: refused before any GPU work, naming the light.
    let r = pathlab().args(["render", scene.to_str().unwrap(), "--method", "plain", "--spp", "1", "-o"]).arg(std::env::temp_dir().join("never.exr")).output().unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("method plain cannot see point light 0") && stderr.contains("next event estimation"), "{stderr}");
    assert!(!stderr.contains("adapter:"), "refused after opening the GPU: {stderr}");
    // bench leaves it out, says so, and measures the others.
    let r = pathlab().args(["bench", scene.to_str().unwrap(), "--methods", "plain,nee", "--size", "8x8", "--seconds", "0.2"]).output().unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&r.stdout), String::from_utf8_lossy(&r.stderr));
    assert!(r.status.success(), "{stderr}");
    assert!(stderr.contains("plain is left out: it cannot see point light 0"), "{stderr}");
    assert!(stdout.lines().any(|l| l.starts_with("nee")) && !stdout.lines().any(|l| l.starts_with("plain")), "{stdout}");
    // The library refuses it too (Python and the viewer share it).
    let s = Scene::load(&scene).unwrap();
    let err = pathlab::render::RenderError::check_sees_lights(&s, &Preset::Plain.method()).unwrap_err();
    assert!(err.to_string().contains("point light 0"), "{err}");
    assert!(pathlab::render::RenderError::check_sees_lights(&s, &Preset::Nee.method()).is_ok());
    // study: the methods without light sampling are left out, each said.
    let options = pathlab::study::StudyOptions { methods: Some(vec!["plain".into(), "mis".into()]), quick: true, ..Default::default() };
    let study = options.study(s.clone(), scene.clone(), std::env::temp_dir().join("never"), String::new()).unwrap();
    assert_eq!(study.methods.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(), ["mis"]);
    assert!(study.left_out.len() == 1 && study.left_out[0].contains("plain is left out: it cannot see point light 0"), "{:?}", study.left_out);
    let only_blind = pathlab::study::StudyOptions { methods: Some(vec!["plain".into()]), quick: true, ..Default::default() };
    let err = only_blind.study(s, scene, std::env::temp_dir().join("never"), String::new()).unwrap_err();
    assert!(err.to_string().contains("no method left"), "{err}");
}

#[test]
fn delta_lights_are_read_from_toml_and_xml_and_bad_ones_refused() {
    let dir = tempfile::tempdir().unwrap();
    // The XML fixture through `pathlab convert`: the same scene (one content hash).
    let out = dir.path().join("converted.toml");
    let r = pathlab().arg("convert").arg(fixture("delta_lights.xml")).arg("-o").arg(&out).output().unwrap();
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(Scene::load(&out).unwrap().content_hash(), Scene::load(fixture("delta_lights.xml")).unwrap().content_hash());
    // Mitsuba's defaults: a spot's cutoff 20 degrees and beam width 3/4 of it; intensity 1.
    let xml = |body: &str| {
        format!(
            "<scene version=\"3.0.0\"><sensor type=\"perspective\"><float name=\"fov\" value=\"45\"/>\
             <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/></film></sensor>\
             <shape type=\"cube\"/>\n{body}\n</scene>"
        )
    };
    let path = dir.path().join("s.xml");
    let load = |body: &str| {
        std::fs::write(&path, xml(body)).unwrap();
        Scene::load(&path)
    };
    let s = load("<emitter type=\"spot\"><transform name=\"to_world\"><lookat origin=\"0, 4, 0\" target=\"0, 0, 0\" up=\"0, 0, 1\"/></transform></emitter>").unwrap();
    let spot = &s.spot_lights[0];
    assert_eq!((spot.cutoff_angle, spot.beam_width, spot.intensity.x), (20.0, 15.0, 1.0));
    assert!((spot.direction - glam::DVec3::NEG_Y).length() < 1e-12 && (spot.position.y - 4.0).abs() < 1e-12, "{spot:?}");
    let s = load("<emitter type=\"directional\"><transform name=\"to_world\"><rotate x=\"1\" angle=\"90\"/></transform></emitter>").unwrap();
    assert!((s.directional_lights[0].direction - glam::DVec3::NEG_Y).length() < 1e-12, "+z turned by 90 degrees about x: {:?}", s.directional_lights[0]);
    let s = load("<emitter type=\"point\"><transform name=\"to_world\"><translate x=\"1\" y=\"2\" z=\"3\"/></transform></emitter>").unwrap();
    assert_eq!(s.point_lights[0].position.to_array(), [1.0, 2.0, 3.0]);
    for (body, message) in [
        ("<emitter type=\"point\"><point name=\"position\" value=\"0, 1, 0\"/><transform name=\"to_world\"><translate x=\"1\"/></transform></emitter>", "either `position` or `to_world`"),
        ("<emitter type=\"directional\"><vector name=\"direction\" value=\"0, -1, 0\"/><transform name=\"to_world\"><rotate x=\"1\" angle=\"9\"/></transform></emitter>", "either `direction` or `to_world`"),
        ("<emitter type=\"spot\"><transform name=\"to_world\"><scale x=\"2\"/></transform></emitter>", "a rotation with a uniform scale"),
        ("<emitter type=\"spot\"><texture type=\"rawconstant\" name=\"texture\"><float name=\"value\" value=\"1\"/></texture></emitter>", "must vary over it"),
        ("<emitter type=\"spot\"><texture type=\"bitmap\" name=\"texture\"><string name=\"filename\" value=\"a.png\"/></texture></emitter>", "image file \"a.png\" not found"),
        ("<emitter type=\"spot\"><rgb name=\"texture\" value=\"1\"/></emitter>", "`texture` of <emitter type=\"spot\"> is not supported"),
        ("<emitter type=\"spot\"><float name=\"cutoff_angle\" value=\"10\"/><float name=\"beam_width\" value=\"20\"/></emitter>", "must not exceed `cutoff_angle`"),
        ("<emitter type=\"directional\"><vector name=\"direction\" value=\"0, 0, 0\"/></emitter>", "non-zero direction"),
        ("<emitter type=\"point\"><rgb name=\"intensity\" value=\"-1\"/></emitter>", ">= 0"),
        ("<emitter type=\"point\"><float name=\"radius\" value=\"1\"/></emitter>", "`radius` of <emitter type=\"point\"> is not supported (pathlab reads: position, to_world, intensity)"),
    ] {
        match load(body) {
            Err(SceneError::Invalid(d)) => assert!(d.iter().any(|d| d.message.contains(message) && d.line >= 1), "{body}: {d:?}"),
            other => panic!("{body}: accepted ({:?})", other.map(|s| s.num_delta_lights())),
        }
    }
}
