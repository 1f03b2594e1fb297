//! Mitsuba's `twosided` with two BSDFs (`Material::back`, `material_on_side` in
//! shaders/scene.wgsl): the first BSDF scatters on the surface's front, the second on its back,
//! in the frame turned to that side. tests/fixtures/twosided/twosided.xml (an orange diffuse /
//! blue plastic material on two panels, one showing its front and one its back; a masked rough
//! aluminium / green diffuse panel showing its back) rendered by `mis` and `best` is z-tested
//! against Mitsuba 3.9.1 rendering the same file (48x48, 65536 spp in 64 passes with the
//! per-pixel variance of its mean; scripts/xml_fixture_reference.sh
//! tests/fixtures/twosided/twosided.xml), on 2x2 blocks as tests/cornell_box.rs does (at least
//! 99.75% of channels passing, Šidák-corrected: fails falsely with probability below 0.01;
//! `mis` scaled by 1.05 is rejected).

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::Scene;

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/twosided/twosided.xml")
}

#[test]
fn two_bsdfs_agree_with_mitsuba() {
    let reference = mitsuba_fixture("twosided");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.materials.iter().filter(|m| m.back.is_some()).count(), 2, "two materials with a back");
    let methods: Vec<Method> = ["mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (1024, 2), 2400, Preset::Mis.method());

    // Without the backs (the fronts' BSDFs on both sides) the image is rejected.
    let mut fronts = scene.clone();
    fronts.materials.iter_mut().for_each(|m| m.back = None);
    let film = render(&fronts, Preset::Mis.method(), 1024, 2500);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    assert!(z.pass_fraction < 0.9975, "the fronts alone pass: {:.4} of channels", z.pass_fraction);
}

#[test]
fn a_back_with_the_fronts_bsdf_renders_the_one_bsdf_image_bit_for_bit() {
    // The back material's BSDF equal to the front's: another kernel path (HAS_BACK_BSDFS), the
    // same numbers.
    let scene = Scene::load(fixture()).unwrap();
    let mut same = scene.clone();
    let mut one = scene.clone();
    for i in 0..scene.materials.len() {
        if let Some(b) = scene.materials[i].back {
            same.materials[b].bsdf = scene.materials[i].bsdf.clone();
            one.materials[i].back = None;
        }
    }
    for method in [Preset::Mis.method(), Preset::Best.method()] {
        let a = render(&same, method, 8, 11);
        let b = render(&one, method, 8, 11);
        assert_eq!(a.mean, b.mean, "{}", method.name());
    }
}

#[test]
fn toml_backs_convert_and_refusals() {
    // convert writes the back as a material of its own, named by `back`: the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert!(toml.contains("back = \"paper-back\""), "{toml}");
    let path = dir.path().join("t.toml");
    std::fs::write(&path, &toml).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), Scene::load(fixture()).unwrap().content_hash());

    let with = |front: &str, extra: &str| {
        Scene::parse(&toml_with_material(&format!("{front}\n[materials.b]\n{extra}")), "test.toml")
    };
    assert!(with("diffuse = 0.5\nback = \"b\"", "diffuse = 0.2").is_ok());
    let refused = |front: &str, extra: &str, says: &str| {
        let e = with(front, extra).expect_err("accepted").to_string();
        assert!(e.contains("materials.m.back") && e.contains(says), "{e}");
    };
    refused("diffuse = 0.5\nback = \"nowhere\"", "diffuse = 0.2", "no material \"nowhere\"");
    refused("diffuse = 0.5\nback = \"m\"", "diffuse = 0.2", "its own back");
    refused("diffuse = 0.5\nback = \"b\"", "bsdf = \"dielectric\"", "transmits");
    refused("diffuse = 0.5\nback = \"b\"", "diffuse = 0.2\nemission = 1", "plain material");
    refused("diffuse = 0.5\nback = \"b\"", "diffuse = 0.2\nopacity = 0.5", "plain material");
    refused("diffuse = 0.5\ntwo_sided = false\nback = \"b\"", "diffuse = 0.2", "two-sided");
    refused("bsdf = \"roughdielectric\"\nback = \"b\"", "diffuse = 0.2", "transmits");

    // XML: at most two nested BSDFs, none that transmits (as Mitsuba refuses them).
    let xml = |inner: &str| xml_with_bsdf(&format!("<bsdf type=\"twosided\" id=\"t\">{inner}</bsdf>"), "t");
    let e = load_xml(&xml("<bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/>"), "t.xml").unwrap_err().to_string();
    assert!(e.contains("t.xml:3:") && e.contains("at most two"), "{e}");
    let e = load_xml(&xml("<bsdf type=\"diffuse\"/><bsdf type=\"dielectric\"/>"), "t.xml").unwrap_err().to_string();
    assert!(e.contains("t.xml:3:") && e.contains("transmits"), "{e}");
    let s = load_xml(&xml("<bsdf type=\"diffuse\"/><bsdf type=\"plastic\"/>"), "t.xml").unwrap();
    assert_eq!(s.materials.iter().filter(|m| m.back.is_some()).count(), 1);
}

#[test]
fn check_lists_the_masks_and_the_backs() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pathlab")).arg("check").arg(fixture()).output().unwrap();
    assert!(out.status.success());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("two BSDFs: 2 material(s)") && stdout.contains("paper (back: paper-back)"), "{stdout}");
    assert!(stdout.contains("masks: 1 material(s)") && stdout.contains("(opacity 0.5)"), "{stdout}");
}
