//! Normal maps: Mitsuba's `normalmap` around a material's BSDF (`Material::normal_map`,
//! `bsdfs::NormalMap`; `normal_mapped` in shaders/bsdfs/normal_map.wgsl, applied by bsdf.wgsl's
//! `eval_pdf_bsdf` and `sample_bsdf`). tests/fixtures/normal_map/normal_map.xml (a bumpy rough
//! plastic sphere, anisotropic rough gold under tiles of tilted normals, a bumpy two-sided
//! diffuse panel seen from behind, a masked bumpy plastic; the maps made by
//! scripts/normal_map_image.py) rendered by `mis`, `best` and `mis+ndf` is z-tested against
//! Mitsuba 3.9.1 rendering the same file (64x48, 65536 spp in 64 passes with the per-pixel
//! variance of its mean; scripts/xml_fixture_reference.sh tests/fixtures/normal_map/normal_map.xml),
//! on 2x2 blocks as tests/cornell_box.rs does (at least 99.75% of channels passing,
//! Šidák-corrected: fails falsely with probability below 0.01; `mis` scaled by 1.05 is
//! rejected). The same scene without its normal maps is rejected.

use crate::common;

use common::*;
use pathlab::method::{Method, Preset};
use pathlab::scene::Scene;

fn fixture() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/normal_map/normal_map.xml")
}

#[test]
fn normal_maps_agree_with_mitsuba() {
    let reference = mitsuba_fixture("normal_map");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let scene = Scene::load_with(fixture(), &defines).unwrap();
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let methods: Vec<Method> = ["mis", "best", "mis+ndf"].iter().map(|m| Method::from_name(m).unwrap()).collect();
    agrees_with_reference(&reference, &scene, &methods, |_| (2048, 2), 3300, Preset::Mis.method());

    // Without the normal maps: rejected.
    let mut flat = scene.clone();
    for m in &mut flat.materials {
        m.normal_map = None;
    }
    let film = render(&flat, Preset::Mis.method(), 2048, 3400);
    let z = pathlab::stats::z_test(&reference.downsample(2), &film.downsample(2), 0.01);
    println!("without the normal maps (2048 spp, 2x2 blocks): {:.4} of channels pass", z.pass_fraction);
    assert!(z.pass_fraction < 0.9975, "the scene without normal maps passes: {:.4} of channels", z.pass_fraction);
}

#[test]
fn normal_maps_are_read_and_refused_where_mitsuba_refuses_them() {
    let scene = Scene::load(fixture()).unwrap();
    assert_eq!(scene.materials.iter().filter(|m| m.normal_map.is_some()).count(), 4);
    let f = pathlab::gpu::SceneFeatures::of(&scene);
    assert!(f.has_normal_maps && f.has_uvs);
    assert!(!pathlab::gpu::SceneFeatures::of(&study_scene()).has_normal_maps);
    // `pathlab check` names them.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pathlab")).arg("check").arg(fixture()).output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success() && text.contains("normal maps: 4 material(s)") && text.contains("anisotropic roughness: 1 material(s)"), "{text}");

    // `convert` writes `normal_map`, and the TOML loads as the same scene.
    let dir = tempfile::tempdir().unwrap();
    let (toml, _) = pathlab::scene::mitsuba::to_toml(&fixture(), &[], dir.path()).unwrap();
    assert!(toml.contains("normal_map"), "{toml}");
    for png in ["bumps.png", "tiles.png"] {
        std::fs::copy(fixture().with_file_name(png), dir.path().join(png)).unwrap();
    }
    let path = dir.path().join("n.toml");
    std::fs::write(&path, &toml).unwrap();
    assert_eq!(Scene::load(&path).unwrap().content_hash(), scene.content_hash());

    // Mitsuba XML, at the line and column of the problem.
    let bumps = fixture().with_file_name("bumps.png");
    let map = format!("<texture name=\"normalmap\" type=\"bitmap\"><boolean name=\"raw\" value=\"true\"/><string name=\"filename\" value=\"{}\"/></texture>", bumps.display());
    let refused = |bsdf: String, wants: &[&str]| {
        let e = load_xml(&xml_with_bsdf(&bsdf, "b"), "n.xml").unwrap_err().to_string();
        assert!(e.contains("n.xml:3:") && wants.iter().all(|w| e.contains(w)), "{bsdf}: {e}");
    };
    let ok = load_xml(&xml_with_bsdf(&format!("<bsdf type=\"normalmap\" id=\"b\">{map}<bsdf type=\"diffuse\"/></bsdf>"), "b"), "n.xml").unwrap();
    assert!(ok.materials[0].normal_map.is_some());
    refused(format!("<bsdf type=\"normalmap\" id=\"b\">{map}<bsdf type=\"dielectric\"/></bsdf>"), &["transmits"]);
    refused(format!("<bsdf type=\"normalmap\" id=\"b\">{map}</bsdf>"), &["needs the <bsdf>"]);
    refused("<bsdf type=\"normalmap\" id=\"b\"><bsdf type=\"diffuse\"/></bsdf>".to_string(), &["normalmap", "<texture name=\"normalmap\">"]);
    refused(format!("<bsdf type=\"normalmap\" id=\"b\">{map}<bsdf type=\"diffuse\"/><bsdf type=\"diffuse\"/></bsdf>"), &["one nested <bsdf>"]);
    refused(format!("<bsdf type=\"normalmap\" id=\"b\">{map}<boolean name=\"flip_invalid_normals\" value=\"false\"/><bsdf type=\"diffuse\"/></bsdf>"), &["flip_invalid_normals", "not supported"]);
    refused(format!("<bsdf type=\"normalmap\" id=\"b\">{map}<bsdf type=\"mask\"><bsdf type=\"diffuse\"/></bsdf></bsdf>"), &["one plain BSDF"]);
    refused(
        "<bsdf type=\"normalmap\" id=\"b\"><texture name=\"normalmap\" type=\"checkerboard\"/><bsdf type=\"diffuse\"/></bsdf>".to_string(),
        &["must be a bitmap", "eval_3"],
    );
    refused(format!("<bsdf type=\"twosided\" id=\"b\"><bsdf type=\"normalmap\">{map}<bsdf type=\"diffuse\"/></bsdf><bsdf type=\"diffuse\"/></bsdf>"), &["normal map"]);

    // TOML: a bitmap table, around a BSDF that reflects.
    let toml_refused = |material: &str, wants: &[&str]| {
        let e = Scene::parse(&toml_with_material(material), "a.toml").unwrap_err().to_string();
        assert!(e.contains("materials.m.normal_map") && wants.iter().all(|w| e.contains(w)), "{material}: {e}");
    };
    toml_refused("normal_map = 0.5", &["texture table"]);
    toml_refused("normal_map = { texture = \"checkerboard\" }", &["must be a bitmap"]);
    toml_refused("bsdf = \"dielectric\"\nnormal_map = { texture = \"checkerboard\" }", &["transmits"]);
}

