//! Bump maps: Mitsuba's `bumpmap` around a material's BSDF (`Material::bump_map`,
//! `bsdfs::BumpMap`; `bump_mapped` in shaders/bsdfs/bump_map.wgsl, the surfaces' partials
//! `surface_partials` in shaders/intersect.wgsl, the heights' gradient `texture_gradient` in
//! shaders/texture.wgsl, tested against Mitsuba's `eval_1_grad` in tests/textures.rs).
//! tests/fixtures/bump_map/bump_map.xml (one height map, made by scripts/bump_map_image.py, on a
//! sphere with `to_uv`, a rectangle mesh with uvs, a two-sided panel seen from behind, a disk, a
//! cylinder and an OBJ panel without uvs) rendered by `mis` and `best` is z-tested against
//! Mitsuba 3.9.1 rendering the same file (64x48, 65536 spp in 64 passes with the per-pixel
//! variance of its mean; WIDTH=64 scripts/xml_fixture_reference.sh
//! tests/fixtures/bump_map/bump_map.xml), on 2x2 blocks as tests/cornell_box.rs does (at least
//! 99.75% of channels passing, Šidák-corrected: fails falsely with probability below 0.01; `mis`
//! scaled by 1.05 is rejected). The same scene without its bump maps is rejected.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::Scene;

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/bump_map/bump_map.xml")
}

#[test]
fn bump_maps_agree_with_mitsuba() {
    let reference = mitsuba_fixture("bump_map");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "best"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 3500, Preset::Mis.method());

    // Without the bump maps: rejected.
    let mut flat = scene.clone();
    for m in &mut flat.materials {
        m.bump_map = None;
    }
    let film = render(&flat, Preset::Mis.method(), 2048, 3600);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    println!("without the bump maps (2048 spp, 2x2 blocks): {:.4} of channels pass", z.pass_fraction);
    assert!(z.pass_fraction < 0.9975, "the scene without bump maps passes: {:.4} of channels", z.pass_fraction);
}