/// Mitsuba's `rawconstant` as a normal map (its test scene `test_normalmap_identity_*`): the
/// identity normal (0.5, 0.5, 1) leaves every frame as it was, so the anisotropic fixture with
/// one around each reflecting material (the frames that matter most: the lobes follow dp/du)
/// must still agree with Mitsuba's render of the fixture without them
/// (tests/fixtures/anisotropic/, `mis` at 2048 spp, 2x2 blocks, as tests/anisotropic.rs).
#[test]
fn an_identity_rawconstant_normal_map_changes_nothing() {
    use pathlab::scene::{NormalMap, Texture};
    let reference = mitsuba_fixture("anisotropic");
    let file = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/anisotropic/anisotropic.xml");
    let defines = [("resx".to_string(), reference.width.to_string()), ("resy".to_string(), reference.height.to_string())];
    let mut scene = Scene::load_with(&file, &defines).unwrap();
    let mut mapped = 0;
    for m in &mut scene.materials {
        if !m.bsdf.kind().transmits() && !m.is_emissive() {
            m.normal_map = Some(NormalMap { texture: Texture::RawConstant { value: glam::DVec3::new(0.5, 0.5, 1.0) } });
            mapped += 1;
        }
    }
    assert!(mapped >= 6, "{mapped}");
    assert!(pathlab::gpu::SceneFeatures::of(&scene).has_normal_maps);
    agrees_with_reference(&reference, &scene, &[Preset::Mis.method()], |_| (2048, 2), 3900, Preset::Mis.method());

    // Read from Mitsuba XML (a <vector> or a <float>) and TOML; bad values refused.
    let normal = |value: &str| format!("<bsdf type=\"normalmap\" id=\"b\"><texture name=\"normalmap\" type=\"rawconstant\">{value}</texture><bsdf type=\"diffuse\"/></bsdf>");
    let s = load_xml(&xml_with_bsdf(&normal("<vector name=\"value\" value=\"0.5, 0.5, 1\"/>"), "b"), "r.xml").unwrap();
    assert_eq!(s.materials[0].normal_map.as_ref().map(|n| n.texture.clone()), Some(Texture::RawConstant { value: glam::DVec3::new(0.5, 0.5, 1.0) }));
    let s = load_xml(&xml_with_bsdf(&normal("<float name=\"value\" value=\"0.5\"/>"), "b"), "r.xml").unwrap();
    assert_eq!(s.materials[0].normal_map.as_ref().map(|n| n.texture.clone()), Some(Texture::RawConstant { value: glam::DVec3::splat(0.5) }));
    for (value, wants) in [("", "needs its `value`"), ("<string name=\"value\" value=\"up\"/>", "a <float> or a <vector>"), ("<float name=\"value\" value=\"inf\"/>", "finite")] {
        let e = load_xml(&xml_with_bsdf(&normal(value), "b"), "r.xml").unwrap_err().to_string();
        assert!(e.contains("r.xml:3:") && e.contains(wants), "{value}: {e}");
    }
    let toml = Scene::parse(&toml_with_material("normal_map = { texture = \"rawconstant\", value = [0.5, 0.5, 1] }"), "r.toml").unwrap();
    assert!(toml.materials[0].normal_map.is_some());
    let e = Scene::parse(&toml_with_material("normal_map = { texture = \"rawconstant\", value = [0.5, 1] }"), "r.toml").unwrap_err().to_string();
    assert!(e.contains("materials.m.normal_map") && e.contains("one finite number or three"), "{e}");
}