#[test]
fn bump_maps_are_read_and_refused_where_mitsuba_refuses_them() {
    let scene = Scene::load(fixture()).unwrap();
    assert_eq!(scene.materials.iter().filter(|m| m.bump_map.is_some()).count(), 6);
    assert_eq!(scene.materials.iter().filter_map(|m| m.bump_map.as_ref()).map(|b| b.scale).fold(0.0, f64::max), 0.15);
    let f = pathlab::gpu::SceneFeatures::of(&scene);
    assert!(f.has_bump_maps && f.has_uvs && !f.has_normal_maps);
    assert!(!pathlab::gpu::SceneFeatures::of(&study_scene()).has_bump_maps);
    // `pathlab check` names them.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pathlab")).arg("check").arg(fixture()).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("bump maps: 6 material(s)") && text.contains("(scale 0.12)"), "{text}");

    // `convert` writes `bump_map` with its scale, and the TOML loads as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert!(toml.contains("bump_map") && toml.contains("scale = 0.12"), "{toml}");
    for file in ["heights.png", "panel.obj"] {
        std::fs::copy(fixture().with_file_name(file), dir.path().join(file)).unwrap();
    }
    let path = dir.path().join("b.toml");
    std::fs::write(&path, &toml).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), scene.content_hash());

    // Mitsuba XML, at the line and column of the problem.
    let heights = fixture().with_file_name("heights.png");
    let map = format!("<texture name=\"h\" type=\"bitmap\"><boolean name=\"raw\" value=\"true\"/><string name=\"filename\" value=\"{}\"/></texture>", heights.display());
    let refused = |bsdf: String, wants: &[&str]| {
        let e = load_xml(&xml_with_bsdf(&bsdf, "b"), "b.xml").unwrap_err().to_string();
        assert!(e.contains("b.xml:3:") && wants.iter().all(|w| e.contains(w)), "{bsdf}: {e}");
    };
    let ok = load_xml(&xml_with_bsdf(&format!("<bsdf type=\"bumpmap\" id=\"b\">{map}<float name=\"scale\" value=\"0.5\"/><bsdf type=\"diffuse\"/></bsdf>"), "b"), "b.xml").unwrap();
    assert_eq!(ok.materials[0].bump_map.as_ref().map(|b| b.scale), Some(0.5));
    let default_scale = load_xml(&xml_with_bsdf(&format!("<bsdf type=\"bumpmap\" id=\"b\">{map}<bsdf type=\"diffuse\"/></bsdf>"), "b"), "b.xml").unwrap();
    assert_eq!(default_scale.materials[0].bump_map.as_ref().map(|b| b.scale), Some(1.0));
    refused(format!("<bsdf type=\"bumpmap\" id=\"b\">{map}<bsdf type=\"dielectric\"/></bsdf>"), &["transmits"]);
    refused(format!("<bsdf type=\"bumpmap\" id=\"b\">{map}</bsdf>"), &["needs the <bsdf>"]);
    refused("<bsdf type=\"bumpmap\" id=\"b\"><bsdf type=\"diffuse\"/></bsdf>".to_string(), &["bumpmap", "one <texture>"]);
    refused(format!("<bsdf type=\"bumpmap\" id=\"b\">{map}{map}<bsdf type=\"diffuse\"/></bsdf>"), &["one <texture>", "Only a single Texture"]);
    refused(format!("<bsdf type=\"bumpmap\" id=\"b\">{map}<bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>"), &["one nested <bsdf>"]);
    refused(format!("<bsdf type=\"bumpmap\" id=\"b\">{map}<boolean name=\"use_shadowing_function\" value=\"false\"/><bsdf type=\"diffuse\"/></bsdf>"), &["use_shadowing_function", "not supported"]);
    refused(format!("<bsdf type=\"bumpmap\" id=\"b\">{map}<bsdf type=\"mask\"><bsdf type=\"diffuse\"/></bsdf></bsdf>"), &["one plain BSDF"]);
    refused("<bsdf type=\"bumpmap\" id=\"b\"><texture name=\"h\" type=\"checkerboard\"/><bsdf type=\"diffuse\"/></bsdf>".to_string(), &["must be a bitmap", "eval_1_grad"]);
    refused(format!("<bsdf type=\"twosided\" id=\"b\"><bsdf type=\"bumpmap\">{map}<bsdf type=\"diffuse\"/></bsdf><bsdf type=\"diffuse\"/></bsdf>"), &["bump map"]);
    let normal = format!("<texture name=\"normalmap\" type=\"bitmap\"><boolean name=\"raw\" value=\"true\"/><string name=\"filename\" value=\"{}\"/></texture>", heights.display());
    refused(format!("<bsdf type=\"bumpmap\" id=\"b\">{map}<bsdf type=\"normalmap\">{normal}<bsdf type=\"diffuse\"/></bsdf></bsdf>"), &["one plain BSDF"]);

    // TOML: a bitmap table with an optional scale, around a BSDF that reflects, without a
    // normal map.
    let toml_refused = |material: &str, wants: &[&str]| {
        let e = Scene::parse(&toml_with_material(material), "a.toml").unwrap_err().to_string();
        assert!(e.contains("materials.m.bump_map") && wants.iter().all(|w| e.contains(w)), "{material}: {e}");
    };
    toml_refused("bump_map = 0.5", &["texture table"]);
    toml_refused("bump_map = { texture = \"checkerboard\" }", &["must be a bitmap"]);
    toml_refused("bump_map = { scale = \"big\", texture = \"checkerboard\" }", &["`scale`", "finite number"]);
    toml_refused("bsdf = \"dielectric\"\nbump_map = { texture = \"checkerboard\" }", &["transmits"]);
    toml_refused("normal_map = { texture = \"checkerboard\" }\nbump_map = { texture = \"checkerboard\" }", &["not both"]);
}
